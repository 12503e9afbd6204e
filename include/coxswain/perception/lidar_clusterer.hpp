// SPDX-License-Identifier: Apache-2.0
#pragma once
// Lidar clustering (docs/missions.md, after the source team's reduced obstacle_detector):
// (A) group neighbouring returns, (B) split each group at the point farthest from its chord,
// (C) classify long pieces as walls, (D) split walls into bounded pieces; each final piece becomes
// an ObstacleSegment in the body frame. Also fills the closest range per bearing bin.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coxswain/msg/lidar_scan.hpp"
#include "coxswain/perception/obstacles.hpp"

namespace coxswain::perception {

/// Axis-aligned box in the body frame (metres). Returns inside it are the boat's own hull, mast or
/// crew and are dropped. An empty box (min >= max on either axis) drops nothing.
struct HullBox {
  double forward_min_m = 0.0;
  double forward_max_m = 0.0;
  double starboard_min_m = 0.0;
  double starboard_max_m = 0.0;

  [[nodiscard]] bool empty() const {
    return forward_min_m >= forward_max_m || starboard_min_m >= starboard_max_m;
  }
  [[nodiscard]] bool contains(double forward_m, double starboard_m) const {
    return !empty() && forward_m >= forward_min_m && forward_m <= forward_max_m &&
           starboard_m >= starboard_min_m && starboard_m <= starboard_max_m;
  }
};

/// Rule details that differ between coxswain and the source team's 2022 node. kTricat2022 exists
/// only to replay their recordings and compare (tests/unit/perception/lidar/).
enum class ClusterSemantics : std::uint8_t {
  /// Groups need >= min_group_points; a split point is shared by both halves (corners meet); a
  /// split is refused when a half would have fewer than min_split_points; walls are cut into
  /// ceil(length / piece) equal pieces that share their boundary returns (no gaps).
  kCoxswain = 0,
  /// Groups need > min_group_points; the split point starts the second half; a split is refused
  /// when either half would have fewer than min_group_points; wall pieces are cut when a return is
  /// farther than the piece length from the piece's first return (pieces leave gaps).
  kTricat2022 = 1,
};

/// Tunables of LidarClusterer. Distances in metres, angles in degrees. Defaults are coxswain's;
/// `reference_tricat2022()` is the source team's set for their 0223 recording.
struct LidarClusterParams {
  /// (A) A new group starts when two consecutive returns are farther apart than
  /// group_gap_m + group_gap_per_m * (smaller of their ranges). The proportional part keeps far
  /// objects whole although beam spacing grows with range (0.03 m/m ~ 1.7 deg of arc).
  double group_gap_m = 0.10;
  double group_gap_per_m = 0.03;
  /// Groups with fewer returns are noise (spray, birds, single stray returns).
  std::uint32_t min_group_points = 4;
  /// (B) Split when the farthest return lies more than this from the chord; the proportional part
  /// absorbs range noise (RPLIDAR ~1 % of range) so far walls are not shredded.
  double split_distance_m = 0.10;
  double split_distance_per_m = 0.01;
  /// kCoxswain: each half of a split must keep at least this many returns.
  std::uint32_t min_split_points = 3;
  /// (C) Pieces longer than this are walls, shorter ones buoys.
  double wall_min_length_m = 0.30;
  /// (D) Walls are cut into pieces no longer than this.
  double wall_piece_max_length_m = 0.70;
  /// Returns nearer than min_range_m or farther than max_range_m (or the scan's own max_range_m
  /// when that is smaller and nonzero) are dropped, as are returns inside `hull`.
  double min_range_m = 0.15;
  double max_range_m = 25.0;
  /// Default: a 2.0 m x 1.08 m hull (docs/simulator.md) behind a bow-mounted lidar, with margin.
  HullBox hull{-2.2, 0.1, -0.65, 0.65};
  /// RangeProfile bin width; 360 / width bins must fit RangeProfile::kMaxBins.
  double profile_bin_width_deg = 1.0;
  /// Fit each final piece by total least squares and end it at the projections of its first and
  /// last returns (false: the chord between the first and last returns, as the source team did).
  bool line_fit = true;
  /// Join the group that wraps across the scan seam (first and last groups of the walk).
  bool merge_across_seam = true;
  /// The walk starts at the first return at or past this bearing in walk order. The source team's
  /// walk started at the bow and went to port (their laser frame's seam pointed at the bow).
  double walk_start_bearing_deg = -180.0;
  /// true: bearing ascending (clockwise, to starboard); false: descending.
  bool walk_clockwise = true;
  ClusterSemantics semantics = ClusterSemantics::kCoxswain;

  /// The source team's behaviour for the 0223 run: fixed 0.1 m gap, groups of more than 10
  /// returns, split 0.1 m, wall 0.3 m, piece 0.7 m, chord endpoints, no seam merge, no hull box,
  /// range 0.15..25 m (their rplidar_ros limits), walk from the bow towards port.
  [[nodiscard]] static LidarClusterParams reference_tricat2022();

