// The MCAP reader against bags written by Foxglove's @mcap/core (tests/ros/fixtures): chunks
// uncompressed, zstd and lz4, no chunks, no index; every message in log-time order with its
// topic, type, bytes and decoded value. Then hostile files made from those bags: truncated,
// wrong magic, lengths past the end, CRC mismatches, a chunk claiming 4 GiB, decompression
// bombs, strings past the end; each is an error naming the file, the byte offset and the fault.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <map>
#include <optional>

#include "fixture_data.h"
#include "semgraph/ros/bag_reader.h"
#include "semgraph/ros/messages.h"

namespace semgraph::ros {
namespace {

using testing::Expected;
using testing::FirstRecord;
using testing::FixturesDir;
using testing::FromJson;
using testing::HaveFixtures;
using testing::LoadU64;
using testing::ReadBytes;
using testing::ResealDataCrc;
using testing::StoreU32;
using testing::StoreU64;
using testing::TempPath;
using testing::WriteBytes;
using Bytes = std::vector<std::uint8_t>;

#define SKIP_WITHOUT_FIXTURES()                      \
  if (!HaveFixtures())                               \
  GTEST_SKIP() << "no fixtures in " << FixturesDir() \
               << " (ctest ros.fixtures writes them; needs node)"

std::string Bag(const std::string& name) { return FixturesDir() + "/" + name; }

// The DataEnd record of an unpatched fixture bag.
testing::RecordAt DataEndOf(const std::string& name) {
  return FirstRecord(ReadBytes(Bag(name)), 0x0F);
}

// Decodes a record's CDR bytes as its kind and compares with the JSON value.
void CheckValue(const BagRecord& r, const YAML::Node& value) {
  const auto bytes = r.data;
  if (r.kind == MessageKind::kTfMessage) {
    TFMessage m;
    auto d = DecodeCdr(bytes, m);
    ASSERT_TRUE(d.has_value()) << Describe(d.error());
    EXPECT_EQ(m, FromJson<TFMessage>(value, false));
  } else if (r.kind == MessageKind::kJointState) {
    JointState m;
    auto d = DecodeCdr(bytes, m);
    ASSERT_TRUE(d.has_value()) << Describe(d.error());
    EXPECT_EQ(m, FromJson<JointState>(value, false));
  } else if (r.kind == MessageKind::kString) {
    String m;
    auto d = DecodeCdr(bytes, m);
    ASSERT_TRUE(d.has_value()) << Describe(d.error());
    EXPECT_EQ(m, FromJson<String>(value, false));
  }
}

void ReadWholeBag(const std::string& file) {
  SCOPED_TRACE(file);
  auto opened = OpenMcapBag(Bag(file));
  ASSERT_TRUE(opened.has_value()) << Describe(opened.error());
  BagReader& reader = **opened;
  EXPECT_EQ(reader.format(), BagFormat::kMcap);
  EXPECT_EQ(reader.path(), Bag(file));
  const YAML::Node& expected = Expected()["bag_messages"];
  BagRecord r;
  std::size_t i = 0;
  std::int64_t last = 0;
  for (;;) {
    auto next = reader.Next(r);
    ASSERT_TRUE(next.has_value()) << Describe(next.error());
    if (!*next) break;
    ASSERT_LT(i, expected.size());
    const YAML::Node& e = expected[i];
    ASSERT_EQ(r.log_time_ns, e["log_time"].as<std::int64_t>()) << "message " << i;
    EXPECT_GE(r.log_time_ns, last);
    last = r.log_time_ns;
    EXPECT_EQ(r.topic, e["topic"].as<std::string>());
    EXPECT_EQ(r.type_name, e["type"].as<std::string>());
    EXPECT_EQ(r.encoding, MessageEncodingOf(e["encoding"].as<std::string>()));
    EXPECT_EQ(r.kind, MessageKindOf(e["type"].as<std::string>()));
    EXPECT_EQ(r.data.size(), e["size"].as<std::size_t>());
    if (r.encoding == MessageEncoding::kCdr) CheckValue(r, e["value"]);
    ++i;
  }
  EXPECT_EQ(i, expected.size());
  // The end is sticky.
  auto again = reader.Next(r);
  ASSERT_TRUE(again.has_value());
  EXPECT_FALSE(*again);
  // Five channels; the json one is "other".
  ASSERT_EQ(reader.topics().size(), 5U);
  const auto chatter = std::find_if(reader.topics().begin(), reader.topics().end(),
                                    [](const BagTopic& t) { return t.name == "/chatter"; });
  ASSERT_NE(chatter, reader.topics().end());
  EXPECT_EQ(chatter->encoding, MessageEncoding::kOther);
  EXPECT_EQ(chatter->kind, MessageKind::kString);  // by type name; the encoding says "json"
}

TEST(RosMcapReader, ReadsUncompressedChunks) {
  SKIP_WITHOUT_FIXTURES();
  ReadWholeBag("tf_none.mcap");
}
TEST(RosMcapReader, ReadsZstdChunks) {
  SKIP_WITHOUT_FIXTURES();
  ReadWholeBag("tf_zstd.mcap");
}
TEST(RosMcapReader, ReadsLz4Chunks) {
  SKIP_WITHOUT_FIXTURES();
  ReadWholeBag("tf_lz4.mcap");
}
TEST(RosMcapReader, ReadsMessagesOutsideChunks) {
  SKIP_WITHOUT_FIXTURES();
  ReadWholeBag("tf_unchunked.mcap");
}
TEST(RosMcapReader, ReadsWithoutSummaryOrIndex) {
  SKIP_WITHOUT_FIXTURES();
  ReadWholeBag("tf_noindex.mcap");
}

TEST(RosMcapReader, TopicsAndCountsFromTheSummary) {
  SKIP_WITHOUT_FIXTURES();
  auto opened = OpenMcapBag(Bag("tf_zstd.mcap"));
  ASSERT_TRUE(opened.has_value());
  std::map<std::string, std::int64_t> expected;
  for (const auto& m : Expected()["bag_messages"]) ++expected[m["topic"].as<std::string>()];
  ASSERT_EQ((*opened)->topics().size(), expected.size());
  for (const BagTopic& t : (*opened)->topics()) {
    EXPECT_EQ(t.message_count, expected[t.name]) << t.name;
  }
  EXPECT_EQ(expected["/tf"], 1200);
}

// ---- Hostile files ----

struct Failure {
  BagErrorCode code;
  std::uint64_t offset;
  std::string message;
};

// Opens and reads a file to its end; the error of whichever step fails.
std::optional<Failure> ReadToEnd(const std::string& path, const BagReaderOptions& options = {}) {
  auto opened = OpenMcapBag(path, options);
  if (!opened) {
    EXPECT_EQ(opened.error().file, path);
    return Failure{opened.error().code, opened.error().offset, opened.error().message};
  }
  BagRecord r;
  for (;;) {
    auto next = (*opened)->Next(r);
    if (!next) {
      EXPECT_EQ(next.error().file, path);
      // Sticky: the same error again.
      auto again = (*opened)->Next(r);
      EXPECT_FALSE(again.has_value());
      if (!again.has_value()) {
        EXPECT_EQ(again.error().message, next.error().message);
      }
      return Failure{next.error().code, next.error().offset, next.error().message};
    }
    if (!*next) return std::nullopt;
  }
}

std::optional<Failure> ReadPatched(const std::string& name, const Bytes& bytes,
                                   const BagReaderOptions& options = {}) {
  const std::string path = TempPath(name);
  WriteBytes(path, bytes);
  return ReadToEnd(path, options);
}

bool Has(const std::string& message, const std::string& part) {
  return message.find(part) != std::string::npos;
}

TEST(RosMcapHostile, Truncated) {
  SKIP_WITHOUT_FIXTURES();
  const Bytes full = ReadBytes(Bag("tf_zstd.mcap"));
  for (const std::size_t keep :
       {std::size_t{0}, std::size_t{5}, std::size_t{40}, full.size() / 2, full.size() - 1}) {
    SCOPED_TRACE(keep);
    const Bytes cut(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(keep));
    auto f = ReadPatched("truncated.mcap", cut);
    ASSERT_TRUE(f.has_value());
    if (keep < 8) {
      EXPECT_EQ(f->code, BagErrorCode::kUnknownFormat) << f->message;
    } else {
      EXPECT_EQ(f->code, BagErrorCode::kTruncated) << f->message;
      EXPECT_LE(f->offset, keep);
    }
  }
}

TEST(RosMcapHostile, WrongMagic) {
  SKIP_WITHOUT_FIXTURES();
  Bytes b = ReadBytes(Bag("tf_none.mcap"));
  b[5] = '1';  // major version 1
  auto f = ReadPatched("magic.mcap", b);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->code, BagErrorCode::kUnknownFormat);
  EXPECT_EQ(f->offset, 0U);
  EXPECT_TRUE(Has(f->message, "wrong magic")) << f->message;
}

TEST(RosMcapHostile, RecordLengthPastTheEnd) {
  SKIP_WITHOUT_FIXTURES();
  Bytes b = ReadBytes(Bag("tf_unchunked.mcap"));
  const auto rec = FirstRecord(b, 0x05);  // the first message
  StoreU64(b, rec.offset + 1, std::uint64_t{1} << 40);
  ResealDataCrc(b, DataEndOf("tf_unchunked.mcap"));
  auto f = ReadPatched("length.mcap", b);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->code, BagErrorCode::kTruncated) << f->message;
  EXPECT_EQ(f->offset, rec.offset + 1);
  EXPECT_TRUE(Has(f->message, "runs past the end of the file")) << f->message;
  // Past the data section but not the file: malformed.
  b = ReadBytes(Bag("tf_unchunked.mcap"));
  StoreU64(b, rec.offset + 1, b.size() - rec.offset - 20);
  ResealDataCrc(b, DataEndOf("tf_unchunked.mcap"));
  f = ReadPatched("length2.mcap", b);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->code, BagErrorCode::kMalformed) << f->message;
  EXPECT_TRUE(Has(f->message, "past the end of the data section")) << f->message;
}

