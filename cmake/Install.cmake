# `cmake --install BUILD [--prefix DIR]`: every library module with its headers under
# include/vkrecon/ (by their path in the tree, so "engine/scene/Scene.h" includes as it does
# here), the vkrecon binary, the bundled assets and a vkreconConfig.cmake, so that another
# CMake project can `find_package(vkrecon)` and link `vkrecon::vkrecon`
# (docs/reference/LIBRARY.md). `cpack -G DEB` in the build folder packs the same tree.
include(CMakePackageConfigHelpers)

get_property(vkr_modules GLOBAL PROPERTY VKR_MODULES)
# The one target a consumer links: every module, each bringing its own dependencies.
add_library(vkr_all INTERFACE)
target_link_libraries(vkr_all INTERFACE ${vkr_modules})
set_target_properties(vkr_all PROPERTIES EXPORT_NAME vkrecon)

set(VKRECON_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/vkrecon)
install(TARGETS ${vkr_modules} vkr_all EXPORT vkreconTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}/vkrecon COMPONENT dev)
install(TARGETS vkrecon RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT bin)
foreach(room engine pipelines optimiser recon report bench/harness bench/peers)
  if(IS_DIRECTORY ${PROJECT_SOURCE_DIR}/${room})
    install(DIRECTORY ${room}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/vkrecon/${room} COMPONENT dev
            FILES_MATCHING PATTERN "*.h")
  endif()
endforeach()
# The assets without their generated photographs: `vkrecon synth` makes those.
install(DIRECTORY assets/ DESTINATION ${CMAKE_INSTALL_DATADIR}/vkrecon/assets COMPONENT bin
        PATTERN "images" EXCLUDE PATTERN "*.py" EXCLUDE)
install(FILES LICENSE README.md DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT bin)

install(EXPORT vkreconTargets NAMESPACE vkrecon:: DESTINATION ${VKRECON_CMAKE_DIR} COMPONENT dev)
configure_package_config_file(cmake/vkreconConfig.cmake.in ${CMAKE_CURRENT_BINARY_DIR}/vkreconConfig.cmake
                              INSTALL_DESTINATION ${VKRECON_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/vkreconConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/vkreconConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/vkreconConfigVersion.cmake
        DESTINATION ${VKRECON_CMAKE_DIR} COMPONENT dev)

# A .deb of the whole tree: `cpack -G DEB` in the build folder (docs/reference/LIBRARY.md).
# dpkg-shlibdeps names the shared libraries' packages; the Vulkan driver and the report's
# JavaScript are what the binary loads at run time without linking.
set(CPACK_PACKAGE_NAME vkrecon)
set(CPACK_PACKAGE_VENDOR "vkrecon")
set(CPACK_PACKAGE_CONTACT "vkrecon developers")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "3D geometry from calibrated photographs by inverse rendering (Vulkan)")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "mesa-vulkan-drivers | vulkan-icd")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libjs-chart.js, libjs-three")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_STRIP_FILES ON)
include(CPack)
