// SPDX-License-Identifier: Apache-2.0
// libFuzzer target for every YAML loader: the input is written to a file and read as a boat,
// devices, mission, vision, course and simulator-sensor file, and its kind detected, through the
// same strict loader the daemon and the simulator use. Contract: no crash, no exception escapes,
// and a refused file always says why.
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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace cfg = coxswain::config;
  const std::string& path = scratch_path();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    cfg::ConfigErrors errors;
    if (!cfg::load_yaml_file(path, errors) && errors.empty()) std::abort();
    load(path,
         [](const std::string& p, cfg::ConfigErrors& e) { (void)cfg::detect_config_kind(p, e); });
    load(path,
         [](const std::string& p, cfg::ConfigErrors& e) { (void)cfg::load_boat_config(p, e); });
    load(path,
         [](const std::string& p, cfg::ConfigErrors& e) { (void)cfg::load_devices_config(p, e); });
    load(path,
         [](const std::string& p, cfg::ConfigErrors& e) { (void)cfg::load_mission_config(p, e); });
    load(path,
         [](const std::string& p, cfg::ConfigErrors& e) { (void)cfg::load_vision_file(p, e); });
#ifdef COXSWAIN_FUZZ_SIM
    load(path, [](const std::string& p, cfg::ConfigErrors& e) {
      (void)coxswain::sim::world::load_course(p, e);
    });
    load(path, [](const std::string& p, cfg::ConfigErrors& e) {
      (void)coxswain::sim::sensors::load_sensor_config_file(p, e);
    });
#endif
  } catch (...) {
    std::abort();  // the loaders collect errors; nothing may throw
  }
  return 0;
}
