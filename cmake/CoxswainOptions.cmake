# SPDX-License-Identifier: Apache-2.0
# Warning and sanitizer flags, applied through the interface target coxswain_options so that
# every coxswain target gets the same set and third-party headers are left alone.
add_library(coxswain_options INTERFACE)
target_compile_options(coxswain_options INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast -Wcast-align
  -Woverloaded-virtual -Wconversion -Wsign-conversion -Wdouble-promotion
  -Wformat=2 -Wimplicit-fallthrough)
if(COXSWAIN_WERROR)
  target_compile_options(coxswain_options INTERFACE -Werror)
endif()

# The per-tick libraries (perception, guidance, control, mission) at -O3 in the optimised build
# types: GCC's -O2 vectorises only the cheapest loops, and the lidar clustering alone is some
# 13% faster at -O3. Floating-point results do not change (no -ffast-math; the x86-64 baseline
# has no fused multiply-add to contract into). The quick sanitizer and fuzz trees of CI turn it
# off to keep their -O1.
option(COXSWAIN_OPTIMIZE_HOT_PATHS "Compile the per-tick libraries at -O3 in optimised builds" ON)
function(coxswain_hot_path target)
  if(COXSWAIN_OPTIMIZE_HOT_PATHS)
    target_compile_options(${target} PRIVATE $<$<CONFIG:RelWithDebInfo,Release>:-O3>)
  endif()
endfunction()

if(COXSWAIN_SANITIZE)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    # GCC 12's flow analysis under the sanitizers reports false maybe-uninitialized warnings
    # inside libstdc++ (std::function in std::regex); the plain build keeps the warning. Clang
    # (and clang-tidy reading the compile commands) has no such option.
    target_compile_options(coxswain_options INTERFACE -Wno-maybe-uninitialized)
  endif()
  if(COXSWAIN_SANITIZE MATCHES "thread" AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    # GCC warns that ThreadSanitizer does not model std::atomic_thread_fence, which Boost.Asio's
    # cross-thread posting uses; the warning is about the tool, not a fault in our code.
    target_compile_options(coxswain_options INTERFACE -Wno-tsan)
  endif()
  string(REPLACE ";" "," _coxswain_san "${COXSWAIN_SANITIZE}")
  add_compile_options(-fsanitize=${_coxswain_san} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${_coxswain_san})
endif()

if(COXSWAIN_BUILD_FUZZ)
  # Every library in a fuzz build carries libFuzzer's coverage hooks and the sanitizers, so a
  # fuzz target gets feedback from (and catches faults in) the code it links, not just its own
  # source file. The fuzz targets themselves add the fuzzer main (tests/fuzz).
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
