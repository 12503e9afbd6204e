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

template <class Load>
void load(const std::string& path, Load fn) {
  coxswain::config::ConfigErrors errors;
  fn(path, errors);
}

#ifdef COXSWAIN_FUZZ_SIM
constexpr std::uint8_t kLoaderCount = 7;
#else
constexpr std::uint8_t kLoaderCount = 5;
#endif

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace cfg = coxswain::config;
  if (size == 0) return 0;
  const std::uint8_t kind = data[0];
  const std::string& path = scratch_path();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    switch (kind % kLoaderCount) {
      case 0: {
        cfg::ConfigErrors errors;
        if (!cfg::load_yaml_file(path, errors) && errors.empty()) std::abort();
        load(path, [](const std::string& p, cfg::ConfigErrors& e) {
          (void)cfg::detect_config_kind(p, e);
        });
        break;
      }
      case 1:
        load(path,
             [](const std::string& p, cfg::ConfigErrors& e) { (void)cfg::load_boat_config(p, e); });
        break;
      case 2:
        load(path, [](const std::string& p, cfg::ConfigErrors& e) {
          (void)cfg::load_devices_config(p, e);
        });
        break;
      case 3:
        load(path, [](const std::string& p, cfg::ConfigErrors& e) {
          (void)cfg::load_mission_config(p, e);
        });
        break;
      case 4:
        load(path,
             [](const std::string& p, cfg::ConfigErrors& e) { (void)cfg::load_vision_file(p, e); });
        break;
#ifdef COXSWAIN_FUZZ_SIM
      case 5:
        load(path, [](const std::string& p, cfg::ConfigErrors& e) {
          (void)coxswain::sim::world::load_course(p, e);
        });
        break;
      case 6:
        load(path, [](const std::string& p, cfg::ConfigErrors& e) {
          (void)coxswain::sim::sensors::load_sensor_config_file(p, e);
        });
        break;
#endif
      default:
        break;
    }
  } catch (...) {
    std::abort();  // the loaders collect errors; nothing may throw
  }
  return 0;
}
