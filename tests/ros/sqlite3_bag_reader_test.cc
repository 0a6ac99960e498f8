// The rosbag2 sqlite3 reader against bags written with Python's sqlite3 in rosbag2's schema
// (tests/ros/fixtures/write_ros1_bags.py; a .db3 with rows out of timestamp order, and a bag
// folder split into two files whose times interleave), decoded with the CDR codecs and compared
// with the values the writer was given; the test-side CDR bytes are also checked against
// semgraph's encoder (itself byte-checked against Foxglove's writer in the codec tests). Hostile
// databases are built here with the sqlite3 API.
#include <sqlite3.h>

#include <filesystem>

#include "bag_fixtures.h"

namespace semgraph::ros {
namespace {

using testing::ExpectBagMatches;
using testing::FixturePath;
using testing::ReadAll;

std::vector<testing::OwnedRecord> ReadBag(const std::string& path) {
  auto reader = OpenRosbag2Sqlite3Bag(path);
  EXPECT_TRUE(reader) << (reader ? "" : Describe(reader.error()));
  if (!reader) return {};
  EXPECT_EQ((*reader)->format(), BagFormat::kRosbag2Sqlite3);
  EXPECT_EQ((*reader)->path(), path);
  std::optional<BagError> error;
  auto records = ReadAll(**reader, &error);
  EXPECT_FALSE(error) << Describe(*error);
  return records;
}

std::optional<BagError> ErrorOf(const std::string& path) {
  auto reader = OpenRosbag2Sqlite3Bag(path);
  if (!reader) return reader.error();
  std::optional<BagError> error;
  ReadAll(**reader, &error);
  return error;
}

TEST(Sqlite3BagReader, Db3FileReadsInTimestampOrderWithTheWrittenValues) {
  ExpectBagMatches(ReadBag(FixturePath("ros2.db3")), "ros2.db3", MessageEncoding::kCdr);
}

TEST(Sqlite3BagReader, SplitBagFolderMergesItsFilesByTimestamp) {
  ExpectBagMatches(ReadBag(FixturePath("ros2_split")), "ros2_split", MessageEncoding::kCdr);
}

TEST(Sqlite3BagReader, FoxgloveWrittenCdrSamplesReadAndDecode) {
  // Rows holding Foxglove's own CDR bytes (@foxglove/rosmsg2-serialization), inserted in reverse
  // log-time order; written only when the Foxglove fixtures (node) were available.
  if (!testing::Expected()["bags"]["ros2_foxglove.db3"]) {
    GTEST_SKIP() << "no Foxglove fixtures (node missing): ros2_foxglove.db3 was not written";
  }
  ExpectBagMatches(ReadBag(FixturePath("ros2_foxglove.db3")), "ros2_foxglove.db3",
                   MessageEncoding::kCdr);
}

TEST(Sqlite3BagReader, TopicsComeFromTheTopicsTable) {
  auto reader = OpenRosbag2Sqlite3Bag(FixturePath("ros2.db3"));
  ASSERT_TRUE(reader);
  std::map<std::string, std::string> topics;
  for (const BagTopic& t : (*reader)->topics()) {
    EXPECT_EQ(t.encoding, MessageEncoding::kCdr);
    EXPECT_EQ(t.message_count, -1);  // not counted up front (that would read the whole table)
    topics[t.name] = t.type_name;
  }
  EXPECT_EQ(topics,
            (std::map<std::string, std::string>{{"/tf", "tf2_msgs/msg/TFMessage"},
                                                {"/tf_static", "tf2_msgs/msg/TFMessage"},
                                                {"/joint_states", "sensor_msgs/msg/JointState"},
                                                {"/robot_description", "std_msgs/msg/String"},
                                                {"/chatter", "std_msgs/msg/String"}}));
}

TEST(Sqlite3BagReader, TestSideCdrBytesEqualSemgraphsEncoder) {
  // The fixture's CDR writer is the test's own: its bytes must be what EncodeCdr writes for the
  // decoded message (EncodeCdr's bytes are checked against Foxglove's writer elsewhere).
  for (const auto& record : ReadBag(FixturePath("ros2.db3"))) {
    std::vector<std::uint8_t> again;
    if (record.kind == MessageKind::kTfMessage) {
      TFMessage msg;
      ASSERT_TRUE(DecodeCdr(record.data, msg));
      ASSERT_TRUE(EncodeCdr(msg, again));
    } else if (record.kind == MessageKind::kJointState) {
      JointState msg;
      ASSERT_TRUE(DecodeCdr(record.data, msg));
      ASSERT_TRUE(EncodeCdr(msg, again));
    } else {
      String msg;
      ASSERT_TRUE(DecodeCdr(record.data, msg));
      ASSERT_TRUE(EncodeCdr(msg, again));
    }
    EXPECT_EQ(again, record.data) << record.topic << " at " << record.log_time_ns;
  }
}

TEST(Sqlite3BagReader, OpenBagDetectsSqliteFilesAndFolders) {
  for (const char* name : {"ros2.db3", "ros2_split"}) {
    auto reader = OpenBag(FixturePath(name));
    ASSERT_TRUE(reader) << Describe(reader.error());
    EXPECT_EQ((*reader)->format(), BagFormat::kRosbag2Sqlite3);
    ExpectBagMatches(ReadAll(**reader, nullptr), name, MessageEncoding::kCdr);
  }
}

// ---- Hostile databases ----

// A database at `path` built by `sql` (rosbag2's tables unless the SQL says otherwise).
std::string MakeDb(const std::string& name, const std::string& sql) {
  const std::string path = testing::ScratchDir("sqlite_" + name) + "/bag.db3";
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* message = nullptr;
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message), SQLITE_OK)
      << (message ? message : "");
  sqlite3_free(message);
  sqlite3_close(db);
  return path;
}

