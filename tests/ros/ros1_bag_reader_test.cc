// The ROS 1 bag v2.0 reader against bags written by Debian's python3-rosbag (uncompressed, bz2,
// lz4; messages serialized by genpy, written out of log-time order so chunks overlap), decoded
// with the ROS 1 codecs and compared with the values the writer was given; and against hostile
// bags built here record by record.
#include <bzlib.h>
#include <lz4frame.h>

#include <algorithm>
#include <cstring>

#include "bag_fixtures.h"

namespace semgraph::ros {
namespace {

using testing::ExpectBagMatches;
using testing::FixturePath;
using testing::ReadAll;
using Bytes = std::vector<std::uint8_t>;

const char* const kRos1Bags[] = {"ros1_none.bag", "ros1_bz2.bag", "ros1_lz4.bag"};

std::vector<testing::OwnedRecord> ReadBag(const std::string& path,
                                          const BagReaderOptions& options = {}) {
  auto reader = OpenRos1Bag(path, options);
  EXPECT_TRUE(reader) << (reader ? "" : Describe(reader.error()));
  if (!reader) return {};
  std::optional<BagError> error;
  auto records = ReadAll(**reader, &error);
  EXPECT_FALSE(error) << Describe(*error);
  return records;
}

// The error of opening and reading a bag to its end (nullopt when it reads cleanly).
std::optional<BagError> ErrorOf(const std::string& path, const BagReaderOptions& options = {}) {
  auto reader = OpenRos1Bag(path, options);
  if (!reader) return reader.error();
  std::optional<BagError> error;
  ReadAll(**reader, &error);
  if (error) {  // a finished reader repeats its error
    BagRecord r;
    auto again = (*reader)->Next(r);
    EXPECT_FALSE(again);
    if (!again) {
      EXPECT_EQ(again.error().message, error->message);
    }
  }
  return error;
}

TEST(Ros1BagReader, RosbagFixturesReadInLogTimeOrderWithTheWrittenValues) {
  ASSERT_TRUE(testing::Expected()["lz4"].as<bool>()) << "python3-roslz4 missing: no lz4 bag";
  for (const char* bag : kRos1Bags) {
    auto records = ReadBag(FixturePath(bag));
    ExpectBagMatches(records, bag, MessageEncoding::kRos1);
  }
}

TEST(Ros1BagReader, TopicsAndCountsComeFromTheIndex) {
  auto reader = OpenRos1Bag(FixturePath("ros1_bz2.bag"));
  ASSERT_TRUE(reader);
  EXPECT_EQ((*reader)->format(), BagFormat::kRos1);
  EXPECT_EQ((*reader)->path(), FixturePath("ros1_bz2.bag"));
  std::map<std::string, std::pair<std::string, std::int64_t>> topics;
  for (const BagTopic& t : (*reader)->topics()) {
    EXPECT_EQ(t.encoding, MessageEncoding::kRos1);
    EXPECT_EQ(t.kind, MessageKindOf(t.type_name));
    topics[t.name] = {t.type_name, t.message_count};
  }
  using P = std::pair<std::string, std::int64_t>;
  EXPECT_EQ(topics.size(), 5u);
  EXPECT_EQ(topics["/tf"], P("tf2_msgs/TFMessage", 8));
  EXPECT_EQ(topics["/tf_static"], P("tf2_msgs/TFMessage", 1));
  EXPECT_EQ(topics["/joint_states"], P("sensor_msgs/JointState", 8));
  EXPECT_EQ(topics["/robot_description"], P("std_msgs/String", 1));
  EXPECT_EQ(topics["/chatter"], P("std_msgs/String", 8));
}

TEST(Ros1BagReader, OpenBagDetectsRos1ByContent) {
  const std::string copy = testing::ScratchDir("detect") + "/no_extension";
  testing::WriteFile(copy, testing::ReadFile(FixturePath("ros1_lz4.bag")));
  auto format = DetectBagFormat(copy);
  ASSERT_TRUE(format);
  EXPECT_EQ(*format, BagFormat::kRos1);
  auto reader = OpenBag(copy);
  ASSERT_TRUE(reader) << Describe(reader.error());
  EXPECT_EQ((*reader)->format(), BagFormat::kRos1);
  ExpectBagMatches(ReadAll(**reader, nullptr), "ros1_lz4.bag", MessageEncoding::kRos1);
}

// The bag header's index_pos field (bytes of the file) and its value.
std::pair<std::size_t, std::uint64_t> IndexPos(const Bytes& bag) {
  const std::string_view file(reinterpret_cast<const char*>(bag.data()), bag.size());
  const std::size_t at = file.find("index_pos=") + std::strlen("index_pos=");
  std::uint64_t value = 0;
  std::memcpy(&value, bag.data() + at, 8);
  return {at, value};
}

TEST(Ros1BagReader, AnUnindexedBagIsScannedToTheSameRecords) {
  // As left by an interrupted `rosbag record`: index_pos 0 and no index section.
  for (const char* bag : kRos1Bags) {
    Bytes bytes = testing::ReadFile(FixturePath(bag));
    const auto [at, index_pos] = IndexPos(bytes);
    ASSERT_GT(index_pos, 4096u);
    bytes.resize(index_pos);
    std::fill_n(bytes.begin() + static_cast<std::ptrdiff_t>(at), 8, 0);
    const std::string path = testing::ScratchDir("unindexed") + "/" + bag;
    testing::WriteFile(path, bytes);
    ExpectBagMatches(ReadBag(path), bag, MessageEncoding::kRos1);
  }
}

TEST(Ros1BagReader, EveryTruncationIsAnErrorNamingFileAndOffset) {
  const Bytes bag = testing::ReadFile(FixturePath("ros1_bz2.bag"));
  const std::string path = testing::ScratchDir("truncated") + "/cut.bag";
  for (std::size_t n = 0; n < bag.size(); n += (n < 64 ? 1 : 41)) {
    SCOPED_TRACE("first " + std::to_string(n) + " bytes");
    testing::WriteFile(path, std::span(bag).first(n));
    const auto error = ErrorOf(path);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->code, n == 0 ? BagErrorCode::kUnknownFormat : BagErrorCode::kTruncated)
        << Describe(*error);
    EXPECT_EQ(error->file, path);
    EXPECT_LE(error->offset, n);
    EXPECT_NE(Describe(*error).find(path + ": byte " + std::to_string(error->offset)),
              std::string::npos);
  }
}

TEST(Ros1BagReader, AChunkLimitBelowTheChunksRefusesTheBag) {
  BagReaderOptions options;
  options.max_chunk_bytes = 256;  // rosbag wrote chunks of more than 600 bytes
  const auto error = ErrorOf(FixturePath("ros1_none.bag"), options);
  ASSERT_TRUE(error);
  EXPECT_EQ(error->code, BagErrorCode::kOverLimit) << Describe(*error);
}

// ---- Hand-built bags: one connection, one chunk of two messages, then the index ----

void PutU32(Bytes& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
Bytes U32(std::uint32_t v) {
  Bytes b;
  PutU32(b, v);
  return b;
}
Bytes U64(std::uint64_t v) {
  Bytes b = U32(static_cast<std::uint32_t>(v));
  PutU32(b, static_cast<std::uint32_t>(v >> 32));
  return b;
}
Bytes Time(std::uint32_t sec, std::uint32_t nsec) {
  Bytes b = U32(sec);
  PutU32(b, nsec);
  return b;
}
Bytes Text(std::string_view s) { return Bytes(s.begin(), s.end()); }
Bytes Cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}
Bytes Field(std::string_view name, const Bytes& value) {
  Bytes b = U32(static_cast<std::uint32_t>(name.size() + 1 + value.size()));
  b.insert(b.end(), name.begin(), name.end());
  b.push_back('=');
  b.insert(b.end(), value.begin(), value.end());
  return b;
}
Bytes Record(const Bytes& header, const Bytes& data) {
  return Cat({U32(static_cast<std::uint32_t>(header.size())), header,
              U32(static_cast<std::uint32_t>(data.size())), data});
}
Bytes Op(std::uint8_t op) { return Field("op", Bytes{op}); }
Bytes Ros1String(std::string_view s) {
  return Cat({U32(static_cast<std::uint32_t>(s.size())), Text(s)});
}

struct HandBag {
  std::string compression = "none";
  std::optional<std::uint32_t> declared_size;  // the chunk's `size` (default: the true size)
  std::optional<Bytes> chunk_data;             // the chunk's data (default: compressed records)
  std::uint32_t message_conn = 0;
  bool indexed = true;
  bool index_connection = true;     // the index section's connection record
  std::uint32_t info_end_nsec = 5;  // the chunk info's end_time (10 s + this)
  std::uint32_t info_count = 2;     // the chunk info's message count for connection 0
  std::uint32_t chunks = 1;         // copies of the chunk
};

Bytes ConnectionRecord() {
  const Bytes data = Cat({Field("topic", Text("/chatter")), Field("type", Text("std_msgs/String")),
                          Field("md5sum", Text("992ce8a1687cec8c8bd883ec73ca41d1")),
                          Field("message_definition", Text("string data\n"))});
  return Record(Cat({Op(0x07), Field("conn", U32(0)), Field("topic", Text("/chatter"))}), data);
}

Bytes Bz2(const Bytes& in) {
  Bytes out(in.size() + in.size() / 100 + 600);
  auto n = static_cast<unsigned>(out.size());
  EXPECT_EQ(BZ2_bzBuffToBuffCompress(reinterpret_cast<char*>(out.data()), &n,
                                     const_cast<char*>(reinterpret_cast<const char*>(in.data())),
                                     static_cast<unsigned>(in.size()), 9, 0, 0),
            BZ_OK);
  out.resize(n);
  return out;
}

// An LZ4 frame as roslz4 writes it: independent blocks, a content checksum.
Bytes Lz4(const Bytes& in) {
  LZ4F_preferences_t prefs{};
  prefs.frameInfo.blockMode = LZ4F_blockIndependent;
  prefs.frameInfo.contentChecksumFlag = LZ4F_contentChecksumEnabled;
  Bytes out(LZ4F_compressFrameBound(in.size(), &prefs));
  const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), &prefs);
  EXPECT_FALSE(LZ4F_isError(n));
  out.resize(n);
  return out;
}

