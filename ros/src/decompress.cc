#include "decompress.h"

#include <lz4frame.h>
#include <zstd.h>

#include <memory>

namespace semgraph::ros::detail {
namespace {

DecompressResult Fail(std::string message) { return DecompressResult{false, std::move(message)}; }

std::string Bigger(std::uint64_t declared) {
  return "decompresses to more than its declared " + std::to_string(declared) + " bytes";
}

std::string Smaller(std::uint64_t got, std::uint64_t declared) {
  return "decompresses to " + std::to_string(got) + " bytes, not its declared " +
         std::to_string(declared);
}

}  // namespace

DecompressResult DecompressZstd(std::span<const std::uint8_t> in, std::uint64_t declared,
                                std::vector<std::uint8_t>& out) {
  out.resize(declared);
  std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> ctx(ZSTD_createDCtx(), &ZSTD_freeDCtx);
  if (!ctx) return Fail("cannot create a zstd context (out of memory)");
  // The streaming API bounds the output by the buffer: a bomb stops at `declared` bytes.
  ZSTD_outBuffer o{out.data(), out.size(), 0};
  ZSTD_inBuffer i{in.data(), in.size(), 0};
  std::size_t ret = 1;
  while (i.pos < i.size) {
    ret = ZSTD_decompressStream(ctx.get(), &o, &i);
    if (ZSTD_isError(ret) != 0U) return Fail(std::string("zstd: ") + ZSTD_getErrorName(ret));
    if (o.pos == o.size && ret != 0) {
      // Output full but the frame is not finished: one more byte of output would be a bomb.
      std::uint8_t probe = 0;
      ZSTD_outBuffer p{&probe, 1, 0};
      ret = ZSTD_decompressStream(ctx.get(), &p, &i);
      if (ZSTD_isError(ret) != 0U) return Fail(std::string("zstd: ") + ZSTD_getErrorName(ret));
      if (p.pos > 0) return Fail(Bigger(declared));
    }
    if (ret != 0 && i.pos == i.size) break;
  }
  if (ret != 0) return Fail("zstd: the data ends inside a frame (truncated)");
  if (o.pos != declared) return Fail(Smaller(o.pos, declared));
  return {};
}

DecompressResult DecompressLz4Frame(std::span<const std::uint8_t> in, std::uint64_t declared,
                                    std::vector<std::uint8_t>& out) {
  out.resize(declared);
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)) != 0U) {
    return Fail("cannot create an lz4 context (out of memory)");
  }
  std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(
      raw, &LZ4F_freeDecompressionContext);
  std::size_t in_pos = 0;
  std::size_t out_pos = 0;
  std::size_t ret = 1;
  std::uint8_t probe[64];
  while (in_pos < in.size()) {
    const bool full = out_pos == out.size();
    std::size_t dst_size = full ? sizeof(probe) : out.size() - out_pos;
    std::size_t src_size = in.size() - in_pos;
    ret = LZ4F_decompress(ctx.get(), full ? probe : out.data() + out_pos, &dst_size,
                          in.data() + in_pos, &src_size, nullptr);
    if (LZ4F_isError(ret) != 0U) return Fail(std::string("lz4: ") + LZ4F_getErrorName(ret));
    if (full && dst_size > 0) return Fail(Bigger(declared));
    in_pos += src_size;
    out_pos += full ? 0 : dst_size;
    if (src_size == 0 && dst_size == 0) break;  // no progress: the input ends inside a frame
  }
  if (ret != 0) return Fail("lz4: the data ends inside a frame (truncated)");
  if (out_pos != declared) return Fail(Smaller(out_pos, declared));
  return {};
}

}  // namespace semgraph::ros::detail
