# salsa_add_plugin(<target> <sources>... [VERSION v] [AUTHOR a] [BRIEF b] [NO_RUN] [NO_INSTALL])
# Builds a salsa plugin: a shared library that only sees the SDK, with its metadata compiled in.
# In the salsa build tree it lands in the build's plugins/ folder; installed, in lib/salsa/plugins.
#
# Out of tree (through find_package(salsa)) it also:
# - builds the plugin optimised (-O2 -DNDEBUG) when the project chose no build type (single-config
#   generators only; a build type the author chose is kept);
# - installs it into the user plugin folder the loader searches, SALSA_USER_PLUGIN_DIR (default
#   ~/.local/share/salsa/plugins), so `cmake --install build` makes it available to salsa and salsa-gui;
# - when the project has testing on (enable_testing(); BUILD_TESTING not OFF) and the package ships the
#   `salsa` program (SALSA_EXECUTABLE), adds the CTest smoke test <target>_loads: `salsa plugins
#   --plugin-dir <folder of the built file>` must list the plugin's registrations without refusing any,
#   and each registration runs in a 1 s test of a few drones (NO_RUN: only the listing).
# NO_INSTALL: neither the install rule nor the smoke test (salsa's own test plugins).
function(salsa_add_plugin target)
  cmake_parse_arguments(ARG "NO_RUN;NO_INSTALL" "VERSION;AUTHOR;BRIEF" "" ${ARGN})
  if(NOT ARG_VERSION)
    set(ARG_VERSION "${PROJECT_VERSION}")
  endif()
  add_library(${target} MODULE ${ARG_UNPARSED_ARGUMENTS})
  if(TARGET salsa_sdk)
    target_link_libraries(${target} PRIVATE salsa_sdk)
  else()
    target_link_libraries(${target} PRIVATE salsa::sdk)
  endif()
  target_compile_definitions(${target} PRIVATE
    SALSA_PLUGIN_NAME="${target}" SALSA_PLUGIN_VERSION="${ARG_VERSION}"
    SALSA_PLUGIN_AUTHOR="${ARG_AUTHOR}" SALSA_PLUGIN_BRIEF="${ARG_BRIEF}")
  # Hidden by default: each plugin keeps its own copy of the SDK's inline state.
  set_target_properties(${target} PROPERTIES CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
  if(DEFINED SALSA_PLUGIN_OUTPUT_DIR)
    set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${SALSA_PLUGIN_OUTPUT_DIR})
    target_compile_options(${target} PRIVATE ${SALSA_WARNINGS})
    install(TARGETS ${target} LIBRARY DESTINATION ${SALSA_PLUGIN_INSTALL_DIR})
    return()
  endif()

  # ---- Out of tree ----
  # Optimised by default: a behavior's decide runs for every drone on every step.
  get_property(multi_config GLOBAL PROPERTY GENERATOR_IS_MULTI_CONFIG)
  if(NOT multi_config AND NOT CMAKE_BUILD_TYPE)
    target_compile_options(${target} PRIVATE -O2)
    target_compile_definitions(${target} PRIVATE NDEBUG)
  endif()

  if(ARG_NO_INSTALL)
    return()
  endif()
  # `cmake --install build` puts it where salsa looks for a user's plugins.
  if(NOT DEFINED SALSA_USER_PLUGIN_DIR)
    set(user_dir "$ENV{HOME}/.local/share/salsa/plugins")
    set(SALSA_USER_PLUGIN_DIR "${user_dir}" CACHE PATH
        "Where `cmake --install` puts salsa plugins (the user plugin folder salsa searches)")
  endif()
  install(TARGETS ${target} LIBRARY DESTINATION "${SALSA_USER_PLUGIN_DIR}")

  # The smoke test, run by the installed salsa against the built file.
  if(DEFINED BUILD_TESTING AND NOT BUILD_TESTING)
    return()
  endif()
  if(NOT SALSA_EXECUTABLE OR NOT EXISTS "${SALSA_EXECUTABLE}")
    message(STATUS "salsa_add_plugin(${target}): no smoke test (the salsa program was not found at '${SALSA_EXECUTABLE}')")
    return()
  endif()
  set(run ON)
  if(ARG_NO_RUN)
    set(run OFF)
  endif()
  add_test(NAME ${target}_loads
           COMMAND ${CMAKE_COMMAND} -DSALSA=${SALSA_EXECUTABLE} -DPLUGIN=$<TARGET_FILE:${target}>
                   -DWORK=${CMAKE_CURRENT_BINARY_DIR}/${target}_loads -DRUN=${run}
                   -P ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/SalsaSmokeTest.cmake)
  # Only the built file and salsa's own plugins: not a copy installed in the user folder earlier.
  set_tests_properties(${target}_loads PROPERTIES TIMEOUT 120
                       ENVIRONMENT "HOME=${CMAKE_CURRENT_BINARY_DIR}/${target}_loads/home;SALSA_PLUGIN_PATH=")
endfunction()

# salsa_add_plugin_test(<target> <sources>... PLUGIN <plugin target>)
# A test executable for a plugin: links the stepping fixture (salsa/fixture.hpp, salsa::fixture),
# defines SALSA_PLUGIN_FILE as the built plugin's path and registers it with CTest.
function(salsa_add_plugin_test target)
  cmake_parse_arguments(ARG "" "PLUGIN" "" ${ARGN})
  if(NOT ARG_PLUGIN)
    message(FATAL_ERROR "salsa_add_plugin_test(${target}): PLUGIN <plugin target> is required")
  endif()
  add_executable(${target} ${ARG_UNPARSED_ARGUMENTS})
  if(TARGET salsa_fixture)
    target_link_libraries(${target} PRIVATE salsa_fixture)
  else()
    target_link_libraries(${target} PRIVATE salsa::fixture)
  endif()
  target_compile_definitions(${target} PRIVATE SALSA_PLUGIN_FILE="$<TARGET_FILE:${ARG_PLUGIN}>")
  add_dependencies(${target} ${ARG_PLUGIN})
  add_test(NAME ${target} COMMAND ${target})
endfunction()
