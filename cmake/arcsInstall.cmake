# Install rules and the CMake package of arcs, for out-of-tree plugins.
#
#   cmake --install BUILD --prefix PREFIX
# installs
#   PREFIX/bin/arcs                                  the program (it exports the framework's
#                                                    symbols to the plugins it loads)
#   PREFIX/include/arcs/{framework,registry}/**.h    the headers a plugin compiles against
#   PREFIX/lib/cmake/arcs/arcsConfig.cmake           find_package(arcs CONFIG) ->
#                                                    arcs::plugin_api (INTERFACE: include dir,
#                                                    Eigen3::Eigen, C++20), arcs_EXECUTABLE,
#                                                    arcs_PLUGIN_API_VERSION
# A plugin links arcs::plugin_api only (no arcs library: see registry/plugin_api.h);
# examples/plugin_reconstructor/ is a complete one.
#
# Include this file once from the top-level CMakeLists.txt (anywhere after
# project()): the rules are deferred to the end of the top-level directory, so
# the `arcs` target exists when they run. For a build whose CMakeLists does not
# include it yet: -DCMAKE_PROJECT_INCLUDE=<src>/cmake/arcsInstall.cmake.
include_guard(GLOBAL)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

function(arcs_install_rules)
  set(cfgdir ${CMAKE_INSTALL_LIBDIR}/cmake/arcs)
  # Headers, with the source tree's layout (#include "registry/plugin_api.h").
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/framework ${CMAKE_SOURCE_DIR}/registry
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/arcs
          FILES_MATCHING PATTERN "*.h")
  if(TARGET arcs)
    install(TARGETS arcs RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
  # The plugin interface target (also usable in-tree as arcs::plugin_api).
  add_library(arcs_plugin_api INTERFACE)
  add_library(arcs::plugin_api ALIAS arcs_plugin_api)
  set_target_properties(arcs_plugin_api PROPERTIES EXPORT_NAME plugin_api)
  target_include_directories(arcs_plugin_api INTERFACE
    $<BUILD_INTERFACE:${CMAKE_SOURCE_DIR}> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/arcs>)
  target_link_libraries(arcs_plugin_api INTERFACE Eigen3::Eigen)
  target_compile_features(arcs_plugin_api INTERFACE cxx_std_20)
  install(TARGETS arcs_plugin_api EXPORT arcsTargets)
  install(EXPORT arcsTargets NAMESPACE arcs:: DESTINATION ${cfgdir})
  # The plugin API version the installed headers carry (checked at load time).
  file(STRINGS ${CMAKE_SOURCE_DIR}/registry/plugin_api.h api_line REGEX "^#define ARCS_PLUGIN_API_VERSION [0-9]+")
  string(REGEX REPLACE ".* ([0-9]+)$" "\\1" api_version "${api_line}")
  set(cfg ${CMAKE_BINARY_DIR}/arcs-package/arcsConfig.cmake)
  file(WRITE ${cfg} [=[
# arcs package: the plugin interface of an installed arcs.
include(CMakeFindDependencyMacro)
find_dependency(Eigen3 3.3 NO_MODULE)
include("${CMAKE_CURRENT_LIST_DIR}/arcsTargets.cmake")
get_filename_component(_arcs_prefix "${CMAKE_CURRENT_LIST_DIR}/@rel@" ABSOLUTE)
set(arcs_EXECUTABLE "${_arcs_prefix}/@bindir@/arcs")
set(arcs_INCLUDE_DIR "${_arcs_prefix}/@incdir@/arcs")
set(arcs_PLUGIN_API_VERSION @api@)
unset(_arcs_prefix)
]=])
  file(RELATIVE_PATH rel /${cfgdir} /)
  file(READ ${cfg} text)
  string(REPLACE "@rel@" "${rel}" text "${text}")
  string(REPLACE "@bindir@" "${CMAKE_INSTALL_BINDIR}" text "${text}")
  string(REPLACE "@incdir@" "${CMAKE_INSTALL_INCLUDEDIR}" text "${text}")
  string(REPLACE "@api@" "${api_version}" text "${text}")
  file(WRITE ${cfg} "${text}")
  write_basic_package_version_file(${CMAKE_BINARY_DIR}/arcs-package/arcsConfigVersion.cmake
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
  install(FILES ${cfg} ${CMAKE_BINARY_DIR}/arcs-package/arcsConfigVersion.cmake DESTINATION ${cfgdir})
endfunction()

cmake_language(DEFER DIRECTORY ${CMAKE_SOURCE_DIR} CALL arcs_install_rules)
