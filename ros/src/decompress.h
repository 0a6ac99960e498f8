// Chunk decompression for the bag readers (MCAP "zstd" and "lz4", ROS 1 "lz4"), into a buffer
// of the size the file declares. Internal to ros/.
//
// Invariants: never writes more than `declared` bytes, whatever the input claims (a
// decompression bomb is caught when its output would pass the declared size, before more is
// inflated); the output has exactly `declared` bytes or the call fails. Costs: O(output);
// allocates `out` (declared bytes) and the codec's context.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace semgraph::ros::detail {

/// What went wrong; empty on success.
struct DecompressResult {
  bool ok = true;
  std::string message;
};

/// zstd (one or more frames).
[[nodiscard]] DecompressResult DecompressZstd(std::span<const std::uint8_t> in,
                                              std::uint64_t declared,
                                              std::vector<std::uint8_t>& out);

/// LZ4 frame format (one or more frames; liblz4's LZ4F API).
[[nodiscard]] DecompressResult DecompressLz4Frame(std::span<const std::uint8_t> in,
                                                  std::uint64_t declared,
                                                  std::vector<std::uint8_t>& out);

}  // namespace semgraph::ros::detail
