// OpenBag: the reader chosen by content (files named misleadingly on purpose), rosbag2 bag
// folders by their metadata.yaml (sqlite3 in sqlite3_bag_reader_test.cc; MCAP here, with the
// MCAP bags written by Foxglove's @mcap/core), and split folders merged by log time.
#include <algorithm>
#include <filesystem>

#include "bag_fixtures.h"

namespace semgraph::ros {
namespace {

using testing::OwnedRecord;
using testing::ReadAll;

// The Foxglove-written MCAP bags (ctest ros.fixtures; skipped without node).
std::string McapFixture(const std::string& name) {
  return std::string(SEMGRAPH_ROS_FIXTURES) + "/" + name;
}
#define SKIP_WITHOUT_MCAP_FIXTURES()                                                      \
  if (!std::filesystem::exists(McapFixture("tf_zstd.mcap"))) {                            \
    GTEST_SKIP() << "no MCAP fixtures in " << SEMGRAPH_ROS_FIXTURES << " (node missing)"; \
  }

std::vector<OwnedRecord> ReadOrFail(Expected<BagReaderPtr, BagError> reader) {
  EXPECT_TRUE(reader) << (reader ? "" : Describe(reader.error()));
  if (!reader) return {};
  std::optional<BagError> error;
  auto records = ReadAll(**reader, &error);
  EXPECT_FALSE(error) << Describe(*error);
  return records;
}

void ExpectSame(const OwnedRecord& a, const OwnedRecord& b) {
  EXPECT_EQ(a.topic, b.topic);
  EXPECT_EQ(a.type_name, b.type_name);
  EXPECT_EQ(a.encoding, b.encoding);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.log_time_ns, b.log_time_ns);
  EXPECT_EQ(a.data, b.data);
}

std::string McapFolder(const std::string& name, const std::vector<std::string>& files) {
  const std::string dir = testing::ScratchDir(name);
  std::string yaml =
      "rosbag2_bagfile_information:\n  version: 8\n  storage_identifier: mcap\n"
      "  relative_file_paths:\n";
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::string part = name + "_" + std::to_string(i) + ".mcap";
    std::filesystem::copy_file(McapFixture(files[i]), dir + "/" + part);
    yaml += "    - " + part + "\n";
  }
  testing::WriteFile(dir + "/metadata.yaml", std::vector<std::uint8_t>(yaml.begin(), yaml.end()));
  return dir;
}

TEST(OpenBag, McapFolderReadsLikeItsFile) {
  SKIP_WITHOUT_MCAP_FIXTURES();
  const auto want = ReadOrFail(OpenMcapBag(McapFixture("tf_zstd.mcap")));
  ASSERT_GT(want.size(), 1000u);
  const std::string dir = McapFolder("mcap_one", {"tf_zstd.mcap"});
  auto reader = OpenBag(dir);
  ASSERT_TRUE(reader) << Describe(reader.error());
  EXPECT_EQ((*reader)->format(), BagFormat::kMcap);
  EXPECT_EQ((*reader)->path(), dir);
  const auto got = ReadOrFail(std::move(reader));
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) ExpectSame(got[i], want[i]);
}

TEST(OpenBag, SplitMcapFolderMergesItsFilesByLogTime) {
  SKIP_WITHOUT_MCAP_FIXTURES();
  // Two files holding the same messages (lz4 and uncompressed chunks): each message twice, the
  // first file's copy first (equal log times keep the order of the files).
  const auto one = ReadOrFail(OpenMcapBag(McapFixture("tf_lz4.mcap")));
  auto reader = OpenBag(McapFolder("mcap_two", {"tf_lz4.mcap", "tf_none.mcap"}));
  ASSERT_TRUE(reader) << Describe(reader.error());
  for (const BagTopic& topic : (*reader)->topics()) {
    const auto n = std::count_if(one.begin(), one.end(),
                                 [&](const OwnedRecord& r) { return r.topic == topic.name; });
    EXPECT_EQ(topic.message_count, 2 * n) << topic.name;  // both files have statistics
  }
  const auto got = ReadOrFail(std::move(reader));
  ASSERT_EQ(got.size(), 2 * one.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    ExpectSame(got[2 * i], one[i]);
    ExpectSame(got[2 * i + 1], one[i]);
  }
}

TEST(OpenBag, FormatsAreChosenByContentNotByName) {
  const std::string dir = testing::ScratchDir("misnamed");
  struct Case {
    std::string from, as;
    BagFormat format;
  };
  std::vector<Case> cases = {
      {testing::FixturePath("ros2.db3"), dir + "/really_sqlite.mcap", BagFormat::kRosbag2Sqlite3},
      {testing::FixturePath("ros1_bz2.bag"), dir + "/really_ros1.db3", BagFormat::kRos1}};
  if (std::filesystem::exists(McapFixture("tf_zstd.mcap"))) {
    cases.push_back({McapFixture("tf_zstd.mcap"), dir + "/really_mcap.bag", BagFormat::kMcap});
  }
  for (const Case& c : cases) {
    std::filesystem::copy_file(c.from, c.as);
    auto reader = OpenBag(c.as);
    ASSERT_TRUE(reader) << Describe(reader.error());
    EXPECT_EQ((*reader)->format(), c.format) << c.as;
    const auto got = ReadOrFail(std::move(reader));
    EXPECT_GT(got.size(), 0u) << c.as;
  }
}

TEST(OpenBag, WhatIsNoBagIsRefused) {
  const std::string dir = testing::ScratchDir("no_bag");
  auto folder = OpenBag(dir);  // a folder without metadata.yaml
  ASSERT_FALSE(folder);
  EXPECT_EQ(folder.error().code, BagErrorCode::kUnknownFormat) << Describe(folder.error());
  const std::string text = dir + "/notes.txt";
  testing::WriteFile(text, std::vector<std::uint8_t>(40, 'a'));
  auto file = OpenBag(text);
  ASSERT_FALSE(file);
  EXPECT_EQ(file.error().code, BagErrorCode::kUnknownFormat) << Describe(file.error());
  EXPECT_EQ(file.error().file, text);
  auto missing = OpenBag(dir + "/missing.bag");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().code, BagErrorCode::kIo) << Describe(missing.error());
}

}  // namespace
}  // namespace semgraph::ros
