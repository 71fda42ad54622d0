# Compiler settings shared by every Kilohertz target.
#
# Warnings live on an INTERFACE target that targets link PRIVATE (wrapped in BUILD_INTERFACE so it
# never reaches the export set): consumers of the installed package get none of our flags.

add_library(khz_warnings INTERFACE)
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  target_compile_options(khz_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                                                -Wnon-virtual-dtor -Wcast-align)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_GREATER_EQUAL 12)
    # GCC 12's default level (2) flags Eigen 3.4's aligned realloc, which only reads the old
    # pointer when realloc failed; level 1 still reports unconditional use after free.
    target_compile_options(khz_warnings INTERFACE -Wuse-after-free=1)
  endif()
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND (KHZ_SANITIZE OR (KHZ_NATIVE AND
                                                                  CMAKE_CXX_COMPILER_VERSION
                                                                  VERSION_LESS 13)))
    # False positives, not findings: GCC 12's AVX-512 intrinsics headers trip
    # -Wmaybe-uninitialized on their own variables (GCC bug 105593) whenever Eigen vectorizes
    # with AVX-512, and sanitizer instrumentation at -O1 does the same inside CGAL's std::pair
    # use. -Wuninitialized stays on; the sanitizers themselves catch real uninitialized reads.
    target_compile_options(khz_warnings INTERFACE -Wno-maybe-uninitialized)
  endif()
  if(KHZ_WARNINGS_AS_ERRORS)
    target_compile_options(khz_warnings INTERFACE -Werror)
  endif()
endif()

if(KHZ_NATIVE)
  add_compile_options(-march=native)
endif()

# khz_round_as_written(<source>...): compiles the sources without floating-point contraction, so
# every a·b + c rounds as written (explicit std::fma still fuses). For files whose entry points
# promise one another's values bit for bit: the compiler inlines shared code into each entry point
# separately and, allowed to contract, may fuse a multiply-add in one copy and not in another,
# depending on the CPU it tunes for (docs/ARCHITECTURE.md, "Reproducibility").
# They also skip the precompiled header, which was compiled with contraction allowed.
function(khz_round_as_written)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    set_source_files_properties(${ARGN} DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
                                PROPERTIES COMPILE_OPTIONS -ffp-contract=off
                                           SKIP_PRECOMPILE_HEADERS ON)
  endif()
endfunction()

# khz_precompile_common_headers(<target> [<header>...]): with KHZ_PRECOMPILE_HEADERS, compiles
# the standard and Eigen headers most of our files include (and any given) once for <target>
# instead of once per file. Parsing <Eigen/Dense> and <gtest/gtest.h> alone takes about 4 s per
# file on CI's machine, more than many of our files take to compile; a build has over 400 files.
# Only outside headers go in, so a file that forgets to include one of ours still fails to
# compile. One that forgets one of these compiles here; the fuzz build, which precompiles nothing,
# checks the readers' files, and -DKHZ_PRECOMPILE_HEADERS=OFF checks every file.
set(KHZ_COMMON_HEADERS
    <algorithm>
    <array>
    <cmath>
    <cstdint>
    <filesystem>
    <functional>
    <limits>
    <memory>
    <string>
    <string_view>
    <utility>
    <vector>
    <Eigen/Core>
    <Eigen/Geometry>
    <Eigen/Sparse>)
function(khz_precompile_common_headers target)
  if(KHZ_PRECOMPILE_HEADERS)
    target_precompile_headers(${target} PRIVATE ${KHZ_COMMON_HEADERS} ${ARGN})
  endif()
endfunction()

if(KHZ_SANITIZE)
  # Applied globally: tests and libraries must agree on the instrumented runtime.
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# Hidden visibility: only what a generated export header marks is part of a library's ABI.
set(CMAKE_CXX_VISIBILITY_PRESET hidden)
set(CMAKE_VISIBILITY_INLINES_HIDDEN ON)

find_program(KHZ_CCACHE ccache)
if(KHZ_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  set(CMAKE_CXX_COMPILER_LAUNCHER "${KHZ_CCACHE}")
endif()