Bytes Compress(const std::string& compression, const Bytes& in) {
  if (compression == "bz2") return Bz2(in);
  if (compression == "lz4") return Lz4(in);
  return in;
}

// The records of the chunk: the connection, "hi" at 10 s + 5 ns, then "yo" at 10 s + 1 ns.
Bytes ChunkRecords(std::uint32_t message_conn) {
  auto message = [&](std::uint32_t nsec, std::string_view text) {
    return Record(Cat({Op(0x02), Field("conn", U32(message_conn)), Field("time", Time(10, nsec))}),
                  Ros1String(text));
  };
  return Cat({ConnectionRecord(), message(5, "hi"), message(1, "yo")});
}

Bytes BagHeader(std::uint64_t index_pos, std::uint32_t chunk_count = 1) {
  return Record(Cat({Op(0x03), Field("index_pos", U64(index_pos)), Field("conn_count", U32(1)),
                     Field("chunk_count", U32(chunk_count))}),
                Bytes(64, ' '));
}
Bytes ChunkHeader(const std::string& compression, std::uint32_t size) {
  return Cat({Op(0x05), Field("compression", Text(compression)), Field("size", U32(size))});
}
// Where the chunk record starts, and its data (the header's size does not depend on values).
std::size_t ChunkPos() { return 13 + BagHeader(0).size(); }
std::size_t ChunkDataPos(const std::string& compression) {
  return ChunkPos() + 4 + ChunkHeader(compression, 0).size() + 4;
}

