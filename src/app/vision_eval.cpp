// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/vision_eval.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace coxswain::app {
namespace {

constexpr std::size_t kMaxRows = 1'000'000;
constexpr std::size_t kMaxLine = 4096;
constexpr std::size_t kMaxNotes = 12;

constexpr std::array<msg::Colour, 8> kColourList{
    msg::Colour::kRed,  msg::Colour::kOrange, msg::Colour::kYellow, msg::Colour::kGreen,
    msg::Colour::kBlue, msg::Colour::kPurple, msg::Colour::kBlack,  msg::Colour::kWhite};
constexpr std::array<msg::Shape, 5> kShapeList{msg::Shape::kTriangle, msg::Shape::kRectangle,
                                               msg::Shape::kCross, msg::Shape::kCircle,
                                               msg::Shape::kBuoy};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, ',')) out.push_back(item);
  if (!s.empty() && s.back() == ',') out.emplace_back();
  return out;
}

std::optional<msg::Colour> parse_colour(const std::string& s) {
  for (const msg::Colour c : kColourList) {
    if (s == msg::colour_name(c)) return c;
  }
  return std::nullopt;
}

std::optional<msg::Shape> parse_shape(const std::string& s) {
  if (s == "square") return msg::Shape::kRectangle;
  for (const msg::Shape k : kShapeList) {
    if (s == msg::shape_name(k)) return k;
  }
  return std::nullopt;
}

std::optional<double> parse_number(const std::string& s) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used != s.size() || !std::isfinite(v) || std::abs(v) > 1e6) return std::nullopt;
    return v;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

/// The detection's centre lies on the object (its box grown by a quarter and 3 px each side).
bool on(const msg::Detection& d, const LabelledObject& o) {
  const double gx = 0.25 * o.box.width + 3.0;
  const double gy = 0.25 * o.box.height + 3.0;
  const auto x = static_cast<double>(d.center_x_px);
  const auto y = static_cast<double>(d.center_y_px);
  return x >= o.box.x - gx && x <= o.box.x + o.box.width + gx && y >= o.box.y - gy &&
         y <= o.box.y + o.box.height + gy;
}

/// A detection the labels account for: the object's own colour and shape, or the buoy reading
/// every blob of a buoy colour also gives (a marker's glyph), or a buoy read as a circle.
bool explains(const LabelledObject& o, const msg::Detection& d) {
  if (!on(d, o) || d.colour != o.colour) return false;
  if (o.partial) return true;
  return d.shape == o.shape || d.shape == msg::Shape::kBuoy ||
         (o.shape == msg::Shape::kBuoy && d.shape == msg::Shape::kCircle);
}

std::size_t ci(msg::Colour c) { return std::min<std::size_t>(static_cast<std::size_t>(c), 8); }
std::size_t si(msg::Shape s) { return std::min<std::size_t>(static_cast<std::size_t>(s), 5); }

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto k =
      static_cast<std::size_t>(std::clamp(p, 0.0, 1.0) * static_cast<double>(v.size() - 1));
  return v[k];
}

std::string pct(int num, int den) {
  if (den == 0) return "    -";
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << std::setw(5) << 100.0 * num / den;
  return s.str();
}

}  // namespace

