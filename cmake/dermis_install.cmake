# `cmake --install`: headers, static libraries, the dermis tool, a CMake package
# (find_package(dermis CONFIG) with dermis::core, dermis::runtime, dermis::deform, dermis::asset,
# dermis::offline (its stages dermis::offline_geometry, _io, _build, _fit, _character),
# dermis::gltf, dermis::assimp, dermis::plugins, and dermis::gpu when built), its version file,
# and a pkg-config file for the runtime (dermis-runtime.pc: core + runtime + deform, GLM only).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(dermis_install_targets dermis_core dermis_runtime dermis_deform dermis_asset dermis_offline
                           dermis_offline_geometry dermis_offline_io dermis_offline_build
                           dermis_offline_fit dermis_offline_character dermis_gltf
                           dermis_assimp dermis_plugins)
if(TARGET dermis_gpu)
  # The GPU evaluation: its library, and the shader as GLSL source and SPIR-V (docs/gpu.md).
  list(APPEND dermis_install_targets dermis_gpu)
  install(FILES ${PROJECT_SOURCE_DIR}/sdk/src/gpu/shaders/evaluate_plan.comp
                ${PROJECT_BINARY_DIR}/sdk/shaders/evaluate_plan.spv
          DESTINATION ${CMAKE_INSTALL_DATADIR}/dermis/shaders)
endif()
foreach(t ${dermis_install_targets})
  string(REPLACE "dermis_" "" short ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${short})
endforeach()

install(TARGETS ${dermis_install_targets}
        EXPORT dermisTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/sdk/include/dermis ${PROJECT_SOURCE_DIR}/plugins/include/dermis
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
if(TARGET dermis)
  install(TARGETS dermis RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

set(dermis_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/dermis)
install(EXPORT dermisTargets NAMESPACE dermis:: DESTINATION ${dermis_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/dermisConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/dermisConfig.cmake
                              INSTALL_DESTINATION ${dermis_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/dermisConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/dermisConfig.cmake ${PROJECT_BINARY_DIR}/dermisConfigVersion.cmake
        DESTINATION ${dermis_cmake_dir})

# Relocatable: the prefix is found from the .pc file's own folder.
file(RELATIVE_PATH DERMIS_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
configure_file(${PROJECT_SOURCE_DIR}/cmake/dermis-runtime.pc.in
               ${PROJECT_BINARY_DIR}/dermis-runtime.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/dermis-runtime.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
