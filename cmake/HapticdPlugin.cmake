# hapticd_add_plugin(<target> SOURCES <files...>)
# Builds a hapticd plugin: a shared library linked against hapticd::api, with hidden visibility except the
# entry points that HAPTICD_PLUGIN_LIBRARY exports, no "lib" prefix games, and output into the plugin folder
# that the server searches (<prefix>/lib/hapticd/plugins in the build tree and once installed).
# Used in-tree and, through find_package(hapticd), by out-of-tree plugin authors.
function(hapticd_add_plugin target)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  add_library(${target} MODULE ${ARG_SOURCES})
  if(TARGET hapticd::api)
    target_link_libraries(${target} PRIVATE hapticd::api)
  else()
    target_link_libraries(${target} PRIVATE hapticd_api)
  endif()
  set_target_properties(${target} PROPERTIES
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    PREFIX "lib")
  if(DEFINED HAPTICD_PLUGIN_SUBDIR)
    set_target_properties(${target} PROPERTIES
      LIBRARY_OUTPUT_DIRECTORY "${PROJECT_BINARY_DIR}/${HAPTICD_PLUGIN_SUBDIR}")
  endif()
endfunction()
