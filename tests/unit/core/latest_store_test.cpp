// SPDX-License-Identifier: Apache-2.0
#include "coxswain/core/latest_store.hpp"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <memory>
#include <thread>
#include <vector>

namespace coxswain::core {
namespace {

// A value whose every word is derived from one counter: any mix of two writes is detectable.
struct Pattern {
  static constexpr std::size_t kWords = 700;  // ~5.6 KiB, many cache lines
  std::array<std::uint64_t, kWords> words{};
  void fill(std::uint64_t counter) {
    for (std::size_t i = 0; i < kWords; ++i) words[i] = counter * 1'000'003ULL + i;
  }
  [[nodiscard]] bool consistent(std::uint64_t* counter_out) const {
    const std::uint64_t counter = words[0] / 1'000'003ULL;
    for (std::size_t i = 0; i < kWords; ++i) {
      if (words[i] != counter * 1'000'003ULL + i) return false;
    }
    *counter_out = counter;
    return true;
  }
};

TEST(LatestSlot, NeverWrittenIsInvalidAndStale) {
  LatestSlot<msg::ImuSample> slot;
  const Sample<msg::ImuSample> s = slot.read();
  EXPECT_FALSE(s.valid());
  EXPECT_EQ(s.sequence, 0U);
  EXPECT_TRUE(s.is_stale(0, kNsPerSec));
  EXPECT_EQ(slot.sequence(), 0U);
}

TEST(LatestSlot, ReadReturnsLatestWithSequenceAndStamp) {
  LatestSlot<msg::ImuSample> slot;
  msg::ImuSample imu;
  imu.heading_deg = 12.5;
  slot.publish(imu, 1000);
  imu.heading_deg = -3.0;
  slot.publish(imu, 2000);
  const Sample<msg::ImuSample> s = slot.read();
  EXPECT_TRUE(s.valid());
  EXPECT_EQ(s.sequence, 2U);
  EXPECT_EQ(s.stamp_ns, 2000);
  EXPECT_DOUBLE_EQ(s.value.heading_deg, -3.0);
  EXPECT_EQ(s.age_ns(2500), 500);
  EXPECT_FALSE(s.is_stale(2500, 500));
  EXPECT_TRUE(s.is_stale(2501, 500));
}

TEST(LatestStore, SnapshotCopiesEverySlot) {
  auto store = std::make_unique<LatestStore>();
  auto snap = std::make_unique<Snapshot>();
  msg::LidarScan scan;
  ASSERT_TRUE(scan.push({10.0F, 2.5F, 40, 0}));
  store->lidar.publish(scan, 5);
  msg::GnssFix fix;
  fix.lat_deg = 35.0;
  store->gnss.publish(fix, 6);
  msg::DeviceHealth health;
  health.device = msg::DeviceId::kCamera;
  health.set_detail("cannot open /dev/videoCAM");
  store->health_of(msg::DeviceId::kCamera).publish(health, 7);
  store->snapshot(*snap);
  EXPECT_EQ(snap->lidar.value.point_count, 1U);
  EXPECT_FLOAT_EQ(snap->lidar.value.points[0].range_m, 2.5F);
  EXPECT_DOUBLE_EQ(snap->gnss.value.lat_deg, 35.0);
  EXPECT_FALSE(snap->imu.valid());
  EXPECT_EQ(snap->health[4].value.detail_text(), "cannot open /dev/videoCAM");
}

// Writers publish as fast as they can while readers check every value they see for tearing and
// for sequence numbers that go backwards. Runs under ThreadSanitizer in CI (label concurrency).
// A value whose size is not a whole number of words (the slot's last word is partly used).
struct Odd {
  std::uint8_t bytes[13];
};

TEST(LatestSlot, ValuesOfAnySizeRoundTrip) {
  LatestSlot<Odd> slot;
  Odd in{};
  for (std::uint8_t i = 0; i < 13; ++i) in.bytes[i] = static_cast<std::uint8_t>(200 + i);
  slot.publish(in, 11);
  const Sample<Odd> out = slot.read();
  EXPECT_EQ(std::memcmp(out.value.bytes, in.bytes, sizeof in.bytes), 0);
  EXPECT_EQ(out.stamp_ns, 11);
  EXPECT_EQ(out.sequence, 1U);
}

TEST(LatestSlot, RefreshCopiesOnlyANewValue) {
  LatestSlot<msg::ImuSample> slot;
  Sample<msg::ImuSample> out;
  slot.refresh(out);
  EXPECT_FALSE(out.valid());
  msg::ImuSample a;
  a.roll_deg = 1.5;
  slot.publish(a, 10);
  slot.refresh(out);
  EXPECT_EQ(out.sequence, 1U);
  EXPECT_DOUBLE_EQ(out.value.roll_deg, 1.5);
  // Nothing new: the held copy is taken as current and left alone (a caller that changes its
  // copy would see its change; refresh() is for callers that do not).
  out.value.roll_deg = 99.0;
  slot.refresh(out);
  EXPECT_DOUBLE_EQ(out.value.roll_deg, 99.0);
  a.roll_deg = -2.0;
  slot.publish(a, 20);
  slot.refresh(out);
  EXPECT_EQ(out.sequence, 2U);
  EXPECT_EQ(out.stamp_ns, 20);
  EXPECT_DOUBLE_EQ(out.value.roll_deg, -2.0);
}

TEST(LatestStore, RefreshGivesWhatSnapshotGives) {
  auto store = std::make_unique<LatestStore>();
  auto refreshed = std::make_unique<Snapshot>();
  auto copied = std::make_unique<Snapshot>();
  msg::LidarScan scan;
  for (int tick = 0; tick < 12; ++tick) {
    if (tick % 5 == 0) {  // a scan now and then, other slots every tick
      ASSERT_TRUE(scan.push({static_cast<float>(tick), 2.5F, 40, 0}));
      store->lidar.publish(scan, tick);
    }
    msg::GnssFix fix;
    fix.lat_deg = 35.0 + tick;
    store->gnss.publish(fix, tick);
    store->refresh(*refreshed);
    store->snapshot(*copied);
    ASSERT_EQ(std::memcmp(&refreshed->lidar.value, &copied->lidar.value, sizeof(msg::LidarScan)),
              0);
    EXPECT_EQ(refreshed->lidar.sequence, copied->lidar.sequence);
    EXPECT_EQ(refreshed->lidar.stamp_ns, copied->lidar.stamp_ns);
    EXPECT_DOUBLE_EQ(refreshed->gnss.value.lat_deg, 35.0 + tick);
    EXPECT_EQ(refreshed->gnss.sequence, copied->gnss.sequence);
    EXPECT_FALSE(refreshed->imu.valid());
  }
}

TEST(LatestStoreStress, NoTornReadsWithConcurrentWritersAndReaders) {
  constexpr int kSlots = 3;
  constexpr int kReadersPerSlot = 2;
  constexpr std::uint64_t kWrites = 20'000;
  std::array<LatestSlot<Pattern>, kSlots> slots;
  std::atomic<bool> writers_done{false};
  std::atomic<std::uint64_t> torn{0};
  std::atomic<std::uint64_t> backwards{0};
  std::atomic<std::uint64_t> mismatched{0};
  std::atomic<std::uint64_t> reads{0};

  std::vector<std::thread> threads;
  for (int s = 0; s < kSlots; ++s) {
    threads.emplace_back([&, s] {
      auto value = std::make_unique<Pattern>();
      for (std::uint64_t c = 1; c <= kWrites; ++c) {
        value->fill(c + static_cast<std::uint64_t>(s) * 7);
        slots[static_cast<std::size_t>(s)].publish(*value, static_cast<TimeNs>(c));
      }
    });
    for (int r = 0; r < kReadersPerSlot; ++r) {
      threads.emplace_back([&, s] {
        auto sample = std::make_unique<Sample<Pattern>>();
        std::uint64_t last_seq = 0;
        std::uint64_t local_reads = 0;
        while (!writers_done.load(std::memory_order_acquire) || local_reads < 100) {
          slots[static_cast<std::size_t>(s)].read(*sample);
          ++local_reads;
          if (!sample->valid()) continue;
          std::uint64_t counter = 0;
          if (!sample->value.consistent(&counter)) {
            torn.fetch_add(1);
            continue;
          }
          // Value, stamp and sequence come from the same write.
          if (counter != sample->sequence + static_cast<std::uint64_t>(s) * 7 ||
              sample->stamp_ns != static_cast<TimeNs>(sample->sequence)) {
            mismatched.fetch_add(1);
          }
          if (sample->sequence < last_seq) backwards.fetch_add(1);
          last_seq = sample->sequence;
        }
        reads.fetch_add(local_reads);
      });
    }
  }
  for (int s = 0; s < kSlots; ++s)
    threads[static_cast<std::size_t>(s * (1 + kReadersPerSlot))].join();
  writers_done.store(true, std::memory_order_release);
  for (std::size_t i = 0; i < threads.size(); ++i) {
    if (threads[i].joinable()) threads[i].join();
  }
  EXPECT_EQ(torn.load(), 0U);
  EXPECT_EQ(mismatched.load(), 0U);
  EXPECT_EQ(backwards.load(), 0U);
  EXPECT_GT(reads.load(), 0U);
  for (auto& slot : slots) EXPECT_EQ(slot.sequence(), kWrites);
}

}  // namespace
}  // namespace coxswain::core
