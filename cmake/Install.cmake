# `cmake --install`: public headers, static libraries, shaders, the CMake package `cubeao` and the
# pkg-config file cubeao-runtime.pc (issue 17; docs/INTEGRATION.md says how an engine uses them).
#
# Two export sets, so that an engine that links only the run-time never needs the offline libraries'
# dependencies (Embree, TBB, OpenImageIO, assimp, OpenMesh) installed:
#   cubeao::runtime  cubeao_runtime and what it links: core, gl, cache, kernels (shaders/common/*.h)
#   cubeao::offline  an umbrella: cubeao_offline (the bake, cubeao::bake) with scene, reference, metrics, and
#                    the procedural builtin: scenes (cubeao_scenes); cubeao::placement on its own
# Not installed: cubeao_ssao (the screen-space baselines), cubeao_window and the viewer, the tools.
#
# Layout under the prefix:
#   include/cubeao/{core,gl,cache,runtime}/*.h          run-time headers (gl/window.h is not one)
#   include/cubeao/{scene,reference,metrics,bake,scenes,placement}/*.h   offline headers
#   lib/libcubeao_*.a, lib/cmake/cubeao/, lib/pkgconfig/cubeao-runtime.pc
#   share/cubeao/shaders/                                every shader; common/ is also the include directory
#                                                        of the kernel headers ("common/NAME.h"), so C++ and
#                                                        GLSL read one copy
include(CMakePackageConfigHelpers)

set(cubeao_runtime_libraries cubeao_kernels cubeao_core cubeao_gl cubeao_cache cubeao_runtime)
# cubeao_offline links cubeao_scene but not the scenes above it (layering, DESIGN.md §2); a program that
# bakes usually wants builtin: too, hence the umbrella.
add_library(cubeao_offline_package INTERFACE)
target_link_libraries(cubeao_offline_package INTERFACE cubeao_offline cubeao_scenes)
set(cubeao_offline_libraries cubeao_scene cubeao_scenes cubeao_reference cubeao_metrics cubeao_offline
    cubeao_offline_package cubeao_placement)
foreach(lib IN LISTS cubeao_runtime_libraries cubeao_offline_libraries)
  string(REGEX REPLACE "^cubeao_" "" name ${lib})
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${name})
endforeach()
set_target_properties(cubeao_offline PROPERTIES EXPORT_NAME bake)
set_target_properties(cubeao_offline_package PROPERTIES EXPORT_NAME offline)
# The public headers are C++20 (std::span and more): consumers get the standard with them.
target_compile_features(cubeao_core PUBLIC cxx_std_20)
# The same names inside this build, so a project that adds cubeao as a subdirectory links alike.
add_library(cubeao::runtime ALIAS cubeao_runtime)
add_library(cubeao::offline ALIAS cubeao_offline_package)

set(cubeao_cmake_dir "${CMAKE_INSTALL_LIBDIR}/cmake/cubeao")
install(TARGETS ${cubeao_runtime_libraries} EXPORT cubeao-runtime-targets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS ${cubeao_offline_libraries} EXPORT cubeao-offline-targets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT cubeao-runtime-targets NAMESPACE cubeao:: DESTINATION ${cubeao_cmake_dir})
install(EXPORT cubeao-offline-targets NAMESPACE cubeao:: DESTINATION ${cubeao_cmake_dir})

install(DIRECTORY src/cubeao/core src/cubeao/gl src/cubeao/cache src/cubeao/runtime
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/cubeao
  FILES_MATCHING PATTERN "*.h" PATTERN "window.h" EXCLUDE
  PATTERN "cache_codec.h" EXCLUDE)                                   # the cache files' shared layout, private
install(DIRECTORY src/cubeao/scene src/cubeao/reference src/cubeao/metrics src/cubeao/bake
                  scenes/include/cubeao/scenes placement/include/cubeao/placement
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/cubeao
  FILES_MATCHING PATTERN "*.h" PATTERN "soup_importer.h" EXCLUDE    # soup_importer.h: private (OpenMesh)
  PATTERN "oiio_module.h" EXCLUDE)                                   # the image plugin's private table
# The image plugin that cubeao_metrics loads at run time (metrics/oiio_module.h), where oiio_loader.cpp
# looks for it.
install(TARGETS cubeao_oiio LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/cubeao)
install(DIRECTORY shaders/ DESTINATION ${CMAKE_INSTALL_DATADIR}/cubeao/shaders)

configure_package_config_file(cmake/cubeao-config.cmake.in "${CMAKE_CURRENT_BINARY_DIR}/cubeao-config.cmake"
  INSTALL_DESTINATION ${cubeao_cmake_dir}
  PATH_VARS CMAKE_INSTALL_DATADIR)
# 0.x: minor versions may change the API.
write_basic_package_version_file("${CMAKE_CURRENT_BINARY_DIR}/cubeao-config-version.cmake"
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/cubeao-config.cmake"
              "${CMAKE_CURRENT_BINARY_DIR}/cubeao-config-version.cmake"
  DESTINATION ${cubeao_cmake_dir})

# pkg-config, run-time only. Relocatable: the prefix is found from the .pc file's own place, so
# `cmake --install --prefix DIR` works as well as the configured prefix.
file(RELATIVE_PATH cubeao_pc_prefix "${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig" "${CMAKE_INSTALL_PREFIX}")
string(REGEX REPLACE "/$" "" cubeao_pc_prefix "\${pcfiledir}/${cubeao_pc_prefix}")
configure_file(cmake/cubeao-runtime.pc.in "${CMAKE_CURRENT_BINARY_DIR}/cubeao-runtime.pc" @ONLY)
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/cubeao-runtime.pc" DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