const std::string kTopics =
    "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
    " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
    "INSERT INTO topics VALUES (1, '/tf', 'tf2_msgs/msg/TFMessage', 'cdr', '');";
const std::string kMessages =
    "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
    " timestamp INTEGER NOT NULL, data BLOB NOT NULL);";

void ExpectError(const std::string& path, BagErrorCode code, std::string_view says) {
  const auto error = ErrorOf(path);
  ASSERT_TRUE(error) << path << " read without an error";
  EXPECT_EQ(error->code, code) << Describe(*error);
  EXPECT_EQ(error->file, path);
  EXPECT_NE(error->message.find(says), std::string::npos) << Describe(*error);
}

TEST(Sqlite3BagReader, NotASqliteDatabaseIsRefused) {
  const std::string path = testing::ScratchDir("sqlite_text") + "/bag.db3";
  testing::WriteFile(path, std::vector<std::uint8_t>(100, 'x'));
  ExpectError(path, BagErrorCode::kUnknownFormat, "not a sqlite3 database");
}

TEST(Sqlite3BagReader, MissingTablesAndColumnsAreRefused) {
  ExpectError(MakeDb("no_messages", kTopics), BagErrorCode::kMalformed, "no table 'messages'");
  ExpectError(MakeDb("no_topics", kMessages), BagErrorCode::kMalformed, "no table 'topics'");
  ExpectError(MakeDb("no_data", kTopics + "CREATE TABLE messages(id INTEGER PRIMARY KEY,"
                                          " topic_id INTEGER, timestamp INTEGER);"),
              BagErrorCode::kMalformed, "table 'messages' has no column 'data'");
}

TEST(Sqlite3BagReader, BadRowsAreRefusedNamingTheRow) {
  ExpectError(MakeDb("unknown_topic", kTopics + kMessages +
                                          "INSERT INTO messages VALUES (1, 1, 5, x'00010000');"
                                          "INSERT INTO messages VALUES (2, 9, 6, x'00010000');"),
              BagErrorCode::kMalformed, "messages row id 2: topic_id 9, which the topics table");
  ExpectError(
      MakeDb("text_data", kTopics + "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id,"
                                    " timestamp, data);"
                                    "INSERT INTO messages VALUES (4, 1, 5, 'text');"),
      BagErrorCode::kMalformed, "messages row id 4: data is not a blob");
  ExpectError(
      MakeDb("text_time", kTopics + "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id,"
                                    " timestamp, data);"
                                    "INSERT INTO messages VALUES (3, 1, 'soon', x'00');"),
      BagErrorCode::kMalformed, "messages row id 3: topic_id or timestamp not an integer");
}

