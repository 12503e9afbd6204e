# SPDX-License-Identifier: Apache-2.0
execute_process(COMMAND git -C ${SOURCE_DIR} rev-parse --short=12 HEAD
                OUTPUT_VARIABLE GIT_HASH OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET
                RESULT_VARIABLE GIT_RESULT)
if(NOT GIT_RESULT EQUAL 0 OR GIT_HASH STREQUAL "")
  set(GIT_HASH "unknown")
else()
  execute_process(COMMAND git -C ${SOURCE_DIR} status --porcelain --untracked-files=no
                  OUTPUT_VARIABLE GIT_DIRTY OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(NOT GIT_DIRTY STREQUAL "")
    set(GIT_HASH "${GIT_HASH}-dirty")
  endif()
endif()
set(CONTENT "// SPDX-License-Identifier: Apache-2.0\n// Generated at build time; do not edit.\n#pragma once\nnamespace coxswain {\ninline constexpr const char* kVersion = \"${PROJECT_VERSION}\";\ninline constexpr const char* kGitHash = \"${GIT_HASH}\";\n}  // namespace coxswain\n")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} OLD)
endif()
if(NOT "${OLD}" STREQUAL "${CONTENT}")
  file(WRITE ${OUTPUT} "${CONTENT}")
endif()
