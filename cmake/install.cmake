# The installed package (docs/embedding.md): libraries, public headers, the `skygraph` tool,
# the shaders passes compile at run time, and a CMake config exporting skygraph::skygraph.
#
# Users link one target, skygraph::skygraph: an umbrella over the compiler, the built-in pass
# types' declarations, the scene, image and math libraries and, when the executor is built, the
# executor and the built-in passes' recording code. The pieces are exported too
# (skygraph::compiler, skygraph::verifier, skygraph::golden and skygraph::pass_types are device-free, for tools
# that only compile and check graphs).
# The same names work after add_subdirectory(skygraph).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(SKYGRAPH_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/skygraph)
set(SKYGRAPH_INSTALL_SHADERDIR ${SKYGRAPH_INSTALL_DATADIR}/shaders)
set(SKYGRAPH_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/skygraph)

add_library(skygraph_all INTERFACE)
add_library(skygraph::skygraph ALIAS skygraph_all)
set_target_properties(skygraph_all PROPERTIES EXPORT_NAME skygraph)
target_link_libraries(skygraph_all INTERFACE skygraph_compiler skygraph_verifier skygraph_golden skygraph_pass_types
                      skygraph_scene skygraph_image skygraph_math)
# In the build tree (add_subdirectory) the macro names the source tree's shaders; the installed
# config file points it at the installed copy.
target_compile_definitions(skygraph_all INTERFACE
  $<BUILD_INTERFACE:SKYGRAPH_PACKAGE_SHADER_DIR="${PROJECT_SOURCE_DIR}/shaders">)

set(_skygraph_exported skygraph_all skygraph_compiler skygraph_verifier skygraph_golden skygraph_pass_types skygraph_scene skygraph_image skygraph_math
    skygraph_files skygraph_warnings)
set_target_properties(skygraph_compiler PROPERTIES EXPORT_NAME compiler)
set_target_properties(skygraph_verifier PROPERTIES EXPORT_NAME verifier)
set_target_properties(skygraph_golden PROPERTIES EXPORT_NAME golden)
set_target_properties(skygraph_pass_types PROPERTIES EXPORT_NAME pass_types)
set_target_properties(skygraph_scene PROPERTIES EXPORT_NAME scene)
set_target_properties(skygraph_image PROPERTIES EXPORT_NAME image)
set_target_properties(skygraph_math PROPERTIES EXPORT_NAME math)
# Linked privately by the static libraries, so they are in their link interface. Internal:
# skygraph_files (replacing a file whole) installs no header, and skygraph_warnings carries no
# usage requirements beyond the build tree's warning flags (not propagated by LINK_ONLY).
set_target_properties(skygraph_files PROPERTIES EXPORT_NAME files)
set_target_properties(skygraph_warnings PROPERTIES EXPORT_NAME warnings)
set(SKYGRAPH_PACKAGE_HAS_EXECUTOR OFF)
if(TARGET skygraph_passes)
  set(SKYGRAPH_PACKAGE_HAS_EXECUTOR ON)
  target_link_libraries(skygraph_all INTERFACE skygraph_executor skygraph_passes)
  set_target_properties(skygraph_executor PROPERTIES EXPORT_NAME executor)
  set_target_properties(skygraph_passes PROPERTIES EXPORT_NAME passes)
  list(APPEND _skygraph_exported skygraph_executor skygraph_passes)
endif()

# Projects that add_subdirectory(skygraph) usually install only their own files.
option(SKYGRAPH_INSTALL "Install skygraph's package with the project" ${PROJECT_IS_TOP_LEVEL})
if(SKYGRAPH_INSTALL)
install(TARGETS ${_skygraph_exported} EXPORT skygraphTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/skygraph
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.hpp")
install(TARGETS skygraph RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/shaders/ DESTINATION ${SKYGRAPH_INSTALL_SHADERDIR})
# graphs/ and scenes/ keep their "$schema": "../schemas/..." references valid beside schemas/.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/graphs ${PROJECT_SOURCE_DIR}/scenes ${PROJECT_SOURCE_DIR}/schemas
  DESTINATION ${SKYGRAPH_INSTALL_DATADIR})

install(EXPORT skygraphTargets NAMESPACE skygraph:: DESTINATION ${SKYGRAPH_INSTALL_CMAKEDIR})
# skygraph::testing links GoogleTest: a set of its own, loaded when the user's project has GTest.
if(TARGET skygraph_testing)
  install(TARGETS skygraph_testing EXPORT skygraphTestingTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(EXPORT skygraphTestingTargets NAMESPACE skygraph:: DESTINATION ${SKYGRAPH_INSTALL_CMAKEDIR})
endif()
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/skygraphConfig.cmake.in
  ${PROJECT_BINARY_DIR}/skygraphConfig.cmake
  INSTALL_DESTINATION ${SKYGRAPH_INSTALL_CMAKEDIR}
  PATH_VARS SKYGRAPH_INSTALL_DATADIR SKYGRAPH_INSTALL_SHADERDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/skygraphConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/skygraphConfig.cmake ${PROJECT_BINARY_DIR}/skygraphConfigVersion.cmake
  DESTINATION ${SKYGRAPH_INSTALL_CMAKEDIR})
endif()

# Where ShaderCompiler::defaultIncludeDir() looks (framework/executor/shader_compiler.cpp):
# SKYGRAPH_SHADER_DIR in the environment, then <executable>/../share/skygraph/shaders (an
# installed, possibly relocated `skygraph`), then the source tree, then the configured prefix.
if(TARGET skygraph_executor)
  file(RELATIVE_PATH _skygraph_bin_to_shaders ${CMAKE_INSTALL_FULL_BINDIR}
       ${CMAKE_INSTALL_PREFIX}/${SKYGRAPH_INSTALL_SHADERDIR})
  target_compile_definitions(skygraph_executor PRIVATE
    SKYGRAPH_SHADER_DIR_FROM_BINDIR="${_skygraph_bin_to_shaders}"
    SKYGRAPH_SHADER_INSTALL_DIR="${CMAKE_INSTALL_PREFIX}/${SKYGRAPH_INSTALL_SHADERDIR}")
endif()
