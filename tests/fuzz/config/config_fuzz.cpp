// SPDX-License-Identifier: Apache-2.0
// libFuzzer target for every YAML loader: the first byte of an input picks the kind it is read
// as (the file's kind detected, a boat, devices, mission, vision, course or simulator-sensor
// file), the rest is written to a file and read through the same strict loader the daemon and
// the simulator use. One loader per input, not all of them: each parses the file afresh, so all
// of them on every input made each input cost eight parses and the long run reach an eighth as
// far; libFuzzer's mutations change the first byte like any other, so every loader is fed.
// Contract: no crash and no exception escapes; read as plain YAML, a refused file says why.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "coxswain/config/config.hpp"
#include "coxswain/config/vision_config.hpp"
#include "coxswain/config/yaml_reader.hpp"
#ifdef COXSWAIN_FUZZ_SIM
#include "sim/sensors/sensor_config.hpp"
#include "sim/world/course.hpp"
#endif

namespace {

const std::string& scratch_path() {
  static const std::string path = [] {
    const char* shm = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    return std::string(shm) + "/coxswain_config_fuzz_" + std::to_string(::getpid()) + ".yaml";
  }();
  return path;
}

namespace cfg = coxswain::config;
using Loader = void (*)(const std::string& path, cfg::ConfigErrors& errors);

// Every loader, as the first byte of an input picks it.
constexpr Loader kLoaders[] = {
    [](const std::string& p, cfg::ConfigErrors& e) {
      if (!cfg::load_yaml_file(p, e) && e.empty()) std::abort();  // refused without a reason
      cfg::ConfigErrors kind_errors;
      (void)cfg::detect_config_kind(p, kind_errors);
    },
    [](const std::string& p, cfg::ConfigErrors& e) { (void)cfg::load_boat_config(p, e); },
    [](const std::string& p, cfg::ConfigErrors& e) { (void)cfg::load_devices_config(p, e); },
    [](const std::string& p, cfg::ConfigErrors& e) { (void)cfg::load_mission_config(p, e); },
    [](const std::string& p, cfg::ConfigErrors& e) { (void)cfg::load_vision_file(p, e); },
#ifdef COXSWAIN_FUZZ_SIM
    [](const std::string& p, cfg::ConfigErrors& e) {
      (void)coxswain::sim::world::load_course(p, e);
    },
    [](const std::string& p, cfg::ConfigErrors& e) {
      (void)coxswain::sim::sensors::load_sensor_config_file(p, e);
    },
#endif
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const Loader load = kLoaders[data[0] % std::size(kLoaders)];
  const std::string& path = scratch_path();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    cfg::ConfigErrors errors;
    load(path, errors);
  } catch (...) {
    std::abort();  // the loaders collect errors; nothing may throw
  }
  return 0;
}
