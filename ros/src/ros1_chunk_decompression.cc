// ROS 1 chunk decompression (bz2, lz4 frames) bounded by the chunk's declared size.
#include "ros1_chunk_decompression.h"

#include <bzlib.h>
#include <lz4frame.h>

#include <array>
#include <climits>
#include <cstring>

namespace semgraph::ros::ros1 {
namespace {

std::string Declared(std::uint32_t declared_size) {
  return "its declared size of " + std::to_string(declared_size) + " bytes";
}

std::optional<DecompressionError> Bz2(std::span<const std::uint8_t> in,
                                      std::uint32_t declared_size,
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
      return DecompressionError{false, "bz2 data decompresses to more than " +
                                           Declared(declared_size)};
    }
  }
  const std::uint64_t produced = (std::uint64_t{s.total_out_hi32} << 32) | s.total_out_lo32;
  BZ2_bzDecompressEnd(&s);
  if (rc != BZ_STREAM_END) {
    return DecompressionError{false, rc == BZ_OK ? "bz2 data ends before the end of its stream"
                                                 : "bz2 data is corrupt (libbz2 error " +
                                                       std::to_string(rc) + ")"};
  }
  if (produced != declared_size) {
    return DecompressionError{false, "bz2 data decompresses to " + std::to_string(produced) +
                                         " bytes, not " + Declared(declared_size)};
  }
  return std::nullopt;
}

std::optional<DecompressionError> Lz4(std::span<const std::uint8_t> in,
                                      std::uint32_t declared_size,
                                      std::vector<std::uint8_t>& out) {
  LZ4F_dctx* dctx = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&dctx, LZ4F_VERSION))) {
    return DecompressionError{false, "lz4: cannot create the decompression context"};
  }
  std::size_t in_pos = 0, out_pos = 0, hint = 1;
  std::optional<DecompressionError> error;
  std::array<std::uint8_t, 1> extra{};
  while (hint != 0 && !error) {
    const bool full = out_pos == declared_size;
    std::size_t dst_size = full ? extra.size() : declared_size - out_pos;
    std::size_t src_size = in.size() - in_pos;
    std::uint8_t* dst = full ? extra.data() : out.data() + out_pos;
    hint = LZ4F_decompress(dctx, dst, &dst_size, in.data() + in_pos, &src_size, nullptr);
    if (LZ4F_isError(hint)) {
      error = DecompressionError{false, std::string("lz4 frame is corrupt: ") +
                                            LZ4F_getErrorName(hint)};
    } else if (full && dst_size > 0) {
      error = DecompressionError{false, "lz4 data decompresses to more than " +
                                            Declared(declared_size)};
    } else if (hint != 0 && src_size == 0 && dst_size == 0) {
      error = DecompressionError{false, "lz4 frame ends before its end mark"};
    }
    in_pos += src_size;
    if (!full) out_pos += dst_size;
  }
  LZ4F_freeDecompressionContext(dctx);
  if (error) return error;
  if (out_pos != declared_size) {
    return DecompressionError{false, "lz4 data decompresses to " + std::to_string(out_pos) +
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
    case ChunkCompression::kBz2: return Bz2(in, declared_size, out);
    case ChunkCompression::kLz4: return Lz4(in, declared_size, out);
  }
  return DecompressionError{true, "unknown compression"};
}

}  // namespace semgraph::ros::ros1
