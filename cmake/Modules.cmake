# vkr_add_module(NAME DIR [DEPS ...]): a static library from every .cpp in DIR.
# Each folder of the layout is one such library, so a module's dependencies are explicit
# and a half-finished file elsewhere never breaks it.
include(GNUInstallDirs)
function(vkr_add_module name dir)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  get_filename_component(dir ${dir} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
  file(GLOB sources CONFIGURE_DEPENDS ${dir}/*.cpp)
  if(NOT sources)
    return()  # a module nobody has written yet
  endif()
  add_library(${name} STATIC ${sources})
  # Headers by their path in the tree ("engine/scene/Scene.h"), here and once installed.
  target_include_directories(${name} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
                                            $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/vkrecon>)
  set_property(GLOBAL APPEND PROPERTY VKR_MODULES ${name})  # what cmake/Install.cmake installs
  target_compile_options(${name} PRIVATE -Wall -Wextra -Wno-missing-field-initializers)
  target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  # Position-independent, so the Python module (python/) can link the same libraries.
  set_target_properties(${name} PROPERTIES UNITY_BUILD ${VKRECON_UNITY} UNITY_BUILD_BATCH_SIZE 16
                                           POSITION_INDEPENDENT_CODE ON)
endfunction()
