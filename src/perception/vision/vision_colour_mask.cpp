// SPDX-License-Identifier: Apache-2.0
#include "coxswain/perception/vision_colour_mask.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <utility>

namespace coxswain::perception {
namespace {

cv::Mat make_kernel(int size_px) {
  if (size_px <= 1) return {};
  return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size_px, size_px));
}

/// OpenCV's 8-bit BGR -> HSV (hue 0..179), rounded the same way.
void bgr_to_hsv(int b, int g, int r, int& h, int& s, int& v) {
  v = std::max({b, g, r});
  const int mn = std::min({b, g, r});
  const int diff = v - mn;
  s = v == 0 ? 0 : static_cast<int>(std::lround(255.0 * diff / v));
  if (diff == 0) {
    h = 0;
    return;
  }
  double hd = 0.0;
  if (v == r) {
    hd = 30.0 * (g - b) / diff;
  } else if (v == g) {
    hd = 60.0 + 30.0 * (b - r) / diff;
  } else {
    hd = 120.0 + 30.0 * (r - g) / diff;
  }
  h = static_cast<int>(std::lround(hd));
  if (h < 0) h += 180;
  if (h >= 180) h -= 180;
}

bool invert3(const std::array<double, 9>& m, std::array<double, 9>& inv) {
  const double det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
                     m[2] * (m[3] * m[7] - m[4] * m[6]);
  if (!(std::abs(det) > 1e-9)) return false;
  const double k = 1.0 / det;
  inv = {(m[4] * m[8] - m[5] * m[7]) * k, (m[2] * m[7] - m[1] * m[8]) * k,
         (m[1] * m[5] - m[2] * m[4]) * k, (m[5] * m[6] - m[3] * m[8]) * k,
         (m[0] * m[8] - m[2] * m[6]) * k, (m[2] * m[3] - m[0] * m[5]) * k,
         (m[3] * m[7] - m[4] * m[6]) * k, (m[1] * m[6] - m[0] * m[7]) * k,
         (m[0] * m[4] - m[1] * m[3]) * k};
  return true;
}

/// Running sums of BGR samples for a mean and covariance, in integers: exact, so the order of the
/// samples does not matter.
struct Moments3 {
  std::int64_t n = 0;
  std::array<std::int64_t, 3> sum{};
  std::array<std::int64_t, 9> sum2{};
  /// Fills the lower triangle from the upper.
  void symmetrise() {
    sum2[3] = sum2[1];
    sum2[6] = sum2[2];
    sum2[7] = sum2[5];
  }
};

/// Loops over the samples run in blocks of this many lanes: at -O2 the compiler vectorises only
/// loops that need no remainder, so the sample buffers are padded to a whole number of blocks
/// (padding samples are never flagged `inside`).
constexpr std::size_t kLanes = 16;

std::size_t padded(std::size_t n) { return (n + kLanes - 1) / kLanes * kLanes; }

/// Sums of the samples flagged in `inside` (the first `n`, padding included). Branch-free, per
/// lane, in blocks whose 32-bit sums cannot overflow (a product of two grey levels is below
/// 2^16), so the loop vectorises.
Moments3 moments_of(const ColourSamples& s, std::size_t n) {
  constexpr std::size_t kBlock = 1U << 14;  // samples per lane sum: kBlock * 65025 < 2^32
  constexpr std::size_t kSums = 10;
  Moments3 m;
  const std::size_t total = padded(n);
  for (std::size_t begin = 0; begin < total; begin += kBlock * kLanes) {
    const std::size_t end = std::min(total, begin + kBlock * kLanes);
    std::array<std::array<std::uint32_t, kLanes>, kSums> acc{};
    for (std::size_t i = begin; i < end; i += kLanes) {
      for (std::size_t k = 0; k < kLanes; ++k) {
        const std::uint32_t f = s.inside[i + k];
        const std::uint32_t b = s.b[i + k] * f;
        const std::uint32_t g = s.g[i + k] * f;
        const std::uint32_t r = s.r[i + k] * f;
        acc[0][k] += f;
        acc[1][k] += b;
        acc[2][k] += g;
        acc[3][k] += r;
        acc[4][k] += b * b;
        acc[5][k] += b * g;
        acc[6][k] += b * r;
        acc[7][k] += g * g;
        acc[8][k] += g * r;
        acc[9][k] += r * r;
      }
    }
    std::array<std::int64_t, kSums> t{};
    for (std::size_t j = 0; j < kSums; ++j) {
      for (const std::uint32_t v : acc[j]) t[j] += v;
    }
    m.n += t[0];
    m.sum[0] += t[1];
    m.sum[1] += t[2];
    m.sum[2] += t[3];
    m.sum2[0] += t[4];
    m.sum2[1] += t[5];
    m.sum2[2] += t[6];
    m.sum2[4] += t[7];
    m.sum2[5] += t[8];
    m.sum2[8] += t[9];
  }
  m.symmetrise();
  return m;
}

