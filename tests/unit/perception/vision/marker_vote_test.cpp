// SPDX-License-Identifier: Apache-2.0
// Temporal voting by time, not by loop count: irregular frame rates, window edges, ring wrap.
#include <gtest/gtest.h>

#include "coxswain/perception/marker_vote.hpp"

namespace coxswain::perception {
namespace {

using core::kNsPerMs;
using core::kNsPerSec;

TEST(MarkerVote, DecidesOnRatioWithinTheWindow) {
  MarkerVote vote;  // 2 s window, 60 %, at least 10 frames spanning 1 s
  core::TimeNs t = 0;
  // 30 fps for 2 s, seen in 2 of every 3 frames (67 %).
  for (int i = 0; i < 60; ++i, t += 33 * kNsPerMs) EXPECT_TRUE(vote.add(t, i % 3 != 0));
  const VoteTally ok = vote.tally(t);
  EXPECT_TRUE(ok.decided);
  EXPECT_NEAR(ok.ratio, 2.0 / 3.0, 0.03);
  // Then 1 s of misses: the ratio inside the window falls below 60 %.
  for (int i = 0; i < 30; ++i, t += 33 * kNsPerMs) vote.add(t, false);
  const VoteTally lost = vote.tally(t);
  EXPECT_FALSE(lost.decided);
  EXPECT_LT(lost.ratio, 0.6);
}

TEST(MarkerVote, IrregularFrameRatesUseTimeNotCounts) {
  // A slow stretch of hits long ago must not count once it has left the 2 s window, however few
  // frames arrived since; a fast burst now is judged on its own.
  MarkerVote vote;
  core::TimeNs t = 0;
  for (int i = 0; i < 40; ++i, t += 100 * kNsPerMs) vote.add(t, true);  // 4 s of hits at 10 fps
  EXPECT_TRUE(vote.tally(t).decided);
  t += 3 * kNsPerSec;  // camera stalls 3 s
  // 2.2 s of misses at an irregular rate (5..60 fps), 30 frames.
  for (int i = 0; i < 30; ++i) {
    vote.add(t, false);
    t += (i % 3 == 0 ? 200 : (i % 3 == 1 ? 17 : 40)) * kNsPerMs;
  }
  const VoteTally tally = vote.tally(t);
  EXPECT_EQ(tally.hits, 0U);
  EXPECT_FALSE(tally.decided);
  EXPECT_GT(tally.frames, 10U);
}

TEST(MarkerVote, WindowEdgeIsExclusiveOfOldVotes) {
  MarkerVoteParams p;
  p.window_ns = 1 * kNsPerSec;
  p.min_frames = 1;
  p.min_span_ns = 0;
  p.min_ratio = 0.5;
  ASSERT_FALSE(p.validate().has_value());
  MarkerVote vote(p);
  vote.add(0, true);
  vote.add(500 * kNsPerMs, false);
  EXPECT_EQ(vote.tally(999 * kNsPerMs).frames, 2U);
  EXPECT_EQ(vote.tally(1000 * kNsPerMs).frames, 1U);  // the vote at 0 is exactly 1 s old: out
  EXPECT_EQ(vote.tally(1000 * kNsPerMs).hits, 0U);
  EXPECT_EQ(vote.tally(2 * kNsPerSec).frames, 0U);
  EXPECT_FALSE(vote.tally(2 * kNsPerSec).decided);
}

TEST(MarkerVote, NeedsEnoughFramesAndHistory) {
  MarkerVote vote;  // min 10 frames, 1 s span
  core::TimeNs t = 0;
  for (int i = 0; i < 20; ++i, t += 10 * kNsPerMs) vote.add(t, true);  // 20 hits in 0.2 s
  const VoteTally burst = vote.tally(t);
  EXPECT_EQ(burst.ratio, 1.0);
  EXPECT_FALSE(burst.decided);  // too short a history to trust
  for (int i = 0; i < 5; ++i, t += 250 * kNsPerMs) vote.add(t, true);
  EXPECT_TRUE(vote.tally(t).decided);
}

TEST(MarkerVote, RejectsOutOfOrderAndIgnoresFutureVotes) {
  MarkerVote vote;
  EXPECT_TRUE(vote.add(5 * kNsPerSec, true));
  EXPECT_FALSE(vote.add(4 * kNsPerSec, true));
  EXPECT_EQ(vote.size(), 1U);
  EXPECT_TRUE(vote.add(5 * kNsPerSec, false));  // equal stamps are allowed
  EXPECT_EQ(vote.tally(4 * kNsPerSec).frames, 0U);
  vote.reset();
  EXPECT_EQ(vote.size(), 0U);
  EXPECT_EQ(vote.tally(5 * kNsPerSec).frames, 0U);
}

TEST(MarkerVote, RingWrapKeepsTheMostRecentVotes) {
  MarkerVoteParams p;
  p.window_ns = 10 * kNsPerSec;
  p.min_frames = 10;
  p.min_span_ns = 0;
  MarkerVote vote(p);
  core::TimeNs t = 0;
  // 300 misses then 300 hits at 100 fps: the ring holds the last 256, all hits.
  for (int i = 0; i < 300; ++i, t += 10 * kNsPerMs) vote.add(t, false);
  for (int i = 0; i < 300; ++i, t += 10 * kNsPerMs) vote.add(t, true);
  const VoteTally tally = vote.tally(t);
  EXPECT_EQ(vote.size(), MarkerVote::kCapacity);
  EXPECT_EQ(tally.frames, MarkerVote::kCapacity);
  EXPECT_EQ(tally.hits, MarkerVote::kCapacity);
  EXPECT_TRUE(tally.decided);
}

TEST(MarkerVote, ValidateCatchesBadParams) {
  MarkerVoteParams p;
  EXPECT_FALSE(p.validate().has_value());
  p.min_ratio = 0.0;
  EXPECT_TRUE(p.validate().has_value());
  p = {};
  p.min_frames = MarkerVote::kCapacity + 1;
  EXPECT_TRUE(p.validate().has_value());
  p = {};
  p.min_span_ns = p.window_ns;
  EXPECT_TRUE(p.validate().has_value());
}

}  // namespace
}  // namespace coxswain::perception
