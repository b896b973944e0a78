# `cmake --install`: headers, static libraries, the shared C library, the dermis tool, a CMake
# package with components and a pkg-config file per runtime flavour:
#   find_package(dermis CONFIG [COMPONENTS runtime offline plugins gpu])
#     runtime  dermis::core, ::deform, ::asset, ::runtime (static) and ::runtime_shared
#              (libdermis_runtime.so, the C API): GLM only
#     offline  dermis::offline and its stages ::offline_geometry, _io, _build, _fit, _character
#              (Eigen, meshoptimizer)
#     plugins  dermis::gltf, ::assimp, ::plugins (tinygltf, Assimp)
#     gpu      dermis::gpu (the Vulkan loader)
#   Without COMPONENTS, every component the package has is loaded (and its dependencies
#   searched); a runtime-only user asks for `runtime` alone and needs nothing but GLM.
#   pkg-config: dermis-runtime (the static libraries) and dermis-runtime-shared (the .so).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(dermis_runtime_targets dermis_core dermis_runtime dermis_deform dermis_asset)
if(TARGET dermis_runtime_shared)
  list(APPEND dermis_runtime_targets dermis_runtime_shared)
endif()
set(dermis_offline_targets dermis_offline dermis_offline_geometry dermis_offline_io
                           dermis_offline_build dermis_offline_fit dermis_offline_character)
set(dermis_plugins_targets dermis_gltf dermis_assimp dermis_plugins)
set(dermis_gpu_targets dermis_gpu)
if(TARGET dermis_gpu)
  # The shader as GLSL source and SPIR-V (docs/gpu.md).
  install(FILES ${PROJECT_SOURCE_DIR}/sdk/src/gpu/shaders/evaluate_plan.comp
                ${PROJECT_BINARY_DIR}/sdk/shaders/evaluate_plan.spv
          DESTINATION ${CMAKE_INSTALL_DATADIR}/dermis/shaders)
endif()

set(dermis_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/dermis)
set(DERMIS_PACKAGE_COMPONENTS "")
foreach(component runtime offline plugins gpu)
  set(targets "")
  foreach(t ${dermis_${component}_targets})
    if(TARGET ${t})
      list(APPEND targets ${t})
      string(REPLACE "dermis_" "" short ${t})
      set_target_properties(${t} PROPERTIES EXPORT_NAME ${short})
    endif()
  endforeach()
  if(NOT targets)
    continue()
  endif()
  list(APPEND DERMIS_PACKAGE_COMPONENTS ${component})
  install(TARGETS ${targets}
          EXPORT dermis_${component}_targets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
          INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(EXPORT dermis_${component}_targets NAMESPACE dermis::
          FILE dermis_${component}_targets.cmake DESTINATION ${dermis_cmake_dir})
endforeach()

install(DIRECTORY ${PROJECT_SOURCE_DIR}/sdk/include/dermis DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
if(DERMIS_BUILD_PLUGINS)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/plugins/include/dermis
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()
if(TARGET dermis)
  install(TARGETS dermis RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/dermisConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/dermisConfig.cmake
                              INSTALL_DESTINATION ${dermis_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/dermisConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/dermisConfig.cmake ${PROJECT_BINARY_DIR}/dermisConfigVersion.cmake
        DESTINATION ${dermis_cmake_dir})

# Relocatable: the prefix is found from the .pc file's own folder. The static flavour names
# the archives (-l:libX.a), as the shared library has the same base name.
file(RELATIVE_PATH DERMIS_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
configure_file(${PROJECT_SOURCE_DIR}/cmake/dermis-runtime.pc.in
               ${PROJECT_BINARY_DIR}/dermis-runtime.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/dermis-runtime.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
if(TARGET dermis_runtime_shared)
  configure_file(${PROJECT_SOURCE_DIR}/cmake/dermis-runtime-shared.pc.in
                 ${PROJECT_BINARY_DIR}/dermis-runtime-shared.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/dermis-runtime-shared.pc
          DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endif()
