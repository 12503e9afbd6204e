// SPDX-License-Identifier: Apache-2.0
#pragma once
// Temporal voting for the docking decision: "seen in at least `ratio` of the frames of the last
// `window_ns`". The source team voted over loop counts (250 of 400); a time window keeps the same
// meaning when the frame rate changes. Pure: the caller supplies stamps; no clock reads.
#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "coxswain/core/time.hpp"

namespace coxswain::perception {

struct MarkerVoteParams {
  core::TimeNs window_ns = 2 * core::kNsPerSec;  // votes older than this are ignored
  double min_ratio = 0.6;                        // hits / frames needed to decide
  std::size_t min_frames = 10;                   // fewer frames in the window: undecided
  core::TimeNs min_span_ns = core::kNsPerSec;    // window must hold this much history (oldest
                                                 // vote in window at least this old) to decide

  [[nodiscard]] std::optional<std::string> validate() const;
};

struct VoteTally {
  std::size_t frames = 0;  // votes inside the window
  std::size_t hits = 0;    // of which "seen"
  double ratio = 0.0;      // hits / frames (0 when no frames)
  bool decided = false;    // enough frames and span, and ratio >= min_ratio
};

/// Fixed-capacity ring of (stamp, seen) votes. When more than kCapacity votes fall inside the
/// window (faster than 256 frames per window) the oldest are overwritten, so the tally covers
/// the most recent kCapacity frames. Votes older than the newest are rejected. Not thread-safe.
class MarkerVote {
 public:
  static constexpr std::size_t kCapacity = 256;

  explicit MarkerVote(const MarkerVoteParams& params = {}) : params_(params) {}

  /// Records one frame. Returns false (and ignores it) when `stamp_ns` is before the newest vote.
  bool add(core::TimeNs stamp_ns, bool seen);
  /// Tally over votes with stamp in (now_ns - window_ns, now_ns].
  [[nodiscard]] VoteTally tally(core::TimeNs now_ns) const;
  void reset() {
    size_ = 0;
    head_ = 0;
  }
  [[nodiscard]] std::size_t size() const { return size_; }

 private:
  struct Vote {
    core::TimeNs stamp_ns = core::kNeverNs;
    bool seen = false;
  };
  MarkerVoteParams params_;
  std::array<Vote, kCapacity> votes_{};
  std::size_t head_ = 0;  // next write index
  std::size_t size_ = 0;
};

}  // namespace coxswain::perception
