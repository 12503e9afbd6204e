// SPDX-License-Identifier: Apache-2.0
#include "coxswain/perception/marker_vote.hpp"

namespace coxswain::perception {

std::optional<std::string> MarkerVoteParams::validate() const {
  if (window_ns <= 0) return "window_ns must be positive";
  if (!(min_ratio > 0.0 && min_ratio <= 1.0)) return "min_ratio must be in (0, 1]";
  if (min_frames == 0) return "min_frames must be at least 1";
  if (min_frames > MarkerVote::kCapacity) return "min_frames exceeds the vote ring capacity";
  if (min_span_ns < 0 || min_span_ns >= window_ns) return "min_span_ns must be in [0, window_ns)";
  return {};
}

bool MarkerVote::add(core::TimeNs stamp_ns, bool seen) {
  if (size_ > 0) {
    const Vote& newest = votes_[(head_ + kCapacity - 1) % kCapacity];
    if (stamp_ns < newest.stamp_ns) return false;
  }
  votes_[head_] = Vote{stamp_ns, seen};
  head_ = (head_ + 1) % kCapacity;
  if (size_ < kCapacity) ++size_;
  return true;
}

VoteTally MarkerVote::tally(core::TimeNs now_ns) const {
  VoteTally t;
  const core::TimeNs oldest_allowed_ns = now_ns - params_.window_ns;
  core::TimeNs oldest_in_window_ns = now_ns;
  // Walk newest to oldest; stamps are non-decreasing in insertion order, so stop at the first
  // vote outside the window.
  for (std::size_t k = 0; k < size_; ++k) {
    const Vote& v = votes_[(head_ + kCapacity - 1 - k) % kCapacity];
    if (v.stamp_ns > now_ns) continue;  // a vote from the caller's future: not yet counted
    if (v.stamp_ns <= oldest_allowed_ns) break;
    ++t.frames;
    if (v.seen) ++t.hits;
    oldest_in_window_ns = v.stamp_ns;
  }
  if (t.frames > 0) t.ratio = static_cast<double>(t.hits) / static_cast<double>(t.frames);
  t.decided = t.frames >= params_.min_frames &&
              now_ns - oldest_in_window_ns >= params_.min_span_ns && t.ratio >= params_.min_ratio;
  return t;
}

}  // namespace coxswain::perception
