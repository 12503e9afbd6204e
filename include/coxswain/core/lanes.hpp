// SPDX-License-Identifier: Apache-2.0
#pragma once
// Short vectors for the hot loops: four floats or two doubles at a time (GCC/Clang vector
// extensions: SSE2 on x86-64, NEON on ARM, plain scalar code elsewhere). Each lane does the
// scalar arithmetic, operation for operation, so a lane's result is the scalar code's.
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace coxswain::core::lanes {

using V4f = float __attribute__((vector_size(16)));
using V4i = std::int32_t __attribute__((vector_size(16)));
using V2d = double __attribute__((vector_size(16)));
using V2i = std::int64_t __attribute__((vector_size(16)));
using V2f = float __attribute__((vector_size(8)));

inline V4f load4(const float* p) {
  V4f v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline V4i load4i(const std::int32_t* p) {
  V4i v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store4(float* p, V4f v) { std::memcpy(p, &v, sizeof v); }
inline V4f splat4(float v) { return V4f{v, v, v, v}; }
inline V4f abs4(V4f v) {
  constexpr std::int32_t kNoSign = std::numeric_limits<std::int32_t>::max();
  return std::bit_cast<V4f>(std::bit_cast<V4i>(v) & V4i{kNoSign, kNoSign, kNoSign, kNoSign});
}
inline V4f and4(V4i mask, V4f v) { return std::bit_cast<V4f>(mask & std::bit_cast<V4i>(v)); }
inline V4f max4(V4f a, V4f b) { return a > b ? a : b; }
// A comparison's lanes (all ones or all zeros each) as bits: lane i is bit i. One instruction
// on SSE2; reading the lanes one by one costs a shuffle each.
inline unsigned bits4(V4i m) {
#if defined(__SSE2__)
  return static_cast<unsigned>(_mm_movemask_ps(std::bit_cast<__m128>(m)));
#else
  return (m[0] != 0 ? 1U : 0U) | (m[1] != 0 ? 2U : 0U) | (m[2] != 0 ? 4U : 0U) |
         (m[3] != 0 ? 8U : 0U);
#endif
}
inline bool any4(V4i m) { return bits4(m) != 0; }
inline bool all4(V4i m) { return bits4(m) == 15U; }

inline V2d load2(const double* p) {
  V2d v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store2(double* p, V2d v) { std::memcpy(p, &v, sizeof v); }
inline V2d splat2(double v) { return V2d{v, v}; }
inline V2d abs2(V2d v) {
  constexpr std::int64_t kNoSign = std::numeric_limits<std::int64_t>::max();
  return std::bit_cast<V2d>(std::bit_cast<V2i>(v) & V2i{kNoSign, kNoSign});
}
// std::max(a, b) lane by lane: (a < b) ? b : a.
inline V2d max2(V2d a, V2d b) { return a < b ? b : a; }
inline unsigned bits2(V2i m) {
#if defined(__SSE2__)
  return static_cast<unsigned>(_mm_movemask_pd(std::bit_cast<__m128d>(m)));
#else
  return (m[0] != 0 ? 1U : 0U) | (m[1] != 0 ? 2U : 0U);
#endif
}
inline bool any2(V2i m) { return bits2(m) != 0; }
inline bool all2(V2i m) { return bits2(m) == 3U; }
// Two floats widened to doubles.
inline V2d widen2(const float* p) {
  V2f v;
  std::memcpy(&v, p, sizeof v);
  return __builtin_convertvector(v, V2d);
}

}  // namespace coxswain::core::lanes
