// Positioned reads of a bag file (pread), with a read-ahead window for the many small reads of a
// scan. Internal to ros/.
//
// Invariants: every read is of bytes inside [0, size()); a short read (a file that shrank) is
// an error. Costs: Peek is O(n) and reads at least 1 MiB when the bytes are outside the window;
// Read is one pread of exactly n bytes.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace semgraph::ros::detail {

class BagFile {
 public:
  BagFile() = default;
  BagFile(const BagFile&) = delete;
  BagFile& operator=(const BagFile&) = delete;
  BagFile(BagFile&& other) noexcept;
  BagFile& operator=(BagFile&& other) noexcept;
  ~BagFile();

  /// Opens for reading; false with `error` set (the errno text) when it cannot.
  bool Open(const std::string& path, std::string& error);

  [[nodiscard]] std::uint64_t size() const { return size_; }

  /// The bytes [offset, offset + n), valid until the next Peek; n ≤ 1 MiB. False with `error`
  /// when they lie past the end or cannot be read.
  bool Peek(std::uint64_t offset, std::size_t n, std::span<const std::uint8_t>& out,
            std::string& error);

  /// Reads [offset, offset + n) into `out` (resized to n).
  bool Read(std::uint64_t offset, std::size_t n, std::vector<std::uint8_t>& out,
            std::string& error);

 private:
  bool ReadInto(std::uint64_t offset, std::size_t n, std::uint8_t* dst, std::string& error);

  int fd_ = -1;
  std::uint64_t size_ = 0;
  std::vector<std::uint8_t> window_;
  std::uint64_t window_offset_ = 0;
};

inline constexpr std::size_t kPeekMax = std::size_t{1} << 20;

}  // namespace semgraph::ros::detail
