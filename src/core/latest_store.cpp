// SPDX-License-Identifier: Apache-2.0
#include "coxswain/core/latest_store.hpp"

#include <thread>

namespace coxswain::core {

void seqlock_pause(unsigned attempt) {
  // A write copies at most ~64 KiB; spin briefly, then give the writer the core.
  if (attempt < 64) {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
    return;
  }
  std::this_thread::yield();
}

void LatestStore::snapshot(Snapshot& out) const {
  lidar.read(out.lidar);
  imu.read(out.imu);
  gnss.read(out.gnss);
  camera.read(out.camera);
  arduino.read(out.arduino);
  operator_input.read(out.operator_input);
  for (std::size_t i = 0; i < health.size(); ++i) health[i].read(out.health[i]);
}

void LatestStore::refresh(Snapshot& out) const {
  lidar.refresh(out.lidar);
  imu.refresh(out.imu);
  gnss.refresh(out.gnss);
  camera.refresh(out.camera);
  arduino.refresh(out.arduino);
  operator_input.refresh(out.operator_input);
  for (std::size_t i = 0; i < health.size(); ++i) health[i].refresh(out.health[i]);
}

}  // namespace coxswain::core
