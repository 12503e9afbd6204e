// SPDX-License-Identifier: Apache-2.0
#pragma once
// Polls a condition until it holds or a timeout passes: for tests that wait on threads, pseudo-
// terminals or child processes (real time, so the timeouts are generous, never a measurement).
#include <chrono>
#include <thread>

namespace coxswain::test {

/// True as soon as `condition()` is; false when `timeout` passed first.
template <class F>
bool wait_for(F&& condition, std::chrono::milliseconds timeout = std::chrono::seconds(15),
              std::chrono::milliseconds poll = std::chrono::milliseconds(2)) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(poll);
  }
  return true;
}

}  // namespace coxswain::test
