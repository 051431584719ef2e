# `cmake --install build --prefix DIR`: the executables (bin/), the libraries (lib/) with their headers
# (include/viewsynthesis/<Area>/*.h, and ViewSynthesis/Embed.h, the embeddable API) and a CMake package
# (lib/cmake/ViewSynthesis): another project does find_package(ViewSynthesis) and links
# ViewSynthesis::Synth (or ::Common, ::Plan, ::Pipeline, ::Scene, ::Mesh). The manual and the licence go
# to share/doc/viewsynthesis, the key templates and ready configs to share/viewsynthesis/cfg.
# `cpack -G DEB` (in the build folder) packs the same tree as a Debian package.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(vs_apps ViewSyn MeshRender SceneGen YuvPsnr CameraConvert SynthBench)
foreach(app ${vs_apps})
  if(TARGET ${app})
    install(TARGETS ${app} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endforeach()

set(vs_export_libs)
foreach(area Common Plan Pipeline Synth Scene Mesh)
  string(TOLOWER ${area} lower)
  if(TARGET vs${lower})
    set_target_properties(vs${lower} PROPERTIES EXPORT_NAME ${area} OUTPUT_NAME viewsynthesis-${lower})
    list(APPEND vs_export_libs vs${lower})
  endif()
endforeach()
install(TARGETS ${vs_export_libs} EXPORT ViewSynthesisTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/viewsynthesis)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/Source/Lib/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/viewsynthesis
        FILES_MATCHING PATTERN "*.h")
set(vs_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/ViewSynthesis)
install(EXPORT ViewSynthesisTargets NAMESPACE ViewSynthesis:: DESTINATION ${vs_cmake_dir})
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/ViewSynthesisConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/ViewSynthesisConfig.cmake INSTALL_DESTINATION ${vs_cmake_dir})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/ViewSynthesisConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/ViewSynthesisConfig.cmake ${CMAKE_BINARY_DIR}/ViewSynthesisConfigVersion.cmake
        DESTINATION ${vs_cmake_dir})

set(vs_doc_dir ${CMAKE_INSTALL_DATADIR}/doc/viewsynthesis)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/doc/ DESTINATION ${vs_doc_dir})
install(FILES ${CMAKE_SOURCE_DIR}/README.md ${CMAKE_SOURCE_DIR}/LICENSE ${CMAKE_SOURCE_DIR}/CITATION.cff
        DESTINATION ${vs_doc_dir})
install(DIRECTORY ${CMAKE_SOURCE_DIR}/cfg/ DESTINATION ${CMAKE_INSTALL_DATADIR}/viewsynthesis/cfg)

# The Debian package: the executables need EGL's shared libraries at run time (found by
# dpkg-shlibdeps; no OpenCV since 2026-11-25: only the tests use it); the -dev package is only for
# projects that link the static libraries.
set(CPACK_PACKAGE_NAME viewsynthesis)
set(CPACK_PACKAGE_VENDOR "the ViewSynthesis authors")
set(CPACK_PACKAGE_CONTACT "the ViewSynthesis authors")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "View synthesis from multi-view video plus depth (successor to MPEG VSRS)")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_RESOURCE_FILE_LICENSE ${CMAKE_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# MeshRender opens EGL through libglvnd's libegl1 (found by dpkg-shlibdeps), which needs a vendor library
# at run time that no link line shows: Mesa's (with its software rasteriser, for machines without a GPU)
# is recommended, so apt installs it by default; an NVIDIA machine may use its driver's instead.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libegl-mesa0, libgl1-mesa-dri")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libegl-dev")
include(CPack)