std::optional<std::vector<LabelledFrame>> read_labels(std::istream& in, std::string& error) {
  std::vector<LabelledFrame> frames;
  std::map<std::string, std::size_t> index;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line_no > kMaxRows) {
      error = "more than 1000000 rows";
      return std::nullopt;
    }
    if (line.size() > kMaxLine) {
      error = "line " + std::to_string(line_no) + ": longer than 4096 bytes";
      return std::nullopt;
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    if (line_no == 1 && line.rfind("file,", 0) == 0) continue;  // header
    const std::vector<std::string> f = split(line);
    const std::string where = "line " + std::to_string(line_no) + ": ";
    if (f.size() < 3) {
      error = where + "expected file,colour,shape,x_px,y_px,width_px,height_px[,flags]";
      return std::nullopt;
    }
    if (f[0].empty() || f[0].find("..") != std::string::npos || f[0][0] == '/') {
      error = where + "the file must be a relative name inside the folder";
      return std::nullopt;
    }
    auto [it, inserted] = index.try_emplace(f[0], frames.size());
    if (inserted) frames.push_back({f[0], {}});
    LabelledFrame& frame = frames[it->second];
    if (f[1] == "none") continue;
    const std::optional<msg::Colour> colour = parse_colour(f[1]);
    const std::optional<msg::Shape> shape = parse_shape(f[2]);
    if (!colour || !shape) {
      error = where + "unknown colour or shape '" + f[1] + "," + f[2] + "'";
      return std::nullopt;
    }
    if (f.size() < 7) {
      error = where + "a labelled object needs x_px,y_px,width_px,height_px";
      return std::nullopt;
    }
    std::array<double, 4> b{};
    for (std::size_t k = 0; k < 4; ++k) {
      const std::optional<double> v = parse_number(f[3 + k]);
      if (!v || (k >= 2 && *v <= 0.0)) {
        error = where + "bad box value '" + f[3 + k] + "'";
        return std::nullopt;
      }
      b[k] = *v;
    }
    LabelledObject o;
    o.colour = *colour;
    o.shape = *shape;
    o.box = cv::Rect2d(b[0], b[1], b[2], b[3]);
    o.partial = f.size() > 7 && f[7] == "partial";
    frame.objects.push_back(o);
  }
  return frames;
}

void EvalTally::add(const LabelledFrame& frame, const msg::CameraDetections& detections) {
  ++frames;
  const std::size_t n = std::min<std::size_t>(detections.count, detections.detections.size());
  for (const LabelledObject& o : frame.objects) {
    if (o.partial) continue;
    ++labelled[ci(o.colour)][si(o.shape)];
    bool hit = false;
    bool any_shape = false;
    bool any_colour = false;
    for (std::size_t i = 0; i < n; ++i) {
      const msg::Detection& d = detections.detections[i];
      if (!on(d, o)) continue;
      if (d.colour == o.colour && d.shape == o.shape && !hit) {
        hit = true;
        centre_dx_px.push_back(static_cast<double>(d.center_x_px) - (o.box.x + 0.5 * o.box.width));
      }
      // Shapes reported on the object in its colour (a glyph's buoy reading left out).
      if (d.colour == o.colour && (d.shape != msg::Shape::kBuoy || o.shape == msg::Shape::kBuoy)) {
        ++shape_confusion[si(o.shape)][si(d.shape)];
        any_shape = true;
      }
      if (d.shape == o.shape) {
        ++colour_confusion[ci(o.colour)][ci(d.colour)];
        any_colour = true;
      }
    }
    if (!any_shape) ++shape_confusion[si(o.shape)][0];
    if (!any_colour) ++colour_confusion[ci(o.colour)][0];
    if (hit) {
      ++found[ci(o.colour)][si(o.shape)];
    } else if (miss_notes.size() < kMaxNotes) {
      std::ostringstream s;
      s << frame.file << ": " << msg::colour_name(o.colour) << "/" << msg::shape_name(o.shape)
        << " " << std::lround(o.box.width) << "x" << std::lround(o.box.height) << " px missed";
      miss_notes.push_back(s.str());
    }
  }
  int wrong = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const msg::Detection& d = detections.detections[i];
    ++reported_by_colour[ci(d.colour)];
    ++reported_by_shape[si(d.shape)];
    const bool ok = std::any_of(frame.objects.begin(), frame.objects.end(),
                                [&](const LabelledObject& o) { return explains(o, d); });
    if (ok) continue;
    ++wrong;
    ++wrong_by_colour[ci(d.colour)];
    ++wrong_by_shape[si(d.shape)];
    if (false_report_notes.size() < kMaxNotes) {
      std::ostringstream s;
      s << frame.file << ": " << msg::colour_name(d.colour) << "/" << msg::shape_name(d.shape)
        << " at " << std::lround(d.center_x_px) << "," << std::lround(d.center_y_px) << " ("
        << std::lround(d.width_px) << "x" << std::lround(d.height_px) << " px)";
      false_report_notes.push_back(s.str());
    }
  }
  false_reports += wrong;
  if (wrong > 0) ++frames_with_false_report;
}