TEST(RosMcapHostile, StringPastTheEnd) {
  SKIP_WITHOUT_FIXTURES();
  Bytes b = ReadBytes(Bag("tf_unchunked.mcap"));
  const auto rec = FirstRecord(b, 0x04);  // a channel in the data section
  const std::size_t topic_len_at = rec.offset + 9 + 2 + 2;
  StoreU32(b, topic_len_at, 0xFFFFFF00U);
  ResealDataCrc(b, DataEndOf("tf_unchunked.mcap"));
  auto f = ReadPatched("string.mcap", b);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->code, BagErrorCode::kMalformed) << f->message;
  EXPECT_EQ(f->offset, topic_len_at + 4);
  EXPECT_TRUE(Has(f->message, "channel topic")) << f->message;
  EXPECT_TRUE(Has(f->message, "past the end of its record")) << f->message;
}

TEST(RosMcapHostile, CrcMismatches) {
  SKIP_WITHOUT_FIXTURES();
  const Bytes good = ReadBytes(Bag("tf_none.mcap"));
  const auto chunk = FirstRecord(good, 0x06);
  Bytes b = good;
  // The last byte of the first chunk's (uncompressed) records: the last byte of a message.
  b[chunk.offset + 9 + chunk.length - 1] ^= 0x01;
  // The data section CRC catches it at Open.
  auto f = ReadPatched("crc.mcap", b);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->code, BagErrorCode::kCrcMismatch);
  EXPECT_TRUE(Has(f->message, "data section CRC32")) << f->message;
  // With the data CRC re-sealed, the chunk's own CRC catches it when the chunk is read.
  ResealDataCrc(b, DataEndOf("tf_none.mcap"));
  f = ReadPatched("crc2.mcap", b);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->code, BagErrorCode::kCrcMismatch);
  EXPECT_EQ(f->offset, chunk.offset);
  EXPECT_TRUE(Has(f->message, "chunk CRC32")) << f->message;
  // verify_crc = false reads it (the flipped bit is inside a message's bytes).
  BagReaderOptions no_crc;
  no_crc.verify_crc = false;
  f = ReadPatched("crc3.mcap", b, no_crc);
  EXPECT_FALSE(f.has_value()) << f->message;
  // The summary CRC.
  b = good;
  const std::uint64_t summary_start = LoadU64(b, b.size() - 8 - 20 + 0);
  b[summary_start + 3] ^= 0x40;
  f = ReadPatched("crc4.mcap", b);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->code, BagErrorCode::kCrcMismatch);
  EXPECT_EQ(f->offset, summary_start);
}

