// SPDX-License-Identifier: Apache-2.0
#include "coxswain/core/geodesy.hpp"

#include <GeographicLib/LocalCartesian.hpp>

namespace coxswain::core {

struct LocalFrame::Impl {
  GeographicLib::LocalCartesian local;
};

LocalFrame::LocalFrame(GeoPoint origin)
    : origin_(origin),
      impl_(std::make_unique<Impl>(
          Impl{GeographicLib::LocalCartesian(origin.lat_deg, origin.lon_deg, origin.height_m)})) {}

LocalFrame::~LocalFrame() = default;
LocalFrame::LocalFrame(const LocalFrame& other)
    : origin_(other.origin_), impl_(std::make_unique<Impl>(*other.impl_)) {}
LocalFrame& LocalFrame::operator=(const LocalFrame& other) {
  if (this != &other) {
    origin_ = other.origin_;
    impl_ = std::make_unique<Impl>(*other.impl_);
  }
  return *this;
}
LocalFrame::LocalFrame(LocalFrame&&) noexcept = default;
LocalFrame& LocalFrame::operator=(LocalFrame&&) noexcept = default;

NavPoint LocalFrame::to_nav(const GeoPoint& p) const {
  double east_m = 0.0;
  double north_m = 0.0;
  double up_m = 0.0;
  impl_->local.Forward(p.lat_deg, p.lon_deg, p.height_m, east_m, north_m, up_m);
  return {north_m, east_m};
}

GeoPoint LocalFrame::to_geo(NavPoint p, double height_m) const {
  GeoPoint g;
  double h = 0.0;
  impl_->local.Reverse(p.east_m, p.north_m, height_m - origin_.height_m, g.lat_deg, g.lon_deg, h);
  g.height_m = h;
  return g;
}

}  // namespace coxswain::core
