#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# CI entry point for the Arduino firmware. Installs nothing; needs
#   apt-get install arduino-mk arduino-core-avr gcc-avr avr-libc
# 1. compiles the shared protocol/logic headers alone with avr-g++ in strict C++11 with -Werror
#    (proves they stay portable to the firmware compiler);
# 2. builds the sketch with arduino-mk into coxswain_firmware/build-*/ (gitignored), or into
#    $COXSWAIN_ARDUINO_OBJDIR when set.
# Exits non-zero on any failure.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
include_dir="$(cd "${here}/../../include" && pwd)"

for tool in avr-g++ make; do
  command -v "${tool}" >/dev/null || { echo "build.sh: ${tool} not found (install gcc-avr arduino-mk)" >&2; exit 2; }
done
[[ -f /usr/share/arduino/Arduino.mk ]] || { echo "build.sh: /usr/share/arduino/Arduino.mk missing (install arduino-mk)" >&2; exit 2; }

tmp="$(mktemp -d)"
trap 'rm -rf "${tmp}"' EXIT
cat >"${tmp}/portability.cpp" <<'CPP'
#include "coxswain/drivers/arduino/firmware_logic.hpp"
#include "coxswain/drivers/arduino/wire.hpp"
namespace cx = coxswain::drivers::arduino;
int main() {
  cx::FirmwareLogic logic((cx::LogicConfig()));
  cx::FrameDecoder rx;
  cx::SetOutputs cmd;
  cmd.pulse_us[0] = 1600;
  cmd.pulse_us[1] = 1400;
  cmd.led = 2;
  cmd.flags = cx::kFlagArm;
  uint8_t buf[cx::kMaxFrame];
  const size_t n = cx::encode(cmd, 7, buf, sizeof(buf));
  for (size_t i = 0; i < n; ++i) {
    if (rx.push(buf[i]) && cx::parse(rx.frame(), &cmd)) {
      (void)logic.on_set_outputs(1, rx.frame().seq, cmd);
    }
  }
  cx::SwitchInputs in = {false, false};
  return logic.step(2, in).pulse_us[0] == 1500 ? 0 : 1;
}
CPP
echo "== avr-g++ strict portability check"
avr-g++ -mmcu=atmega2560 -std=c++11 -Os -fno-exceptions -Wall -Wextra -Wpedantic -Wshadow \
  -Wconversion -Wsign-conversion -Wold-style-cast -Werror -I"${include_dir}" \
  -c "${tmp}/portability.cpp" -o "${tmp}/portability.o"

echo "== sketch"
make_args=(-C "${here}/coxswain_firmware")
if [[ -n "${COXSWAIN_ARDUINO_OBJDIR:-}" ]]; then
  make_args+=("OBJDIR=${COXSWAIN_ARDUINO_OBJDIR}")
fi
make "${make_args[@]}"
echo "build.sh: firmware OK"
