# SPDX-License-Identifier: Apache-2.0
# Every dependency is a Debian 12 package; scripts/setup.sh installs them.
find_package(Threads REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
# Debian's four OpenCV module packages ship headers and libraries but no OpenCVConfig.cmake (that
# comes with libopencv-dev, which pulls VTK and much more), so the modules are found one by one.
find_path(COXSWAIN_OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4 REQUIRED)
# coxswain_opencv_base: core and imgproc, all the daemon links. coxswain_opencv adds imgcodecs
# and videoio (some 120 more shared libraries, ~48 MB resident): the image-I/O module, the
# simulator and the tests link it; the daemon loads the module when it first needs it.
add_library(coxswain_opencv_base INTERFACE)
target_include_directories(coxswain_opencv_base SYSTEM INTERFACE ${COXSWAIN_OPENCV_INCLUDE_DIR})
add_library(coxswain_opencv INTERFACE)
target_link_libraries(coxswain_opencv INTERFACE coxswain_opencv_base)
foreach(cv_module core imgproc imgcodecs videoio)
  find_library(COXSWAIN_OPENCV_${cv_module} opencv_${cv_module} REQUIRED)
  if(cv_module STREQUAL "core" OR cv_module STREQUAL "imgproc")
    target_link_libraries(coxswain_opencv_base INTERFACE ${COXSWAIN_OPENCV_${cv_module}})
  else()
    target_link_libraries(coxswain_opencv INTERFACE ${COXSWAIN_OPENCV_${cv_module}})
  endif()
endforeach()
find_package(Boost 1.74 REQUIRED)
find_package(spdlog REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(GEOGRAPHICLIB REQUIRED IMPORTED_TARGET geographiclib)
pkg_check_modules(ZSTD REQUIRED IMPORTED_TARGET libzstd)
pkg_check_modules(SYSTEMD REQUIRED IMPORTED_TARGET libsystemd)
if(COXSWAIN_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(COXSWAIN_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
