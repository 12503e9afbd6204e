// SPDX-License-Identifier: Apache-2.0
#pragma once
// Little-endian field writers and readers over fixed buffers: the building blocks of the MCAP
// records and of the recorder's binary message layouts (src/record/FORMAT.md). Neither allocates.
// Not thread-safe (one owner each).
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>

namespace coxswain::record {

/// Writes into a caller-owned span. Writing past the end sets `overflow()` and writes nothing
/// more, so a caller checks once at the end.
class ByteWriter {
 public:
  explicit ByteWriter(std::span<std::uint8_t> out) : out_(out) {}

  void u8(std::uint8_t v) { put(&v, 1); }
  void u16(std::uint16_t v) { put_le(v); }
  void u32(std::uint32_t v) { put_le(v); }
  void u64(std::uint64_t v) { put_le(v); }
  void i32(std::int32_t v) { put_le(static_cast<std::uint32_t>(v)); }
  void i64(std::int64_t v) { put_le(static_cast<std::uint64_t>(v)); }
  void f32(float v) { put_le(std::bit_cast<std::uint32_t>(v)); }
  void f64(double v) { put_le(std::bit_cast<std::uint64_t>(v)); }
  void boolean(bool v) { u8(v ? 1 : 0); }
  void bytes(std::span<const std::uint8_t> b) { put(b.data(), b.size()); }
  /// A string with a u16 byte-length prefix, cut at `max_len` bytes.
  void str16(std::string_view s, std::size_t max_len = 0xFFFF) {
    const std::size_t n = s.size() < max_len ? s.size() : max_len;
    u16(static_cast<std::uint16_t>(n));
    put(s.data(), n);
  }

  [[nodiscard]] std::size_t size() const { return pos_; }
  [[nodiscard]] bool overflow() const { return overflow_; }
  [[nodiscard]] std::span<const std::uint8_t> written() const { return out_.first(pos_); }

 private:
  template <class U>
  void put_le(U v) {
    std::uint8_t b[sizeof(U)];
    for (std::size_t i = 0; i < sizeof(U); ++i) b[i] = static_cast<std::uint8_t>(v >> (8 * i));
    put(b, sizeof(U));
  }
  void put(const void* p, std::size_t n) {
    if (overflow_ || n > out_.size() - pos_) {
      overflow_ = true;
      return;
    }
    if (n != 0) std::memcpy(out_.data() + pos_, p, n);
    pos_ += n;
  }

  std::span<std::uint8_t> out_;
  std::size_t pos_ = 0;
  bool overflow_ = false;
};

/// Reads from a span. Reading past the end returns zeros and sets `underrun()`.
class ByteReader {
 public:
  explicit ByteReader(std::span<const std::uint8_t> in) : in_(in) {}

  std::uint8_t u8() { return get_le<std::uint8_t>(); }
  std::uint16_t u16() { return get_le<std::uint16_t>(); }
  std::uint32_t u32() { return get_le<std::uint32_t>(); }
  std::uint64_t u64() { return get_le<std::uint64_t>(); }
  std::int32_t i32() { return static_cast<std::int32_t>(get_le<std::uint32_t>()); }
  std::int64_t i64() { return static_cast<std::int64_t>(get_le<std::uint64_t>()); }
  float f32() { return std::bit_cast<float>(get_le<std::uint32_t>()); }
  double f64() { return std::bit_cast<double>(get_le<std::uint64_t>()); }
  bool boolean() { return u8() != 0; }
  /// The next `n` bytes (empty and underrun when fewer remain).
  std::span<const std::uint8_t> bytes(std::size_t n) {
    if (underrun_ || n > in_.size() - pos_) {
      underrun_ = true;
      return {};
    }
    auto s = in_.subspan(pos_, n);
    pos_ += n;
    return s;
  }
  std::string_view str16() {
    const std::uint16_t n = u16();
    const auto b = bytes(n);
    return {reinterpret_cast<const char*>(b.data()), b.size()};
  }

  [[nodiscard]] std::size_t pos() const { return pos_; }
  [[nodiscard]] std::size_t remaining() const { return in_.size() - pos_; }
  [[nodiscard]] bool underrun() const { return underrun_; }

 private:
  template <class U>
  U get_le() {
    const auto b = bytes(sizeof(U));
    if (b.empty()) return U{0};
    U v = 0;
    for (std::size_t i = 0; i < sizeof(U); ++i)
      v = static_cast<U>(v | (static_cast<U>(b[i]) << (8 * i)));
    return v;
  }

  std::span<const std::uint8_t> in_;
  std::size_t pos_ = 0;
  bool underrun_ = false;
};

}  // namespace coxswain::record