TEST(Sqlite3BagReader, CorruptOrTruncatedFilesAreErrors) {
  const auto original = testing::ReadFile(FixturePath("ros2.db3"));
  ASSERT_GT(original.size(), 8192u);
  const std::string dir = testing::ScratchDir("sqlite_corrupt");
  // Every page after the first overwritten: SQLite reports a malformed image.
  auto garbage = original;
  for (std::size_t i = 4096; i < garbage.size(); ++i) garbage[i] = static_cast<std::uint8_t>(i * 7);
  testing::WriteFile(dir + "/garbage.db3", garbage);
  ExpectError(dir + "/garbage.db3", BagErrorCode::kMalformed, "malformed");
  // Cut after the first page (the schema): the tables' pages are missing.
  testing::WriteFile(dir + "/cut.db3", std::span(original).first(4096));
  const auto error = ErrorOf(dir + "/cut.db3");
  ASSERT_TRUE(error);
  EXPECT_EQ(error->file, dir + "/cut.db3");
}

// ---- metadata.yaml ----

std::string MakeFolder(const std::string& name, const std::string& metadata) {
  const std::string dir = testing::ScratchDir("folder_" + name);
  std::filesystem::copy_file(FixturePath("ros2.db3"), dir + "/a.db3");
  const std::vector<std::uint8_t> text(metadata.begin(), metadata.end());
  testing::WriteFile(dir + "/metadata.yaml", text);
  return dir;
}

TEST(Sqlite3BagReader, MetadataFlowSequenceAndQuotesAreRead) {
  const std::string dir = MakeFolder("flow",
                                     "# written by hand\nrosbag2_bagfile_information:\n"
                                     "  version: 4\n  storage_identifier: 'sqlite3'\n"
                                     "  relative_file_paths: [\"a.db3\"]\n");
  auto reader = OpenBag(dir);
  ASSERT_TRUE(reader) << Describe(reader.error());
  EXPECT_EQ(ReadAll(**reader, nullptr).size(),
            testing::Expected()["bags"]["ros2.db3"]["messages"].size());
}

TEST(Sqlite3BagReader, BadMetadataIsRefused) {
  auto expect = [](const std::string& dir, BagErrorCode code, std::string_view says) {
    auto reader = OpenBag(dir);
    ASSERT_FALSE(reader) << dir;
    EXPECT_EQ(reader.error().code, code) << Describe(reader.error());
    EXPECT_NE(reader.error().message.find(says), std::string::npos) << Describe(reader.error());
  };
  const std::string head = "rosbag2_bagfile_information:\n  version: 5\n";
  expect(MakeFolder("no_storage", head + "  relative_file_paths:\n    - a.db3\n"),
         BagErrorCode::kMalformed, "no storage_identifier");
  expect(MakeFolder("no_files", head + "  storage_identifier: sqlite3\n"), BagErrorCode::kMalformed,
         "no relative_file_paths");
  expect(MakeFolder("other", head + "  storage_identifier: rosbag_v2\n  relative_file_paths:\n"
                                    "  - a.db3\n"),
         BagErrorCode::kUnsupported, "storage_identifier 'rosbag_v2'");
  expect(MakeFolder("zstd", head + "  storage_identifier: sqlite3\n  relative_file_paths:\n"
                                   "  - a.db3.zstd\n  compression_format: zstd\n"
                                   "  compression_mode: FILE\n"),
         BagErrorCode::kUnsupported, "compression 'zstd'");
  expect(MakeFolder("missing", head + "  storage_identifier: sqlite3\n  relative_file_paths:\n"
                                      "  - a.db3\n  - b.db3\n"),
         BagErrorCode::kIo, "cannot open");
  expect(MakeFolder("absolute", head + "  storage_identifier: sqlite3\n"
                                       "  relative_file_paths: [/etc/passwd]\n"),
         BagErrorCode::kMalformed, "not a relative path");
}

}  // namespace
}  // namespace semgraph::ros
