# salsa_add_plugin(<target> <sources>... [VERSION v] [AUTHOR a] [BRIEF b])
# Builds a salsa plugin: a shared library that only sees the SDK, with its metadata compiled in.
# In the salsa build tree it lands in the build's plugins/ folder; installed, in lib/salsa/plugins.
function(salsa_add_plugin target)
  cmake_parse_arguments(ARG "" "VERSION;AUTHOR;BRIEF" "" ${ARGN})
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
  endif()
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