double EvalTally::recall_colour(msg::Colour c) const {
  int l = 0;
  int f = 0;
  for (std::size_t s = 0; s < kShapes; ++s) {
    l += labelled[ci(c)][s];
    f += found[ci(c)][s];
  }
  return l == 0 ? -1.0 : static_cast<double>(f) / l;
}

double EvalTally::recall_shape(msg::Shape s) const {
  int l = 0;
  int f = 0;
  for (std::size_t c = 0; c < kColours; ++c) {
    l += labelled[c][si(s)];
    f += found[c][si(s)];
  }
  return l == 0 ? -1.0 : static_cast<double>(f) / l;
}

double EvalTally::min_recall() const {
  double r = 1.0;
  for (const msg::Colour c : kColourList) {
    if (const double v = recall_colour(c); v >= 0.0) r = std::min(r, v);
  }
  for (const msg::Shape s : kShapeList) {
    if (const double v = recall_shape(s); v >= 0.0) r = std::min(r, v);
  }
  return r;
}

double EvalTally::false_report_rate() const {
  return frames == 0 ? 0.0 : static_cast<double>(frames_with_false_report) / frames;
}

std::string EvalTally::report() const {
  std::ostringstream o;
  o << "frames " << frames << "; frames with a false report " << frames_with_false_report << " ("
    << pct(frames_with_false_report, frames) << " %), false reports " << false_reports << "\n";
  if (!frame_ms.empty()) {
    o << std::fixed << std::setprecision(2) << "time per frame: median "
      << percentile(frame_ms, 0.5) << " ms, p99 " << percentile(frame_ms, 0.99) << " ms, max "
      << percentile(frame_ms, 1.0) << " ms\n";
  }
  if (!centre_dx_px.empty()) {
    std::vector<double> abs_dx(centre_dx_px.size());
    std::transform(centre_dx_px.begin(), centre_dx_px.end(), abs_dx.begin(),
                   [](double v) { return std::abs(v); });
    double sum = 0.0;
    for (const double v : centre_dx_px) sum += v;
    o << std::fixed << std::setprecision(2)
      << "horizontal centre of found objects against the label's (the bearing's error): median "
      << percentile(abs_dx, 0.5) << " px, p95 " << percentile(abs_dx, 0.95) << " px, mean "
      << sum / static_cast<double>(centre_dx_px.size()) << " px (signed)\n";
  }
  o << "\nrecall % (found / labelled) by colour and shape\n"
    << "colour    triangle rectangle    cross   circle     buoy |  recall precision\n";
  for (const msg::Colour c : kColourList) {
    int l = 0;
    int f = 0;
    std::ostringstream row;
    for (const msg::Shape s : kShapeList) {
      const int cl = labelled[ci(c)][si(s)];
      const int cf = found[ci(c)][si(s)];
      l += cl;
      f += cf;
      row << "  " << pct(cf, cl) << "  ";
    }
    if (l == 0 && reported_by_colour[ci(c)] == 0) continue;
    o << std::left << std::setw(8) << msg::colour_name(c) << std::right << row.str() << "| "
      << pct(f, l) << "   "
      << pct(reported_by_colour[ci(c)] - wrong_by_colour[ci(c)], reported_by_colour[ci(c)]) << "  ("
      << f << "/" << l << ")\n";
  }
  o << "by shape ";
  for (const msg::Shape s : kShapeList) {
    int l = 0;
    int f = 0;
    for (std::size_t c = 0; c < kColours; ++c) {
      l += labelled[c][si(s)];
      f += found[c][si(s)];
    }
    o << " " << msg::shape_name(s) << " " << pct(f, l) << " (prec "
      << pct(reported_by_shape[si(s)] - wrong_by_shape[si(s)], reported_by_shape[si(s)]) << ")";
  }
  o << "\n\nshape confusion (rows: labelled; columns: reported on it in its colour)\n"
    << "             none triangle rectangle cross circle buoy\n";
  for (const msg::Shape s : kShapeList) {
    o << std::left << std::setw(10) << msg::shape_name(s) << std::right;
    for (std::size_t k = 0; k < kShapes; ++k) o << std::setw(7) << shape_confusion[si(s)][k];
    o << "\n";
  }
  o << "\ncolour confusion (rows: labelled; columns: reported on it in its shape)\n"
    << "          none    red  green   blue yellow orange purple  black  white\n";
  for (const msg::Colour c : kColourList) {
    int row_total = 0;
    for (std::size_t k = 0; k < kColours; ++k) row_total += colour_confusion[ci(c)][k];
    if (row_total == 0) continue;
    o << std::left << std::setw(8) << msg::colour_name(c) << std::right;
    for (std::size_t k = 0; k < kColours; ++k) o << std::setw(7) << colour_confusion[ci(c)][k];
    o << "\n";
  }
  if (!miss_notes.empty()) {
    o << "\nfirst misses:\n";
    for (const std::string& s : miss_notes) o << "  " << s << "\n";
  }
  if (!false_report_notes.empty()) {
    o << "\nfirst false reports:\n";
    for (const std::string& s : false_report_notes) o << "  " << s << "\n";
  }
  return o.str();
}

