// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/mag_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {

std::array<double, 2> MagCalibration::correct(double x_ut, double y_ut) const {
  const double x = x_ut - hard_iron_x_ut;
  const double y = y_ut - hard_iron_y_ut;
  return {soft_iron[0] * x + soft_iron[1] * y, soft_iron[2] * x + soft_iron[3] * y};
}

double MagCalibration::heading_deg(double x_ut, double y_ut) const {
  // The field points to magnetic north: seen from a board turned psi clockwise, it lies at
  // -psi (x forward, y starboard).
  const std::array<double, 2> c = correct(x_ut, y_ut);
  return std::atan2(-c[1], c[0]) * 180.0 / core::kPi;
}

std::optional<MagCalibration> fit_mag_calibration(std::span<const std::array<double, 2>> samples,
                                                  std::string& why) {
  if (samples.size() < 50) {
    why = "too few magnetometer samples (" + std::to_string(samples.size()) + ", need 50)";
    return std::nullopt;
  }
  // Conic A x^2 + B xy + C y^2 + D x + E y = 1, least squares (centred for conditioning).
  double mx = 0.0;
  double my = 0.0;
  for (const auto& s : samples) {
    mx += s[0];
    my += s[1];
  }
  mx /= static_cast<double>(samples.size());
  my /= static_cast<double>(samples.size());
  Eigen::Matrix<double, 5, 5> ata = Eigen::Matrix<double, 5, 5>::Zero();
  Eigen::Matrix<double, 5, 1> atb = Eigen::Matrix<double, 5, 1>::Zero();
  for (const auto& s : samples) {
    const double x = s[0] - mx;
    const double y = s[1] - my;
    const Eigen::Matrix<double, 5, 1> row(x * x, x * y, y * y, x, y);
    ata += row * row.transpose();
    atb += row;
  }
  const Eigen::Matrix<double, 5, 1> th = ata.ldlt().solve(atb);
  const double a = th(0);
  const double b = th(1);
  const double c = th(2);
  const double d = th(3);
  const double e = th(4);
  if (!(4.0 * a * c - b * b > 0.0)) {
    why = "the samples do not lie on an ellipse (not a full slow turn in place?)";
    return std::nullopt;
  }
  Eigen::Matrix2d m2;
  m2 << 2.0 * a, b, b, 2.0 * c;
  const Eigen::Vector2d centre = m2.inverse() * Eigen::Vector2d(-d, -e);
  const double g = a * centre(0) * centre(0) + b * centre(0) * centre(1) +
                   c * centre(1) * centre(1) + d * centre(0) + e * centre(1) - 1.0;
  Eigen::Matrix2d q;
  q << a, 0.5 * b, 0.5 * b, c;
  q /= -g;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(q);
  if (eig.eigenvalues().minCoeff() <= 0.0) {
    why = "the fitted conic is not an ellipse";
    return std::nullopt;
  }
  // x'^T Q x' = 1  ->  W = r Q^(1/2) maps the ellipse onto a circle of radius r, the geometric
  // mean of its semi-axes (the field's strength is kept).
  const Eigen::Matrix2d sqrt_q = eig.eigenvectors() * eig.eigenvalues().cwiseSqrt().asDiagonal() *
                                 eig.eigenvectors().transpose();
  const double r = 1.0 / std::sqrt(std::sqrt(q.determinant()));
  const Eigen::Matrix2d w = r * sqrt_q;

  MagCalibration cal;
  cal.hard_iron_x_ut = centre(0) + mx;
  cal.hard_iron_y_ut = centre(1) + my;
  cal.soft_iron = {w(0, 0), w(0, 1), w(1, 0), w(1, 1)};
  cal.radius_ut = r;
  cal.samples = samples.size();
  // Heading coverage: the largest gap between sorted corrected headings, from 360.
  std::vector<double> headings;
  headings.reserve(samples.size());
  double sq = 0.0;
  for (const auto& s : samples) {
    const std::array<double, 2> v = cal.correct(s[0], s[1]);
    const double dr = std::hypot(v[0], v[1]) - r;
    sq += dr * dr;
    headings.push_back(cal.heading_deg(s[0], s[1]));
  }
  cal.residual_rms_ut = std::sqrt(sq / static_cast<double>(samples.size()));
  std::sort(headings.begin(), headings.end());
  double gap = headings.front() + 360.0 - headings.back();
  for (std::size_t i = 1; i < headings.size(); ++i) {
    gap = std::max(gap, headings[i] - headings[i - 1]);
  }
  cal.coverage_deg = 360.0 - gap;
  if (cal.coverage_deg < 300.0) {
    why = "the turn covers only " + std::to_string(static_cast<int>(cal.coverage_deg)) +
          " deg of heading (need 300)";
    return std::nullopt;
  }
  return cal;
}

}  // namespace coxswain::guidance
