# `cmake --install`: the libraries (probefilter::core, probefilter::runtime, and the component
# probefilter::tools), their public headers, the command-line tools, and for engines the drop-in
# shaders and the generated tables, with a CMake package so that an engine writes
# find_package(probefilter) and links probefilter::runtime, which needs no OpenEXR and no OpenMP.
#   <prefix>/include/probe/                      public headers
#   <prefix>/share/probefilter/shaders/          engine/probe_table_filter.glsl, engine/probe_pyramid.glsl and
#                                                what they include
#   <prefix>/share/probefilter/tables/           every committed table (.json, .h, .glsl)
#   <prefix>/lib/cmake/probefilter/              probefilterConfig.cmake
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(PROBE_PACKAGE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/probefilter)

install(TARGETS probecore proberuntime probe_shader_spirv EXPORT probefilterTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS probetools EXPORT probefilterToolsTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS probefilter probebench probefit RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY core/include/probe runtime/include/probe DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES shaders/engine/probe_table_filter.glsl shaders/engine/probe_pyramid.glsl
        DESTINATION ${CMAKE_INSTALL_DATADIR}/probefilter/shaders/engine)
install(FILES shaders/table_taps.glsl shaders/frame.glsl shaders/tap_sum.glsl shaders/cube.glsl shaders/pyramid_bspline.glsl
        DESTINATION ${CMAKE_INSTALL_DATADIR}/probefilter/shaders)
install(FILES core/include/probe/shared_constants.h DESTINATION ${CMAKE_INSTALL_DATADIR}/probefilter/shaders/probe)
install(DIRECTORY tables/ DESTINATION ${CMAKE_INSTALL_DATADIR}/probefilter/tables FILES_MATCHING PATTERN "*.json" PATTERN "*.h"
        PATTERN "*.glsl" PATTERN "fits" EXCLUDE)

install(EXPORT probefilterTargets NAMESPACE probefilter:: DESTINATION ${PROBE_PACKAGE_DIR})
install(EXPORT probefilterToolsTargets NAMESPACE probefilter:: DESTINATION ${PROBE_PACKAGE_DIR})
configure_package_config_file(cmake/probefilterConfig.cmake.in ${CMAKE_CURRENT_BINARY_DIR}/probefilterConfig.cmake
                              INSTALL_DESTINATION ${PROBE_PACKAGE_DIR} PATH_VARS CMAKE_INSTALL_DATADIR)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/probefilterConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/probefilterConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/probefilterConfigVersion.cmake
        DESTINATION ${PROBE_PACKAGE_DIR})