/// Flags in `s.inside` the first `n` samples within squared Mahalanobis distance `limit2` of
/// `model`; the padding after them is left unflagged. In single precision with the symmetric
/// form, in whole blocks, so the loop vectorises.
void mark_within(const ColourGaussian& model, double limit2, std::size_t n, ColourSamples& s) {
  const auto m0 = static_cast<float>(model.mean_bgr[0]);
  const auto m1 = static_cast<float>(model.mean_bgr[1]);
  const auto m2 = static_cast<float>(model.mean_bgr[2]);
  const std::array<double, 9>& a = model.inverse_covariance;
  const auto a00 = static_cast<float>(a[0]);
  const auto a11 = static_cast<float>(a[4]);
  const auto a22 = static_cast<float>(a[8]);
  const auto a01 = static_cast<float>(a[1] + a[3]);
  const auto a02 = static_cast<float>(a[2] + a[6]);
  const auto a12 = static_cast<float>(a[5] + a[7]);
  const auto limit = static_cast<float>(limit2);
  const std::uint8_t* b = s.b.data();
  const std::uint8_t* g = s.g.data();
  const std::uint8_t* r = s.r.data();
  std::uint8_t* out = s.inside.data();
  const std::size_t total = padded(n);
  for (std::size_t i = 0; i < total; i += kLanes) {
    for (std::size_t k = 0; k < kLanes; ++k) {
      const float d0 = static_cast<float>(b[i + k]) - m0;
      const float d1 = static_cast<float>(g[i + k]) - m1;
      const float d2 = static_cast<float>(r[i + k]) - m2;
      const float q = a00 * d0 * d0 + a11 * d1 * d1 + a22 * d2 * d2 + a01 * d0 * d1 +
                      a02 * d0 * d2 + a12 * d1 * d2;
      out[i + k] = q <= limit ? 1 : 0;
    }
  }
  std::fill(out + n, out + total, std::uint8_t{0});
}

/// Mean and covariance from `m`, each axis' spread clamped to [min_sigma, max_sigma].
bool to_gaussian(const Moments3& m, const BackgroundParams& p, ColourGaussian& g) {
  if (m.n < 8) return false;
  const auto n = static_cast<double>(m.n);
  std::array<double, 9> cov{};
  for (std::size_t i = 0; i < 3; ++i) g.mean_bgr[i] = static_cast<double>(m.sum[i]) / n;
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      cov[3 * i + j] = static_cast<double>(m.sum2[3 * i + j]) / n - g.mean_bgr[i] * g.mean_bgr[j];
    }
  }
  std::array<double, 3> scale{};
  for (std::size_t i = 0; i < 3; ++i) {
    const double sd = std::sqrt(std::max(0.0, cov[4 * i]));
    g.sigma_bgr[i] = std::clamp(sd, p.min_sigma, p.max_sigma);
    scale[i] = sd > 1e-6 ? g.sigma_bgr[i] / sd : 0.0;
  }
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      cov[3 * i + j] =
          i == j ? g.sigma_bgr[i] * g.sigma_bgr[i] : cov[3 * i + j] * scale[i] * scale[j];
    }
  }
  // A ridge keeps a perfectly correlated (grey-ramp) band invertible.
  for (std::size_t i = 0; i < 3; ++i) cov[4 * i] += 1.0;
  return invert3(cov, g.inverse_covariance);
}

