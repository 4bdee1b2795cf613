# vkr_embed_shaders(TARGET SOURCES...): compiles each GLSL file to SPIR-V with
# glslangValidator at build time and emits a header `shaders/<name>_<stage>.h` holding
# `const uint32_t k<Name><Stage>[]`. A shader error is a build error; #includes are
# tracked through the depfile glslang writes.
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)

function(vkr_embed_shaders target)
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/generated/shaders)
  file(MAKE_DIRECTORY ${out_dir})
  set(headers)
  foreach(src ${ARGN})
    get_filename_component(abs ${src} ABSOLUTE)
    get_filename_component(stem ${src} NAME_WE)
    get_filename_component(ext ${src} EXT)
    string(SUBSTRING ${ext} 1 -1 stage)
    # snake_case file name → CamelCase symbol: scene_render.vert → kSceneRenderVert
    string(REPLACE "_" ";" words "${stem}_${stage}")
    set(symbol "k")
    foreach(w ${words})
      string(SUBSTRING ${w} 0 1 first)
      string(TOUPPER ${first} first)
      string(SUBSTRING ${w} 1 -1 rest)
      string(APPEND symbol "${first}${rest}")
    endforeach()
    set(header ${out_dir}/${stem}_${stage}.h)
    add_custom_command(
      OUTPUT ${header}
      COMMAND ${GLSLANG_VALIDATOR} --target-env vulkan1.3 --quiet
              --vn ${symbol} --depfile ${header}.d -o ${header} ${abs}
      DEPENDS ${abs}
      DEPFILE ${header}.d
      COMMENT "glslang ${stem}.${stage}"
      VERBATIM)
    list(APPEND headers ${header})
  endforeach()
  add_custom_target(${target}_shaders DEPENDS ${headers})
  add_dependencies(${target} ${target}_shaders)
  target_include_directories(${target} PRIVATE ${CMAKE_CURRENT_BINARY_DIR}/generated)
endfunction()
