# vkr_embed_shaders(TARGET SOURCES...): compiles each GLSL file to SPIR-V with
# glslangValidator at build time and emits a header `shaders/<name>_<stage>.h` holding
# `const uint32_t k<Name><Stage>[]`. A shader error is a build error; #includes are
# tracked through the depfile glslang writes.
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)

# vkr_embedded_name(FILE NAME_VAR SYMBOL_VAR): what an embedded file is called in the build,
# its name with the dot as an underscore (scene_render.vert → scene_render_vert, the generated
# header's), and in C++, that in CamelCase (kSceneRenderVert). cmake/EmbedText.cmake too.
function(vkr_embedded_name file name_var symbol_var)
  get_filename_component(file ${file} NAME)
  string(REPLACE "." "_" name "${file}")
  string(REPLACE "_" ";" words "${name}")
  set(symbol "k")
  foreach(w ${words})
    string(SUBSTRING ${w} 0 1 first)
    string(TOUPPER ${first} first)
    string(SUBSTRING ${w} 1 -1 rest)
    string(APPEND symbol "${first}${rest}")
  endforeach()
  set(${name_var} ${name} PARENT_SCOPE)
  set(${symbol_var} ${symbol} PARENT_SCOPE)
endfunction()

function(vkr_embed_shaders target)
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/generated/shaders)
  file(MAKE_DIRECTORY ${out_dir})
  set(headers)
  foreach(src ${ARGN})
    get_filename_component(abs ${src} ABSOLUTE)
    get_filename_component(file ${src} NAME)
    vkr_embedded_name(${src} name symbol)
    set(header ${out_dir}/${name}.h)
    add_custom_command(
      OUTPUT ${header}
      COMMAND ${GLSLANG_VALIDATOR} --target-env vulkan1.3 --quiet
              --vn ${symbol} --depfile ${header}.d -o ${header} ${abs}
      DEPENDS ${abs}
      DEPFILE ${header}.d
      COMMENT "glslang ${file}"
      VERBATIM)
    list(APPEND headers ${header})
  endforeach()
  add_custom_target(${target}_shaders DEPENDS ${headers})
  add_dependencies(${target} ${target}_shaders)
  target_include_directories(${target} PRIVATE ${CMAKE_CURRENT_BINARY_DIR}/generated)
endfunction()