/// ORs `labels` into `cols` element by element and returns the OR of all of `labels`. In blocks
/// of a fixed size: at -O2 the compiler vectorises only loops that need no remainder, and the
/// arguments are restrict-qualified so it knows they do not overlap.
std::uint16_t or_into(const std::uint16_t* __restrict labels, std::uint16_t* __restrict cols,
                      int width) {
  constexpr int kBlock = 16;
  std::array<std::uint16_t, kBlock> all{};
  int x = 0;
  for (; x + kBlock <= width; x += kBlock) {
    for (int k = 0; k < kBlock; ++k) {
      const auto i = static_cast<std::size_t>(k);
      all[i] = static_cast<std::uint16_t>(all[i] | labels[x + k]);
      cols[x + k] = static_cast<std::uint16_t>(cols[x + k] | labels[x + k]);
    }
  }
  std::uint16_t any = 0;
  for (; x < width; ++x) {
    any = static_cast<std::uint16_t>(any | labels[x]);
    cols[x] = static_cast<std::uint16_t>(cols[x] | labels[x]);
  }
  for (const std::uint16_t a : all) any = static_cast<std::uint16_t>(any | a);
  return any;
}

}  // namespace

double ColourGaussian::distance2(double b, double g, double r) const {
  const std::array<double, 3> d{b - mean_bgr[0], g - mean_bgr[1], r - mean_bgr[2]};
  double s = 0.0;
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) s += d[i] * inverse_covariance[3 * i + j] * d[j];
  }
  return s;
}

ColourGaussian fit_dominant_colour(const cv::Mat& bgr, int row_begin, int row_end,
                                   const BackgroundParams& p) {
  ColourSamples samples;
  return fit_dominant_colour(bgr, row_begin, row_end, p, samples);
}

