#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The core's headers (core, msg, perception, guidance, control, mission) must not reach yaml-cpp,
# Asio, spdlog or OpenCV's video/GUI modules, directly or through another header. Each header is
# preprocessed with -H (the compiler lists every header it opens); any forbidden one fails.
set -euo pipefail
cd "$(dirname "$0")/../.."
cxx="${CXX:-g++}"
forbidden='yaml-cpp/|boost/asio|boost/beast|spdlog/|opencv2/highgui|opencv2/videoio|opencv2/imgcodecs'
status=0
checked=0
for header in $(git ls-files 'include/coxswain/core/*.hpp' 'include/coxswain/msg/*.hpp' \
                  'include/coxswain/perception/*.hpp' 'include/coxswain/guidance/*.hpp' \
                  'include/coxswain/control/*.hpp' 'include/coxswain/mission/*.hpp' \
                  'include/coxswain/config/boat_config.hpp' \
                  'include/coxswain/config/mission_config.hpp' \
                  'include/coxswain/config/param_tables.hpp'); do
  checked=$((checked + 1))
  if ! trace=$("$cxx" -std=c++20 -Iinclude -isystem /usr/include/eigen3 -isystem /usr/include/opencv4 \
                 -H -fsyntax-only -x c++ "$header" 2>&1 >/dev/null); then
    echo "core_headers: $header does not compile on its own:"; echo "$trace" | head -20
    status=1
    continue
  fi
  if bad=$(echo "$trace" | grep -E "^\.+ .*($forbidden)" | head -3) && [ -n "$bad" ]; then
    echo "core_headers: $header reaches a forbidden header:"; echo "$bad"
    status=1
  fi
done
echo "core_headers: $checked headers checked"
exit $status