void add_calibration_samples(const cv::Mat& bgr, const LabelledFrame& frame,
                             CalibrationSamples& samples, double core_fraction) {
  if (bgr.empty() || bgr.type() != CV_8UC3) return;
  cv::Mat hsv;
  for (const LabelledObject& o : frame.objects) {
    if (o.partial) continue;
    const double w = o.box.width * core_fraction;
    const double h = o.box.height * core_fraction;
    const cv::Rect r =
        cv::Rect(cv::Point(static_cast<int>(std::lround(o.box.x + 0.5 * (o.box.width - w))),
                           static_cast<int>(std::lround(o.box.y + 0.5 * (o.box.height - h)))),
                 cv::Size(std::max(1, static_cast<int>(std::lround(w))),
                          std::max(1, static_cast<int>(std::lround(h))))) &
        cv::Rect(0, 0, bgr.cols, bgr.rows);
    if (r.area() <= 0) continue;
    cv::cvtColor(bgr(r), hsv, cv::COLOR_BGR2HSV);
    std::vector<cv::Vec3b>& out = samples.hsv[o.colour];
    for (int y = 0; y < hsv.rows; ++y) {
      for (int x = 0; x < hsv.cols; ++x) out.push_back(hsv.at<cv::Vec3b>(y, x));
    }
  }
}

perception::VisionParams fit_colour_boxes(const CalibrationSamples& samples,
                                          const perception::VisionParams& base) {
  perception::VisionParams p = base;
  constexpr int kHueMargin = 4;
  constexpr int kSatMargin = 25;
  constexpr int kValMargin = 30;
  for (const auto& [colour, px] : samples.hsv) {
    if (px.size() < 50) continue;
    const int idx = p.find_colour(colour);
    if (idx < 0) continue;
    perception::HsvRange& r = p.colours[static_cast<std::size_t>(idx)].hsv;
    std::vector<double> h;
    std::vector<double> s;
    std::vector<double> v;
    // Red straddles 0/180: measure its hue shifted by 90 so the range does not split.
    const int shift = colour == msg::Colour::kRed ? 90 : 0;
    for (const cv::Vec3b& q : px) {
      h.push_back((q[0] + shift) % 180);
      s.push_back(q[1]);
      v.push_back(q[2]);
    }
    if (colour == msg::Colour::kBlack) {  // any hue and saturation, dark
      r = {0, 179,
           0, 255,
           0, static_cast<std::uint8_t>(std::clamp(percentile(v, 0.99) + kValMargin, 20.0, 140.0))};
      continue;
    }
    const int h0 = static_cast<int>(percentile(h, 0.01)) - kHueMargin;
    const int h1 = static_cast<int>(percentile(h, 0.99)) + kHueMargin;
    r.h_min = static_cast<std::uint8_t>(((h0 - shift) % 180 + 180) % 180);
    r.h_max = static_cast<std::uint8_t>(((h1 - shift) % 180 + 180) % 180);
    r.s_min = static_cast<std::uint8_t>(std::clamp(percentile(s, 0.01) - kSatMargin, 30.0, 230.0));
    r.s_max = 255;
    r.v_min = static_cast<std::uint8_t>(std::clamp(percentile(v, 0.01) - kValMargin, 30.0, 230.0));
    r.v_max = 255;
  }
  return p;
}

}  // namespace coxswain::app
