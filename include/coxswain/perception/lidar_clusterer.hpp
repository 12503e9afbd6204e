// SPDX-License-Identifier: Apache-2.0
#pragma once
// Lidar clustering (docs/missions.md, after the source team's reduced obstacle_detector):
// (A) group neighbouring returns, (B) split each group at the point farthest from its chord,
// (C) classify long pieces as walls, (D) split walls into bounded pieces; each final piece becomes
// an ObstacleSegment in the body frame. Also fills the closest range per bearing bin.
#include <bit>
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
/// std::invalid_argument on invalid params); process() then never allocates and is deterministic.
/// Not thread-safe: one instance per thread.
class LidarClusterer {
 public:
  explicit LidarClusterer(const LidarClusterParams& params = {});

  /// Overwrites `out` and `profile`. Segments come in walk order; each has its true closest
  /// distance from the body origin (not its first return's).
  void process(const msg::LidarScan& scan, ObstacleList& out, RangeProfile& profile);

  [[nodiscard]] const LidarClusterParams& params() const { return params_; }
  [[nodiscard]] const LidarClusterStats& last_stats() const { return stats_; }

 private:
  struct Span {  // [begin, end) into the work arrays
    std::uint32_t begin;
    std::uint32_t end;
  };
  // What a beam's bearing alone decides. A scanner repeats its geometry scan after scan, so the
  // trigonometry is kept in a list sorted by bearing and looked up by walking it alongside the
  // next (sorted) scan; a bearing found bit for bit is reused, any other is computed as before,
  // so the values are exactly those of a fresh computation. The list is the union of the recent
  // scans' bearings (a beam without a return now and then keeps its entry); when few bearings
  // repeat (a scanner whose angles drift), only the last scan's are kept.
  struct Beam {
    float raw_deg = 0.0F;         // the bearing as the scan gives it (the key, bit for bit)
    float bearing_deg = 0.0F;     // wrapped into (-180, 180]
    std::uint32_t used_scan = 0;  // the last scan that looked it up
    std::uint16_t bin = 0;        // RangeProfile bin, kNoBin when the bearing is not finite
    double cos = 0.0;             // of the wrapped bearing
    double sin = 0.0;
  };
  static constexpr std::uint16_t kNoBin = 0xFFFF;
  static constexpr std::size_t kBeamCapacity = 2 * msg::LidarScan::kMaxPoints;

  // The cached entry of a bearing (scan order), else fresh_beam().
  [[nodiscard]] const Beam& beam(float bearing_deg) {
    while (beam_cursor_ < beam_count_ && beams_[beam_cursor_].raw_deg < bearing_deg) {
      ++beam_cursor_;
    }
    if (beam_cursor_ < beam_count_ && std::bit_cast<std::uint32_t>(beams_[beam_cursor_].raw_deg) ==
                                          std::bit_cast<std::uint32_t>(bearing_deg)) {
      ++beam_hits_;
      Beam& hit = beams_[beam_cursor_++];
      hit.used_scan = beam_scan_;
      return hit;
    }
    return fresh_beam(bearing_deg);
  }
  [[nodiscard]] const Beam& fresh_beam(float bearing_deg);
  void finish_beams();
  void filter_points(const msg::LidarScan& scan);
  void group_points();
  void split_group(Span group);
  void emit_piece(Span piece);
  void emit_wall(Span piece);
  void emit_segment(Span piece, ObstacleKind kind);
  void fill_profile(RangeProfile& profile) const;
  // Walk index -> index into the scan-order scratch arrays.
  [[nodiscard]] std::uint32_t walk_source(std::uint32_t walk_index) const;
  [[nodiscard]] bool breaks_scratch(std::uint32_t a, std::uint32_t b) const;

  LidarClusterParams params_;
  LidarClusterStats stats_;
  std::uint32_t profile_bins_ = 0;
  std::uint32_t point_count_ = 0;
  std::uint32_t walk_start_ = 0;  // scratch index of the walk's first return
  std::uint32_t group_count_ = 0;
  std::uint32_t stack_size_ = 0;
  ObstacleList* out_ = nullptr;
  // Fixed-capacity arrays, sized once in the constructor (structure of arrays: each pass reads
  // only the fields it needs).
  std::vector<Beam> beams_;        // from the previous scans, sorted by raw_deg
  std::vector<Beam> fresh_beams_;  // computed during this scan, in scan order
  std::vector<Beam> merged_beams_;
  std::uint32_t beam_count_ = 0;
  std::uint32_t fresh_count_ = 0;
  std::uint32_t beam_cursor_ = 0;  // walk position in beams_
  std::uint32_t beam_scan_ = 0;    // scans looked up so far
  std::uint32_t beam_hits_ = 0;
  std::uint32_t beam_keep_scans_ = 1;  // entries unused this many scans are dropped
  // Returns after the filters, in scan order (bearing ascending).
  std::vector<double> scratch_x_m_;
  std::vector<double> scratch_y_m_;
  std::vector<float> scratch_range_m_;
  std::vector<float> scratch_bearing_deg_;
  std::vector<std::uint16_t> scratch_bin_;
  // The same in walk order, rotated so a group wrapping across the seam is contiguous.
  std::vector<double> x_m_;  // forward
  std::vector<double> y_m_;  // starboard
  std::vector<float> range_m_;
  std::vector<std::uint16_t> bin_;
  std::vector<Span> groups_;
  std::vector<Span> stack_;  // pending halves of (B)
};

}  // namespace coxswain::perception