ColourGaussian fit_dominant_colour(const cv::Mat& bgr, int row_begin, int row_end,
                                   const BackgroundParams& p, ColourSamples& samples) {
  ColourGaussian g;
  if (bgr.empty() || bgr.type() != CV_8UC3) return g;
  row_begin = std::clamp(row_begin, 0, bgr.rows);
  row_end = std::clamp(row_end, row_begin, bgr.rows);
  constexpr int kBuckets = 8;
  // The grid's pitch: the configured one, coarsened on a large frame until the strip's samples
  // fit the cap (the fit needs a few thousand, however many pixels the camera has).
  const auto grid_count = [&](int pitch) {
    const int across = std::max(0, (bgr.cols - pitch / 2 + pitch - 1) / pitch);
    const int down = std::max(0, (row_end - row_begin - pitch / 2 + pitch - 1) / pitch);
    return std::pair<int, int>{across, down};
  };
  int step = std::max(1, p.sample_step_px);
  const auto cap = static_cast<std::size_t>(std::max(1, p.max_samples));
  for (;;) {
    const auto [across, down] = grid_count(step);
    if (static_cast<std::size_t>(across) * static_cast<std::size_t>(down) <= cap) break;
    ++step;
  }
  // One pass gathers the samples and a coarse 8x8x8 histogram; the dominant colour is the fullest
  // bin and its neighbours.
  const auto [per_row, rows] = grid_count(step);
  const std::size_t capacity =
      padded(static_cast<std::size_t>(per_row) * static_cast<std::size_t>(rows));
  for (auto* v : {&samples.b, &samples.g, &samples.r, &samples.bucket, &samples.inside}) {
    if (v->size() < capacity) v->resize(capacity);
  }
  std::array<int, 512> hist{};
  std::size_t n = 0;
  for (int y = row_begin + step / 2; y < row_end; y += step) {
    const unsigned char* row = bgr.ptr<unsigned char>(y);
    for (int x = step / 2; x < bgr.cols; x += step, ++n) {
      const unsigned char* px = row + static_cast<std::ptrdiff_t>(3) * x;
      samples.b[n] = px[0];
      samples.g[n] = px[1];
      samples.r[n] = px[2];
      samples.bucket[n] = static_cast<std::uint8_t>(x * kBuckets / bgr.cols);
      ++hist[static_cast<std::size_t>(((px[0] >> 5) << 6) | ((px[1] >> 5) << 3) | (px[2] >> 5))];
    }
  }
  if (n == 0) return g;
  const auto peak = static_cast<int>(std::max_element(hist.begin(), hist.end()) - hist.begin());
  const int pb = peak >> 6;
  const int pg = (peak >> 3) & 7;
  const int pr = peak & 7;
  std::fill(samples.inside.begin() + static_cast<std::ptrdiff_t>(n),
            samples.inside.begin() + static_cast<std::ptrdiff_t>(padded(n)), std::uint8_t{0});
  for (std::size_t i = 0; i < n; ++i) {
    samples.inside[i] = std::abs((samples.b[i] >> 5) - pb) <= 1 &&
                                std::abs((samples.g[i] >> 5) - pg) <= 1 &&
                                std::abs((samples.r[i] >> 5) - pr) <= 1
                            ? 1
                            : 0;
  }
  ColourGaussian rough;
  if (!to_gaussian(moments_of(samples, n), p, rough)) return g;
  // Refit twice on the samples within 3 sigma of the last estimate: drops the neighbouring
  // bins' share of whatever else is in the strip (a buoy, a hull) and follows a gradient (sky).
  constexpr double kWithin2 = 9.0;
  Moments3 second;
  for (int pass = 0; pass < 2; ++pass) {
    mark_within(rough, kWithin2, n, samples);
    second = moments_of(samples, n);
    if (!to_gaussian(second, p, rough)) return ColourGaussian{};
  }
  g = rough;
  // Water and sky span the frame: the colour must hold a fifth of nearly every eighth of the
  // strip's width.
  mark_within(g, kWithin2, n, samples);
  std::array<int, kBuckets> members{};
  std::array<int, kBuckets> seen{};
  for (std::size_t i = 0; i < n; ++i) {
    ++seen[samples.bucket[i]];
    members[samples.bucket[i]] += samples.inside[i];
  }
  // One eighth may be lacking: a placard or a hull in front of the water.
  int lacking = 0;
  for (std::size_t k = 0; k < kBuckets; ++k) {
    lacking += seen[k] > 0 && members[k] * 5 < seen[k] ? 1 : 0;
  }
  const bool spans = lacking <= 1;
  g.share = static_cast<double>(second.n) / static_cast<double>(n);
  int h = 0;
  int s = 0;
  int v = 0;
  bgr_to_hsv(static_cast<int>(std::lround(g.mean_bgr[0])),
             static_cast<int>(std::lround(g.mean_bgr[1])),
             static_cast<int>(std::lround(g.mean_bgr[2])), h, s, v);
  g.valid = spans && g.share >= p.min_share && s <= p.max_saturation;
  return g;
}

std::uint16_t colour_bits(const VisionParams& params, int b, int g, int r) {
  int h = 0;
  int s = 0;
  int v = 0;
  bgr_to_hsv(b, g, r, h, s, v);
  std::uint16_t bits = 0;
  for (std::size_t c = 0; c < params.colour_count && c < 16; ++c) {
    if (params.colours[c].hsv.contains(h, s, v)) bits |= static_cast<std::uint16_t>(1U << c);
  }
  return bits;
}