TEST(RosMcapHostile, ChunkClaimingFourGiB) {
  SKIP_WITHOUT_FIXTURES();
  Bytes b = ReadBytes(Bag("tf_zstd.mcap"));
  const auto chunk = FirstRecord(b, 0x06);
  StoreU64(b, chunk.offset + 9 + 16, std::uint64_t{4} << 30);  // uncompressed_size
  ResealDataCrc(b, DataEndOf("tf_zstd.mcap"));
  auto f = ReadPatched("4gib.mcap", b);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->code, BagErrorCode::kOverLimit) << f->message;
  EXPECT_EQ(f->offset, chunk.offset);
  EXPECT_TRUE(Has(f->message, "4294967296")) << f->message;
  // A smaller limit refuses the real 16 KiB chunks too.
  BagReaderOptions small;
  small.max_chunk_bytes = 1000;
  f = ReadToEnd(Bag("tf_zstd.mcap"), small);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->code, BagErrorCode::kOverLimit);
}

// A chunk that inflates to more than it declares is stopped at the declared size.
TEST(RosMcapHostile, DecompressionBomb) {
  SKIP_WITHOUT_FIXTURES();
  for (const char* file : {"tf_zstd.mcap", "tf_lz4.mcap"}) {
    SCOPED_TRACE(file);
    Bytes b = ReadBytes(Bag(file));
    const auto chunk = FirstRecord(b, 0x06);
    const std::size_t size_at = chunk.offset + 9 + 16;
    const std::uint64_t real = LoadU64(b, size_at);
    StoreU64(b, size_at, real - 100);
    ResealDataCrc(b, DataEndOf(file));
    auto f = ReadPatched("bomb.mcap", b);
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(f->code, BagErrorCode::kDecompression) << f->message;
    EXPECT_EQ(f->offset, chunk.offset);
    EXPECT_TRUE(Has(f->message, "more than its declared " + std::to_string(real - 100)))
        << f->message;
    // Declaring more than the data holds fails too.
    StoreU64(b, size_at, real + 100);
    ResealDataCrc(b, DataEndOf(file));
    f = ReadPatched("short.mcap", b);
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(f->code, BagErrorCode::kDecompression) << f->message;
    EXPECT_TRUE(Has(f->message, "not its declared " + std::to_string(real + 100))) << f->message;
  }
}

