// SPDX-License-Identifier: Apache-2.0
#pragma once
// The "last notable event" text device sessions keep for DeviceHealth::detail: two parts joined
// into a fixed NUL-terminated buffer, cut to fit. No allocation.
#include <algorithm>
#include <array>
#include <cstddef>
#include <string_view>

namespace coxswain::drivers {

template <std::size_t N>
void set_detail_text(std::array<char, N>& out, std::string_view a, std::string_view b = {}) {
  static_assert(N > 0);
  // Copied byte by byte: an empty view may have a null data() (no memcpy from null).
  const std::size_t na = std::min(a.size(), N - 1);
  std::copy_n(a.begin(), na, out.begin());
  const std::size_t nb = std::min(b.size(), N - 1 - na);
  std::copy_n(b.begin(), nb, out.begin() + static_cast<std::ptrdiff_t>(na));
  out[na + nb] = '\0';
}

}  // namespace coxswain::drivers
