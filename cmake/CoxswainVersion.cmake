# SPDX-License-Identifier: Apache-2.0
# The git hash is read at build time (not configure time) so --version never lies after a commit.
add_custom_target(coxswain_version_header
  COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${CMAKE_SOURCE_DIR}
          -DOUTPUT=${CMAKE_BINARY_DIR}/generated/coxswain/version.hpp
          -DPROJECT_VERSION=${PROJECT_VERSION}
          -P ${CMAKE_SOURCE_DIR}/cmake/WriteVersion.cmake
  BYPRODUCTS ${CMAKE_BINARY_DIR}/generated/coxswain/version.hpp
  COMMENT "Writing version header")