ColourMasker::ColourMasker(const VisionParams& params)
    : background_params_(params.background),
      colour_count_(std::min<std::size_t>(params.colour_count, 16)),
      blur_kernel_px_(params.blur_kernel_px),
      open_kernel_(make_kernel(params.open_kernel_px)),
      close_kernel_(make_kernel(params.close_kernel_px)),
      table_(kTableSize),
      frame_table_(kTableSize) {
  pad_px_ = std::max(0, params.open_kernel_px) + std::max(0, params.close_kernel_px) + 2;
  // Each cell is judged at its centre value.
  constexpr int kCell = 256 / kLevels;
  for (int b = 0; b < kLevels; ++b) {
    for (int g = 0; g < kLevels; ++g) {
      for (int r = 0; r < kLevels; ++r) {
        table_[static_cast<std::size_t>((b << (2 * kLevelBits)) | (g << kLevelBits) | r)] =
            colour_bits(params, b * kCell + kCell / 2, g * kCell + kCell / 2,
                        r * kCell + kCell / 2);
      }
    }
  }
}

void ColourMasker::reject(const ColourGaussian& g) {
  constexpr int kCell = 256 / kLevels;
  const double r = background_params_.reject_sigma;
  const double r2 = r * r;
  std::array<int, 3> lo{};
  std::array<int, 3> hi{};
  for (std::size_t i = 0; i < 3; ++i) {
    lo[i] = std::clamp(static_cast<int>(std::floor((g.mean_bgr[i] - r * g.sigma_bgr[i]) / kCell)),
                       0, kLevels - 1);
    hi[i] = std::clamp(static_cast<int>(std::floor((g.mean_bgr[i] + r * g.sigma_bgr[i]) / kCell)),
                       0, kLevels - 1);
  }
  for (int b = lo[0]; b <= hi[0]; ++b) {
    for (int gg = lo[1]; gg <= hi[1]; ++gg) {
      for (int rr = lo[2]; rr <= hi[2]; ++rr) {
        // Each cell is judged at its centre grey level.
        const int cb = b * kCell + kCell / 2;
        const int cg = gg * kCell + kCell / 2;
        const int cr = rr * kCell + kCell / 2;
        if (g.distance2(cb, cg, cr) < r2) {
          frame_table_[static_cast<std::size_t>((b << (2 * kLevelBits)) | (gg << kLevelBits) |
                                                rr)] = 0;
        }
      }
    }
  }
}

bool ColourMasker::set_frame(const cv::Mat& bgr) {
  if (bgr.empty() || bgr.type() != CV_8UC3) return false;
  const cv::Mat* src = &bgr;
  if (blur_kernel_px_ >= 3) {
    cv::GaussianBlur(bgr, blurred_, cv::Size(blur_kernel_px_, blur_kernel_px_), 0.0);
    src = &blurred_;
  }
  const int width = bgr.cols;
  const int height = bgr.rows;
  std::copy(table_.begin(), table_.end(), frame_table_.begin());
  background_ = {};
  if (background_params_.enabled) {
    const BackgroundParams& p = background_params_;
    const int strips = std::clamp(p.strips, 1, BackgroundParams::kMaxStrips);
    for (int k = 0; k < strips; ++k) {
      background_[static_cast<std::size_t>(k)] =
          fit_dominant_colour(*src, k * height / strips, (k + 1) * height / strips, p, samples_);
    }
    // Water reaches the bottom of the frame and sky the top: a strip's model counts only when a
    // chain of like strips joins it to the bottom or top strip. A large marker in the middle of
    // the view (a placard up close) is cut off from both by what surrounds it.
    const auto like = [this](std::size_t a, std::size_t b) {
      const ColourGaussian& ga = background_[a];
      const ColourGaussian& gb = background_[b];
      // Within 6 sigma either way: a sky's gradient changes fast towards the horizon.
      return ga.valid && gb.valid &&
             std::min(ga.distance2(gb.mean_bgr[0], gb.mean_bgr[1], gb.mean_bgr[2]),
                      gb.distance2(ga.mean_bgr[0], ga.mean_bgr[1], ga.mean_bgr[2])) <= 36.0;
    };
    const auto n = static_cast<std::size_t>(strips);
    std::array<bool, BackgroundParams::kMaxStrips> from_top{};
    std::array<bool, BackgroundParams::kMaxStrips> from_bottom{};
    from_top[0] = background_[0].valid;
    for (std::size_t k = 1; k < n; ++k) from_top[k] = from_top[k - 1] && like(k - 1, k);
    from_bottom[n - 1] = background_[n - 1].valid;
    for (std::size_t k = n - 1; k-- > 0;) from_bottom[k] = from_bottom[k + 1] && like(k + 1, k);
    for (std::size_t k = 0; k < n; ++k) {
      ColourGaussian& g = background_[k];
      g.valid = g.valid && (from_top[k] || from_bottom[k]);
      if (g.valid) reject(g);
    }
  }

  labels_.create(height, width, CV_16UC1);
  row_bits_.assign(static_cast<std::size_t>(height), 0);
  col_bits_.assign(static_cast<std::size_t>(width), 0);
  const std::uint16_t* table = frame_table_.data();
  std::uint16_t* cols = col_bits_.data();
  constexpr int kShift = 8 - kLevelBits;
  for (int y = 0; y < height; ++y) {
    const unsigned char* px = src->ptr<unsigned char>(y);
    auto* out = labels_.ptr<std::uint16_t>(y);
    for (int x = 0; x < width; ++x, px += 3) {
      out[x] = table[((px[0] >> kShift) << (2 * kLevelBits)) | ((px[1] >> kShift) << kLevelBits) |
                     (px[2] >> kShift)];
    }
    // A second pass over the row's labels (in cache): the lookups above cannot vectorise, these
    // ORs can.
    row_bits_[static_cast<std::size_t>(y)] = or_into(out, cols, width);
  }
  return true;
}

