// File: fuzz/support/op_reader.h
//
// OpReader: hands out the fuzzer's input bytes as small decisions (a byte, an index below n, a
// bool, a raw double, a short string). At the end of the input every call returns a default
// (0, false, 0.0, empty) instead of failing, so any byte string decodes to some op sequence and
// shrinking an input never makes it invalid.
//
// Invariant: position() <= size(); reads never go past the end.
// Cost: O(1) per call (Bytes: O(n)); no allocation; not thread-safe (one reader per input).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace semgraph::fuzz {

class OpReader {
 public:
  OpReader(const std::uint8_t* data, std::size_t size) noexcept : data_(data), size_(size) {}

  [[nodiscard]] bool empty() const noexcept { return pos_ >= size_; }
  [[nodiscard]] std::size_t remaining() const noexcept { return size_ - pos_; }
  [[nodiscard]] std::size_t position() const noexcept { return pos_; }
  [[nodiscard]] std::size_t size() const noexcept { return size_; }

  /// The next byte, or `fallback` at the end.
  std::uint8_t Byte(std::uint8_t fallback = 0) noexcept {
    return empty() ? fallback : data_[pos_++];
  }

  /// An index in [0, n) (n >= 1): one byte modulo n when n <= 256, two bytes otherwise; 0 at
  /// the end. Always consumes its byte(s), even for n == 1, so that an input's decoding does
  /// not shift when a choice happens to have one alternative.
  std::uint32_t Below(std::uint32_t n) noexcept {
    std::uint32_t x = Byte();
    if (n <= 1) return 0;
    if (n > 256) x = (x << 8) | Byte();
    return x % n;
  }

  /// True with probability about 1/2 (low bit of a byte); false at the end.
  bool Bool() noexcept { return (Byte() & 1u) != 0; }

  /// True with probability about 1/n.
  bool OneIn(std::uint32_t n) noexcept { return Below(n) == 0 && !empty(); }

  /// Eight raw bytes as a double (any bit pattern: NaN, Inf, denormals); 0.0 when fewer remain.
  double RawDouble() noexcept {
    if (remaining() < sizeof(double)) {
      pos_ = size_;
      return 0.0;
    }
    double d;
    std::memcpy(&d, data_ + pos_, sizeof(d));
    pos_ += sizeof(d);
    return d;
  }

  /// Up to n bytes (fewer at the end), as a view into the input.
  std::string_view Bytes(std::size_t n) noexcept {
    if (n > remaining()) n = remaining();
    std::string_view s(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    return s;
  }

  /// Everything not read yet.
  std::string_view Rest() noexcept { return Bytes(remaining()); }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

}  // namespace semgraph::fuzz