  /// Empty when usable, else what is wrong.
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Counters of the last process() call, for health reporting and tests.
struct LidarClusterStats {
  std::uint32_t points_in = 0;          // returns in the scan
  std::uint32_t points_kept = 0;        // after range and hull filters
  std::uint32_t groups = 0;             // groups kept after the noise filter
  std::uint32_t groups_dropped = 0;     // groups dropped as noise
  std::uint32_t segments = 0;           // segments written
  std::uint32_t segments_overflow = 0;  // segments lost to ObstacleList::kMaxSegments
  bool seam_merged = false;             // a group wrapped across the walk's seam
};

/// Turns one LidarScan into obstacle segments and a range profile, both in the body frame.
/// Configure once (the constructor sizes every work array from LidarScan::kMaxPoints and throws
/// std::invalid_argument on invalid params); process() then never allocates and is deterministic:
/// its output depends on the scan and the params alone, never on earlier scans.
/// The returns are worked on as single-precision points (a float's 24 bits hold a 25 m range to
/// 2 um, far below the 0.25 mm a lidar reports); the segments' end points are fitted in double.
/// Not thread-safe: one instance per thread.
class LidarClusterer {
 public:
  explicit LidarClusterer(const LidarClusterParams& params = {});

  /// Overwrites `out` and `profile`. Segments come in walk order; each has its true closest
  /// distance from the body origin (not its first return's).
  void process(const msg::LidarScan& scan, ObstacleList& out, RangeProfile& profile);

  [[nodiscard]] const LidarClusterParams& params() const { return params_; }
  [[nodiscard]] const LidarClusterStats& last_stats() const { return stats_; }

  /// Table steps per degree of the beam trigonometry.
  static constexpr int kTrigStepsPerDeg = 4;
  /// cos and sin of a bearing in [-180, 180] degrees as process() turns a return into a point:
  /// a table every 1 / kTrigStepsPerDeg degrees and the angle-addition formula with the first
  /// terms of the series for the remainder (under 4.4e-3 rad, so what is left out lies below a
  /// float's rounding): within 1.5e-7 of the exact values, for a handful of flops instead of a
  /// library call per return.
  void unit_of(float bearing_deg, float& cos_out, float& sin_out) const;

 private:
  struct Span {  // [begin, end) into the work arrays
    std::uint32_t begin;
    std::uint32_t end;
  };

  void filter_points(const msg::LidarScan& scan);
  // One return that the four-at-a-time path left alone: its bearing wrapped when outside
  // (-180, 180], dropped by any check, else appended at `kept`; returns the new count.
  [[nodiscard]] std::uint32_t append_checked(std::uint32_t kept, const msg::LidarPoint& p);
  void find_walk_start();
  [[nodiscard]] std::int32_t bin_of(float bearing_deg) const;
  void group_points();
  void copy_points(std::uint32_t from, std::uint32_t count, std::uint32_t to);
  void split_group(Span group);
  // The return farthest from the chord of s (the first such) and its distance; when that
  // distance is not above no_split_m, s.begin stands for it (it is not split there).
  [[nodiscard]] std::uint32_t farthest_from_chord(Span s, double& max_d, double no_split_m) const;
  void emit_piece(Span piece);
  void emit_wall(Span piece);
  void emit_segment(Span piece, ObstacleKind kind);
  void fill_profile(RangeProfile& profile) const;

  LidarClusterParams params_;
  LidarClusterStats stats_;
  std::uint32_t profile_bins_ = 0;
  // The bin width is 1 / 2^k degrees (k >= 0) and 180 degrees a whole number of bins: the bin of
  // a float bearing b is then floor(b * bins_per_deg_) + half_bins_, exactly, in floats.
  bool bin_by_floor_ = false;
  float bins_per_deg_ = 1.0F;
  std::int32_t half_bins_ = 0;
  // The range limits as floats that compare with a float range exactly as the double limits do.
  float min_range_f_ = 0.0F;
  float max_range_f_ = 0.0F;
  float scan_max_range_f_ = 0.0F;  // max_range_f_, or the scan's own limit when smaller
  std::uint32_t point_count_ = 0;
  std::uint32_t walk_start_ = 0;  // index of the walk's first return
  std::uint32_t group_count_ = 0;
  std::uint32_t stack_size_ = 0;
  ObstacleList* out_ = nullptr;
  std::vector<float> trig_;  // cos, sin pairs from -180 deg in 1 / kTrigStepsPerDeg steps
  // Fixed-capacity arrays, sized once in the constructor (structure of arrays: each pass reads
  // only the fields it needs). The kept returns in walk direction (bearing ascending when the
  // walk is clockwise, descending otherwise); the walk, from walk_start_, runs on past the end
  // into copies of the first returns, so every group, the one across the seam included, is one
  // contiguous span: room for three scans.
  std::vector<float> x_m_;  // forward
  std::vector<float> y_m_;  // starboard
  std::vector<float> range_m_;
  std::vector<float> bearing_deg_;     // wrapped into (-180, 180]
  std::vector<std::int32_t> bin_;      // RangeProfile bin
  std::vector<std::uint32_t> breaks_;  // walk positions where a new group starts
  std::vector<Span> groups_;
  std::vector<Span> stack_;  // pending halves of (B)
};

}  // namespace coxswain::perception