// `spec.chunks` identical chunks (all overlapping in time), each followed by its index data.
Bytes Build(const HandBag& spec) {
  const Bytes records = ChunkRecords(spec.message_conn);
  const Bytes chunk_data = spec.chunk_data.value_or(Compress(spec.compression, records));
  const std::uint32_t size =
      spec.declared_size.value_or(static_cast<std::uint32_t>(records.size()));
  const Bytes chunk = Record(ChunkHeader(spec.compression, size), chunk_data);
  const Bytes index_data =
      Record(Cat({Op(0x04), Field("ver", U32(1)), Field("conn", U32(0)), Field("count", U32(2))}),
             Cat({Time(10, 5), U32(0), Time(10, 1), U32(0)}));
  const std::uint64_t index_pos = ChunkPos() + spec.chunks * (chunk.size() + index_data.size());
  Bytes bag = Cat({Text("#ROSBAG V2.0\n"), BagHeader(spec.indexed ? index_pos : 0, spec.chunks)});
  for (std::uint32_t i = 0; i < spec.chunks; ++i) bag = Cat({bag, chunk, index_data});
  if (!spec.indexed) return bag;
  if (spec.index_connection) bag = Cat({bag, ConnectionRecord()});
  for (std::uint32_t i = 0; i < spec.chunks; ++i) {
    const std::uint64_t chunk_pos = ChunkPos() + i * (chunk.size() + index_data.size());
    bag = Cat(
        {bag, Record(Cat({Op(0x06), Field("ver", U32(1)), Field("chunk_pos", U64(chunk_pos)),
                          Field("start_time", Time(10, 1)),
                          Field("end_time", Time(10, spec.info_end_nsec)), Field("count", U32(1))}),
                     Cat({U32(0), U32(spec.info_count)}))});
  }
  return bag;
}

