# Installation and the exported CMake package: after `cmake --install build --prefix P`, a project
# with CMAKE_PREFIX_PATH=P says find_package(pcrt) and links pcrt::methods (or any other layer,
# each bringing those below it), or pcrt::pcrt for all of them and the command line. Tested by
# tests/consumer.sh.
include(CMakePackageConfigHelpers)
set(PCRT_LAYERS pcrt_core pcrt_structures pcrt_methods pcrt_render pcrt_reconstruction pcrt_harness
                pcrt_cli pcrt_umbrella)
install(TARGETS ${PCRT_LAYERS} EXPORT pcrtTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/pcrt)
install(TARGETS pcrt RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${CMAKE_SOURCE_DIR}/scripts/report.py DESTINATION ${CMAKE_INSTALL_DATADIR}/pcrt)
foreach(layer core structures preprocess methods render reconstruction harness)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/${layer} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/pcrt
          FILES_MATCHING PATTERN "*.hpp")
endforeach()
set(PCRT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/pcrt)
install(EXPORT pcrtTargets NAMESPACE pcrt:: DESTINATION ${PCRT_CMAKE_DIR})
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/pcrtConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/pcrtConfig.cmake INSTALL_DESTINATION ${PCRT_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/pcrtConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/pcrtConfig.cmake ${CMAKE_BINARY_DIR}/pcrtConfigVersion.cmake
        DESTINATION ${PCRT_CMAKE_DIR})
