// File: ros/src/ros1_chunk_decompression.h (internal to semgraph::ros)
//
// Decompression of a ROS 1 bag chunk's data to exactly its declared size: `none` (a copy), `bz2`
// (libbz2, one bzip2 stream) and `lz4` (ros_comm's roslz4 writes the standard LZ4 frame format:
// magic 0x184D2204, the header checksum byte of XXH32 over the descriptor, 4-byte block sizes
// with the high bit for stored blocks, an end mark and a content checksum; read by decompress.h's
// LZ4 frame reader, liblz4's LZ4F, shared with the MCAP reader).
//
// Invariants: `out` is resized to `declared_size` before anything is inflated, and the inflater
// never writes past it, so a decompression bomb costs at most `declared_size` bytes (which the
// caller has checked against its limit); producing more or fewer bytes than declared is an error.
// Costs: O(declared_size + input), one allocation (out), plus the inflater's own state.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace semgraph::ros::ros1 {

enum class ChunkCompression : std::uint8_t { kNone, kBz2, kLz4 };

// "none", "bz2", "lz4"; nullopt for any other name.
[[nodiscard]] std::optional<ChunkCompression> ChunkCompressionOf(std::string_view name) noexcept;

struct DecompressionError {
  bool unsupported = false;  // a format feature the library refuses (not corruption)
  std::string message;
};

// Inflates `in` into `out` (resized to declared_size). nullopt on success.
[[nodiscard]] std::optional<DecompressionError> DecompressChunk(ChunkCompression compression,
                                                                std::span<const std::uint8_t> in,
                                                                std::uint32_t declared_size,
                                                                std::vector<std::uint8_t>& out);

}  // namespace semgraph::ros::ros1
