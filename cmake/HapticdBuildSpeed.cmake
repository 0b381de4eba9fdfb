# What keeps a cold build short (docs/measurements.md, "Build times"; measured with scripts/measure-build.sh and
# the .ninja_log): most translation units spend half their time parsing the same headers (the standard library,
# Eigen with Geometry's SVD, QR and LU, fmt, GoogleTest), so the targets with many of them precompile those; the
# tests carry line tables only (-g1: backtraces and sanitizer reports keep their lines, the objects are an
# eighth of the size and link faster); lld links (CMakeLists.txt).
option(HAPTICD_PCH "precompiled headers for the targets with many translation units" ON)

# System headers only: the precompiled header is the same in every clone and build folder, so ccache can share
# what uses it, and no change to the project's own headers rebuilds it.
set(HAPTICD_PCH_HEADERS
  <algorithm> <array> <atomic> <chrono> <cmath> <cstdint> <cstdio> <filesystem> <functional> <map> <memory>
  <mutex> <optional> <sstream> <stdexcept> <string> <string_view> <thread> <vector>
  <Eigen/Core> <Eigen/Geometry> <Eigen/Cholesky> <fmt/format.h>)

# hapticd_precompile(<target> [REUSE_FROM <other>] [extra headers...])
function(hapticd_precompile target)
  if(NOT HAPTICD_PCH)
    return()
  endif()
  cmake_parse_arguments(ARG "" "REUSE_FROM" "" ${ARGN})
  if(ARG_REUSE_FROM)
    target_precompile_headers(${target} REUSE_FROM ${ARG_REUSE_FROM})
  else()
    target_precompile_headers(${target} PRIVATE ${HAPTICD_PCH_HEADERS} ${ARG_UNPARSED_ARGUMENTS})
  endif()
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    # ccache caches what uses a precompiled header only when the preprocessor output names it.
    target_compile_options(${target} PRIVATE -fpch-preprocess)
  endif()
endfunction()

# Line tables only for what nobody steps through in a debugger: the tests and benchmarks (optimised builds).
function(hapticd_line_tables_only target)
  target_compile_options(${target} PRIVATE $<$<CONFIG:RelWithDebInfo>:-g1>)
endfunction()