TEST(RosMcapHostile, CorruptCompressedBytes) {
  SKIP_WITHOUT_FIXTURES();
  for (const char* file : {"tf_zstd.mcap", "tf_lz4.mcap"}) {
    SCOPED_TRACE(file);
    Bytes b = ReadBytes(Bag(file));
    const auto chunk = FirstRecord(b, 0x06);
    for (std::size_t i = 0; i < 64; ++i) b[chunk.offset + 80 + i] ^= 0x5A;
    ResealDataCrc(b, DataEndOf(file));
    auto f = ReadPatched("garbled.mcap", b);
    ASSERT_TRUE(f.has_value());
    EXPECT_TRUE(f->code == BagErrorCode::kDecompression || f->code == BagErrorCode::kCrcMismatch)
        << f->message;
  }
}

TEST(RosMcapHostile, SummaryIndexMustMatchTheChunks) {
  SKIP_WITHOUT_FIXTURES();
  Bytes b = ReadBytes(Bag("tf_none.mcap"));
  const auto index = FirstRecord(b, 0x08);
  StoreU64(b, index.offset + 9 + 16, 12345);  // chunk_start_offset of the first index entry
  // Re-seal the summary CRC (footer), computed from its start through summary_offset_start.
  const std::size_t footer = b.size() - 8 - 29;
  const std::uint64_t summary_start = LoadU64(b, footer + 9);
  const uLong crc =
      crc32(0L, b.data() + summary_start, static_cast<uInt>(footer + 9 + 16 - summary_start));
  StoreU32(b, footer + 9 + 16, static_cast<std::uint32_t>(crc));
  auto f = ReadPatched("index.mcap", b);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->code, BagErrorCode::kMalformed) << f->message;
  EXPECT_TRUE(Has(f->message, "chunk index disagrees")) << f->message;
}

TEST(RosMcapHostile, NotAFile) {
  auto f = OpenMcapBag("/nonexistent/semgraph/x.mcap");
  ASSERT_FALSE(f.has_value());
  EXPECT_EQ(f.error().code, BagErrorCode::kIo);
  EXPECT_TRUE(Has(Describe(f.error()), "/nonexistent/semgraph/x.mcap: byte 0: cannot open"))
      << Describe(f.error());
}

}  // namespace
}  // namespace semgraph::ros
