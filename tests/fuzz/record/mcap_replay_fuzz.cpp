// SPDX-License-Identifier: Apache-2.0
// libFuzzer target for the MCAP reader and for replay of what it reads: the input is read as a
// recording (in memory, then from a file as `coxswain replay` does); when it holds ticks and a
// configuration, that configuration is loaded and the ticks replayed. Contract: no crash, no
// exception other than the documented std::invalid_argument for a configuration the core
// refuses.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "coxswain/record/mcap_reader.hpp"
#include "coxswain/replay/replay.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coxswain;
  record::McapReader reader;
  reader.load(std::vector<std::uint8_t>(data, data + size));
  std::size_t messages = 0;
  const record::McapReadReport report =
      reader.read([&](const record::McapMessageView&) { ++messages; });
  (void)report;

  static const std::string path =
      std::string(::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp") + "/coxswain_mcap_fuzz_" +
      std::to_string(::getpid()) + ".mcap";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const replay::Recording rec = replay::load_recording(path);
    if (!rec.ok || rec.config_yaml.empty()) return 0;
    config::ConfigErrors errors;
    const auto config = replay::configuration_from_yaml(rec.config_yaml, errors);
    if (!config) return 0;
    try {
      (void)replay::replay(rec, *config);
    } catch (const std::invalid_argument&) {
      // A recorded configuration the core refuses: reported as such by `coxswain replay`.
    }
  } catch (...) {
    std::abort();
  }
  return 0;
}
