# The rooms of the source include one way (docs/internals/OVERVIEW.md): every folder below may
# include only itself and the folders listed for it. Run as a test (`layout/IncludesPointOneWay`),
# so the map in the docs is a fact the build keeps, not a hope. Usage: cmake -DROOT=… -P this.
set(engine engine/common engine/image engine/scene engine/geometry engine/vk)
set(allowed_engine/common "")
set(allowed_engine/image engine/common)
set(allowed_engine/scene engine/common engine/image)
set(allowed_engine/geometry engine/common engine/image engine/scene)
set(allowed_engine/vk engine/common)
set(allowed_optimiser engine/common)
set(allowed_pipelines/model ${engine})
set(allowed_pipelines/passes ${engine} pipelines/model)
set(allowed_pipelines/rendering ${engine} pipelines/model pipelines/passes)
set(allowed_pipelines/likelihood ${engine} pipelines/model pipelines/passes pipelines/rendering)
set(allowed_bench/harness ${engine} pipelines/model pipelines/passes pipelines/rendering pipelines/likelihood)
# The report reads a run's files: it needs the overlays' rendering, never the run itself.
set(allowed_report ${engine} pipelines/model pipelines/passes pipelines/rendering)
# The reconstruction: the one room that sees both the sampler and the GPU; it writes the report.
set(allowed_recon ${engine} optimiser pipelines/model pipelines/passes pipelines/rendering
    pipelines/likelihood report)
set(allowed_bench/peers ${engine} optimiser pipelines/model pipelines/passes pipelines/rendering
    pipelines/likelihood report recon)
# The Python module (python/): a front door beside the command line, over the same rooms.
set(allowed_python ${engine} optimiser pipelines/model pipelines/passes pipelines/rendering
    pipelines/likelihood report recon)
set(rooms engine/common engine/image engine/scene engine/geometry engine/vk optimiser
    pipelines/model pipelines/passes pipelines/rendering pipelines/likelihood bench/harness
    report recon bench/peers python apps)
# The command line parses options and calls any room; none includes it.
set(allowed_apps ${rooms})

set(violations "")
foreach(room ${rooms})
  file(GLOB files ${ROOT}/${room}/*.h ${ROOT}/${room}/*.cpp)
  if(NOT files)
    message(FATAL_ERROR "layout: ${room} holds no source (moved? update tests/LayoutCheck.cmake and docs/internals/OVERVIEW.md)")
  endif()
  foreach(file ${files})
    file(STRINGS ${file} includes REGEX "^#include \"")
    foreach(line ${includes})
      string(REGEX REPLACE "^#include \"([^\"]*)\".*" "\\1" header "${line}")
      get_filename_component(folder ${header} DIRECTORY)
      # shaders/ and embedded/: headers the build generates into a room (cmake/Shaders.cmake,
      # cmake/EmbedText.cmake).
      if(folder STREQUAL "" OR folder STREQUAL room OR folder STREQUAL "shaders" OR folder STREQUAL "embedded")
        continue()
      endif()
      list(FIND allowed_${room} ${folder} found)
      if(found EQUAL -1)
        file(RELATIVE_PATH shown ${ROOT} ${file})
        string(APPEND violations "\n  ${shown} includes ${header}: ${room} may include only ${allowed_${room}}")
      endif()
    endforeach()
  endforeach()
endforeach()
if(violations)
  message(FATAL_ERROR "layout: includes against the rooms' direction:${violations}")
endif()