std::string WriteBag(const std::string& name, const Bytes& bytes) {
  const std::string path = testing::ScratchDir("hand") + "/" + name;
  testing::WriteFile(path, bytes);
  return path;
}

TEST(Ros1BagReader, HandBuiltBagsReadInTimeOrderWithEveryCompression) {
  for (const bool indexed : {true, false}) {
    for (const char* compression : {"none", "bz2", "lz4"}) {
      SCOPED_TRACE(std::string(compression) + (indexed ? " indexed" : " unindexed"));
      HandBag spec;
      spec.compression = compression;
      spec.indexed = indexed;
      const auto records = ReadBag(WriteBag("ok.bag", Build(spec)));
      ASSERT_EQ(records.size(), 2u);
      EXPECT_EQ(records[0].log_time_ns, 10'000'000'001);
      EXPECT_EQ(records[0].data, Ros1String("yo"));
      EXPECT_EQ(records[1].log_time_ns, 10'000'000'005);
      EXPECT_EQ(records[1].data, Ros1String("hi"));
      EXPECT_EQ(records[0].topic, "/chatter");
      EXPECT_EQ(records[0].type_name, "std_msgs/String");
      EXPECT_EQ(records[0].kind, MessageKind::kString);
    }
  }
}

void ExpectError(const Bytes& bag, BagErrorCode code, std::uint64_t offset, std::string_view says) {
  const std::string path = WriteBag("hostile.bag", bag);
  const auto error = ErrorOf(path);
  ASSERT_TRUE(error) << "read without an error";
  EXPECT_EQ(error->code, code) << Describe(*error);
  EXPECT_EQ(error->offset, offset) << Describe(*error);
  EXPECT_EQ(error->file, path);
  EXPECT_NE(error->message.find(says), std::string::npos) << Describe(*error);
}

TEST(Ros1BagReader, WrongMagicIsRefused) {
  ExpectError(Text("#ROSBAG V1.2\nrest"), BagErrorCode::kUnsupported, 0, "version other");
  ExpectError(Text("hello, world, not a bag"), BagErrorCode::kUnknownFormat, 0, "no '#ROSBAG");
  ExpectError(Text("#ROSBAG V2"), BagErrorCode::kTruncated, 0, "inside the magic");
}

TEST(Ros1BagReader, LengthsPastTheEndAreRefused) {
  // A record header length past the end of the file.
  ExpectError(Cat({Text("#ROSBAG V2.0\n"), U32(0x7fffffff), Bytes(20, 0)}),
              BagErrorCode::kTruncated, 13, "record header length 2147483647 past the end");
  // A header field length past the end of its header.
  const Bytes field = Cat({U32(500), Text("op="), Bytes{0x03}});
  ExpectError(
      Cat({Text("#ROSBAG V2.0\n"), U32(static_cast<std::uint32_t>(field.size())), field, U32(0)}),
      BagErrorCode::kMalformed, 17, "header field length 500 past the end");
  // A record data length past the end of the file (the chunk's, in an unindexed bag).
  HandBag spec;
  spec.indexed = false;
  Bytes bag = Build(spec);
  const std::size_t data_len_at = ChunkDataPos("none") - 4;
  const Bytes huge = U32(1u << 30);
  std::copy(huge.begin(), huge.end(), bag.begin() + static_cast<std::ptrdiff_t>(data_len_at));
  ExpectError(bag, BagErrorCode::kTruncated, data_len_at, "record data length 1073741824 past");
}

TEST(Ros1BagReader, AChunkClaimingFourGibibytesIsOverTheLimit) {
  for (const bool indexed : {true, false}) {
    HandBag spec;
    spec.indexed = indexed;
    spec.declared_size = 0xffffffffu;
    ExpectError(Build(spec), BagErrorCode::kOverLimit, ChunkPos(),
                "chunk declares 4294967295 uncompressed bytes, over the limit");
  }
}

TEST(Ros1BagReader, DecompressionBombsAndSizeMismatchesAreRefused) {
  const Bytes zeros(16u << 20, 0);  // 16 MiB of zeros: a few kB compressed
  for (const char* compression : {"bz2", "lz4"}) {
    SCOPED_TRACE(compression);
    HandBag bomb;
    bomb.compression = compression;
    bomb.declared_size = 4096;
    bomb.chunk_data = Compress(compression, zeros);
    ExpectError(Build(bomb), BagErrorCode::kDecompression, ChunkPos(),
                "decompresses to more than its declared 4096 bytes");
    HandBag short_data;
    short_data.compression = compression;
    short_data.declared_size = static_cast<std::uint32_t>(ChunkRecords(0).size() + 10);
    ExpectError(
        Build(short_data), BagErrorCode::kDecompression, ChunkPos(),
        "decompresses to " + std::to_string(ChunkRecords(0).size()) + " bytes, not its declared");
  }
  HandBag none;
  none.declared_size = 7;
  ExpectError(Build(none), BagErrorCode::kDecompression, ChunkPos(), "holds");
}

TEST(Ros1BagReader, CorruptCompressedDataIsRefused) {
  for (const char* compression : {"bz2", "lz4"}) {
    SCOPED_TRACE(compression);
    HandBag spec;
    spec.compression = compression;
    Bytes data = Compress(compression, ChunkRecords(0));
    data[data.size() / 2] ^= 0x5a;
    spec.chunk_data = data;
    ExpectError(Build(spec), BagErrorCode::kDecompression, ChunkPos(), compression);
  }
}

TEST(Ros1BagReader, AMessageOnAnUndefinedConnectionIsRefused) {
  HandBag spec;
  spec.message_conn = 7;
  // In an uncompressed chunk the offset is the message record's own byte in the file.
  const std::size_t chunk_data = ChunkDataPos("none");
  ExpectError(Build(spec), BagErrorCode::kMalformed, chunk_data + ConnectionRecord().size(),
              "refers to connection 7, which no connection record defines");
  HandBag no_index_connection;  // the chunk info names connection 0, which the index lacks
  no_index_connection.index_connection = false;
  const Bytes bag = Build(no_index_connection);
  const auto error = ErrorOf(WriteBag("noconn.bag", bag));
  ASSERT_TRUE(error);
  EXPECT_EQ(error->code, BagErrorCode::kMalformed);
  EXPECT_NE(error->message.find("connection 0, which no connection record defines"),
            std::string::npos)
      << Describe(*error);
}

TEST(Ros1BagReader, AChunkThatDisagreesWithItsChunkInfoIsRefused) {
  // The merge relies on the chunk infos' time ranges: a message outside them is an error.
  HandBag late;
  late.info_end_nsec = 4;  // the "hi" message is at 10 s + 5 ns
  ExpectError(Build(late), BagErrorCode::kMalformed,
              ChunkDataPos("none") + ConnectionRecord().size(),
              "message time outside its chunk info's [start_time, end_time]");
  HandBag count;
  count.info_count = 3;
  ExpectError(Build(count), BagErrorCode::kMalformed, ChunkPos(),
              "the chunk holds 2 messages; its chunk info says 3");
}

TEST(Ros1BagReader, OverlappingChunksAreMergedWithinTheMemoryBound) {
  // Five chunks covering the same time range: all are held at once. With a limit of one chunk,
  // four fit (4 x max_chunk_bytes) and the fifth is refused; with more room the records merge,
  // equal log times in file (chunk) order.
  HandBag spec;
  spec.chunks = 5;
  const std::string path = WriteBag("overlap.bag", Build(spec));
  const auto records = ReadBag(path);
  ASSERT_EQ(records.size(), 10u);
  for (std::size_t i = 0; i < 10; ++i) {
    EXPECT_EQ(records[i].log_time_ns, i < 5 ? 10'000'000'001 : 10'000'000'005) << i;
    EXPECT_EQ(records[i].data, Ros1String(i < 5 ? "yo" : "hi")) << i;
  }
  BagReaderOptions tight;
  tight.max_chunk_bytes = ChunkRecords(0).size();
  const auto error = ErrorOf(path, tight);
  ASSERT_TRUE(error);
  EXPECT_EQ(error->code, BagErrorCode::kOverLimit) << Describe(*error);
  EXPECT_NE(error->message.find("overlapping it in time"), std::string::npos) << Describe(*error);
  spec.chunks = 4;
  EXPECT_EQ(ReadBag(WriteBag("overlap4.bag", Build(spec)), tight).size(), 8u);
}

TEST(Ros1BagReader, EveryFlippedByteReadsOrFailsCleanly) {
  // Each single-byte corruption of a small bag either reads (a changed payload byte) or is an
  // error naming the file; never a crash (the sanitizer builds run this too).
  for (const char* compression : {"none", "bz2", "lz4"}) {
    HandBag spec;
    spec.compression = compression;
    const Bytes bag = Build(spec);
    for (std::size_t i = 0; i < bag.size(); ++i) {
      Bytes bad = bag;
      bad[i] ^= 0xff;
      const std::string path = WriteBag("flip.bag", bad);
      auto reader = OpenRos1Bag(path);
      if (!reader) {
        EXPECT_EQ(reader.error().file, path);
        continue;
      }
      std::optional<BagError> error;
      const auto records = ReadAll(**reader, &error);
      if (error) {
        EXPECT_EQ(error->file, path);
      } else {
        EXPECT_LE(records.size(), 2u);
      }
    }
  }
}

}  // namespace
}  // namespace semgraph::ros
