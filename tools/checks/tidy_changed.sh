#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# clang-tidy (the repository's .clang-tidy, every warning an error) on the C++ sources under
# src/ and tools/ that changed since a base commit: by default the one named in .ci/tidy-base
# (the last state whose changed sources all passed; move it forward when a change lands), or the
# first argument.
# Needs a configured build's compile_commands.json (second argument, default build). The build
# may be GCC's: a warning option clang does not know is ignored, not reported.
#   tools/checks/tidy_changed.sh [BASE] [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/../.."
base=${1:-$(tr -d '[:space:]' < .ci/tidy-base)}
build=${2:-build}
if ! git cat-file -e "$base^{commit}" 2>/dev/null; then
  echo "tidy: base commit '$base' is not in this clone (a shallow clone?): nothing checked"
  exit 0
fi
if [ ! -f "$build/compile_commands.json" ]; then
  echo "tidy: $build/compile_commands.json missing: configure a build first"
  exit 1
fi
mapfile -t files < <(git diff --name-only --diff-filter=AM "$base" HEAD -- 'src/*.cpp' 'tools/*.cpp' |
                     while read -r f; do
                       if grep -q "\"file\": \"[^\"]*/$f\"" "$build/compile_commands.json"; then
                         echo "$f"
                       fi
                     done)
if [ "${#files[@]}" -eq 0 ]; then
  echo "tidy: no C++ source under src/ or tools/ changed since $base"
  exit 0
fi
echo "tidy: ${#files[@]} files changed since $base"
printf '%s\n' "${files[@]}" |
  xargs -P "${COXSWAIN_JOBS:-2}" -n 1 clang-tidy -p "$build" --quiet --warnings-as-errors='*' \
    --extra-arg=-Wno-unknown-warning-option \
    2> >(grep -v "warnings generated" >&2)
echo "tidy: clean"
