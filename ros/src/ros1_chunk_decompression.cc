// ROS 1 chunk decompression (bz2, lz4 frames) bounded by the chunk's declared size.
#include "ros1_chunk_decompression.h"

#include <bzlib.h>

#include <array>
#include <climits>
#include <cstring>

#include "decompress.h"

namespace semgraph::ros::ros1 {
namespace {

std::string Declared(std::uint32_t declared_size) {
  return "its declared " + std::to_string(declared_size) + " bytes";
}

std::optional<DecompressionError> Bz2(std::span<const std::uint8_t> in, std::uint32_t declared_size,
                                      std::vector<std::uint8_t>& out) {
  if (in.size() > UINT_MAX) return DecompressionError{false, "bz2 input over 4 GiB"};
  bz_stream s{};
  if (BZ2_bzDecompressInit(&s, 0, 0) != BZ_OK) {
    return DecompressionError{false, "bz2: cannot initialize the decompressor"};
  }
  s.next_in = const_cast<char*>(reinterpret_cast<const char*>(in.data()));
  s.avail_in = static_cast<unsigned>(in.size());
  s.next_out = reinterpret_cast<char*>(out.data());
  s.avail_out = declared_size;
  int rc = BZ_OK;
  while (rc == BZ_OK && s.avail_out > 0) {
    const unsigned before_in = s.avail_in, before_out = s.avail_out;
    rc = BZ2_bzDecompress(&s);
    if (rc == BZ_OK && s.avail_in == before_in && s.avail_out == before_out) break;  // starved
  }
  // Output full without the end of the stream: one more byte tells a bomb from an exact fit.
  std::array<char, 1> extra{};
  if (rc == BZ_OK && s.avail_out == 0) {
    s.next_out = extra.data();
    s.avail_out = 1;
    rc = BZ2_bzDecompress(&s);
    if (s.avail_out == 0) {
      BZ2_bzDecompressEnd(&s);
      return DecompressionError{false,
                                "bz2 data decompresses to more than " + Declared(declared_size)};
    }
  }
  const std::uint64_t produced = (std::uint64_t{s.total_out_hi32} << 32) | s.total_out_lo32;
  BZ2_bzDecompressEnd(&s);
  if (rc != BZ_STREAM_END) {
    return DecompressionError{
        false, rc == BZ_OK ? "bz2 data ends before the end of its stream"
                           : "bz2 data is corrupt (libbz2 error " + std::to_string(rc) + ")"};
  }
  if (produced != declared_size) {
    return DecompressionError{false, "bz2 data decompresses to " + std::to_string(produced) +
                                         " bytes, not " + Declared(declared_size)};
  }
  return std::nullopt;
}

}  // namespace

std::optional<ChunkCompression> ChunkCompressionOf(std::string_view name) noexcept {
  if (name == "none") return ChunkCompression::kNone;
  if (name == "bz2") return ChunkCompression::kBz2;
  if (name == "lz4") return ChunkCompression::kLz4;
  return std::nullopt;
}

std::optional<DecompressionError> DecompressChunk(ChunkCompression compression,
                                                  std::span<const std::uint8_t> in,
                                                  std::uint32_t declared_size,
                                                  std::vector<std::uint8_t>& out) {
  out.resize(declared_size);
  switch (compression) {
    case ChunkCompression::kNone:
      if (in.size() != declared_size) {
        return DecompressionError{false, "uncompressed chunk holds " + std::to_string(in.size()) +
                                             " bytes, not " + Declared(declared_size)};
      }
      if (declared_size > 0) std::memcpy(out.data(), in.data(), declared_size);
      return std::nullopt;
    case ChunkCompression::kBz2:
      return Bz2(in, declared_size, out);
    case ChunkCompression::kLz4: {  // the LZ4 frame reader shared with MCAP chunks
      auto result = detail::DecompressLz4Frame(in, declared_size, out);
      if (!result.ok) return DecompressionError{false, std::move(result.message)};
      return std::nullopt;
    }
  }
  return DecompressionError{true, "unknown compression"};
}

}  // namespace semgraph::ros::ros1