ColourMasker::MaskView ColourMasker::mask(std::size_t colour_index) {
  MaskView view;
  if (colour_index >= colour_count_ || labels_.empty()) return view;
  const auto bit = static_cast<std::uint16_t>(1U << colour_index);
  const int height = labels_.rows;
  const int width = labels_.cols;
  int y0 = height;
  int y1 = -1;
  for (int y = 0; y < height; ++y) {
    if ((row_bits_[static_cast<std::size_t>(y)] & bit) != 0) {
      y0 = std::min(y0, y);
      y1 = y;
    }
  }
  if (y1 < 0) return view;
  int x0 = width;
  int x1 = -1;
  for (int x = 0; x < width; ++x) {
    if ((col_bits_[static_cast<std::size_t>(x)] & bit) != 0) {
      x0 = std::min(x0, x);
      x1 = x;
    }
  }
  const cv::Rect roi = cv::Rect(cv::Point(x0 - pad_px_, y0 - pad_px_),
                                cv::Point(x1 + 1 + pad_px_, y1 + 1 + pad_px_)) &
                       cv::Rect(0, 0, width, height);
  mask_.create(height, width, CV_8UC1);
  morph_.create(height, width, CV_8UC1);
  cv::Mat a = mask_(roi);
  cv::Mat b = morph_(roi);
  for (int y = 0; y < roi.height; ++y) {
    const auto* in = labels_.ptr<std::uint16_t>(roi.y + y) + roi.x;
    auto* out = a.ptr<unsigned char>(y);
    for (int x = 0; x < roi.width; ++x) out[x] = (in[x] & bit) != 0 ? 255 : 0;
  }
  // BORDER_ISOLATED: the filters see only the cut-out (zeros beyond it, as the padding is).
  constexpr int kBorder = cv::BORDER_CONSTANT | cv::BORDER_ISOLATED;
  if (!open_kernel_.empty()) {
    cv::morphologyEx(a, b, cv::MORPH_OPEN, open_kernel_, cv::Point(-1, -1), 1, kBorder);
    cv::swap(a, b);
  }
  if (!close_kernel_.empty()) {
    cv::morphologyEx(a, b, cv::MORPH_CLOSE, close_kernel_, cv::Point(-1, -1), 1, kBorder);
    cv::swap(a, b);
  }
  view.mask = a;
  view.offset = roi.tl();
  return view;
}

}  // namespace coxswain::perception
