# vkr_add_header_check(TARGET LINK_LIBS...): an object library with one translation unit per
# header of the project, each including its header alone (twice, so a missing include guard
# shows too). A header that uses what it does not include fails to compile here; unity builds
# hide exactly that, since a batch's earlier files may have included it already.
function(vkr_add_header_check target)
  file(GLOB_RECURSE headers RELATIVE ${PROJECT_SOURCE_DIR} CONFIGURE_DEPENDS
       ${PROJECT_SOURCE_DIR}/engine/*.h ${PROJECT_SOURCE_DIR}/pipelines/*.h
       ${PROJECT_SOURCE_DIR}/optimiser/*.h ${PROJECT_SOURCE_DIR}/report/*.h
       ${PROJECT_SOURCE_DIR}/recon/*.h ${PROJECT_SOURCE_DIR}/apps/*.h
       ${PROJECT_SOURCE_DIR}/bench/harness/*.h ${PROJECT_SOURCE_DIR}/bench/peers/*.h ${PROJECT_SOURCE_DIR}/tests/*.h)
  set(sources)
  foreach(header ${headers})
    string(MAKE_C_IDENTIFIER ${header} id)
    set(source ${CMAKE_CURRENT_BINARY_DIR}/header_check/${id}.cpp)
    file(CONFIGURE OUTPUT ${source} CONTENT "#include \"${header}\"\n#include \"${header}\"\n" @ONLY)
    list(APPEND sources ${source})
  endforeach()
  add_library(${target} OBJECT ${sources})
  target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR})
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-missing-field-initializers)
  target_link_libraries(${target} PRIVATE ${ARGN})
endfunction()
