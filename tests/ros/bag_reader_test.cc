// The format-independent parts of the bag readers: type names (spec §3), errors, and format
// detection by content (not by file name).
#include "semgraph/ros/bag_reader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace semgraph::ros {
namespace {

TEST(RosBagReader, RecognisesTheMessageTypesByName) {
  for (const char* name : {"tf2_msgs/msg/TFMessage", "tf2_msgs/TFMessage", "tf/tfMessage"}) {
    EXPECT_EQ(MessageKindOf(name), MessageKind::kTfMessage) << name;
  }
  EXPECT_EQ(MessageKindOf("sensor_msgs/msg/JointState"), MessageKind::kJointState);
  EXPECT_EQ(MessageKindOf("sensor_msgs/JointState"), MessageKind::kJointState);
  EXPECT_EQ(MessageKindOf("std_msgs/msg/String"), MessageKind::kString);
  EXPECT_EQ(MessageKindOf("std_msgs/String"), MessageKind::kString);
  for (const char* name :
       {"geometry_msgs/msg/PoseWithCovarianceStamped", "geometry_msgs/PoseWithCovarianceStamped"}) {
    EXPECT_EQ(MessageKindOf(name), MessageKind::kPoseWithCovarianceStamped) << name;
  }
  EXPECT_EQ(MessageKindOf("nav_msgs/msg/Odometry"), MessageKind::kOdometry);
  EXPECT_EQ(MessageKindOf("nav_msgs/Odometry"), MessageKind::kOdometry);
  for (const char* name :
       {"", "tf2_msgs/msg/TFMessage ", "geometry_msgs/msg/TransformStamped", "tf2_msgs/tfMessage",
        "TFMessage", "geometry_msgs/msg/PoseWithCovariance", "nav_msgs/msg/Odometry "}) {
    EXPECT_EQ(MessageKindOf(name), MessageKind::kOther) << name;
  }
  EXPECT_EQ(MessageEncodingOf("cdr"), MessageEncoding::kCdr);
  EXPECT_EQ(MessageEncodingOf("ros1"), MessageEncoding::kRos1);
  EXPECT_EQ(MessageEncodingOf("json"), MessageEncoding::kOther);
  EXPECT_EQ(ToString(MessageEncoding::kCdr), "cdr");
  EXPECT_EQ(ToString(BagFormat::kRosbag2Sqlite3), "rosbag2_sqlite3");
}

TEST(RosBagReader, DescribeNamesFileOffsetAndProblem) {
  const BagError e{BagErrorCode::kCrcMismatch, "/data/x.mcap", 1234,
                   "chunk CRC32 1 does not match"};
  EXPECT_EQ(Describe(e), "/data/x.mcap: byte 1234: chunk CRC32 1 does not match (crc_mismatch)");
  EXPECT_EQ(ToString(BagErrorCode::kOverLimit), "over_limit");
}

class RosDetect : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("semgraph_ros_detect_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& bytes) {
    const auto p = (dir_ / name).string();
    std::filesystem::create_directories(std::filesystem::path(p).parent_path());
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  std::filesystem::path dir_;
};

TEST_F(RosDetect, ByContentNotByName) {
  const std::string mcap("\x89MCAP0\r\n\x01", 9);
  const std::string sqlite("SQLite format 3\0rest", 20);
  EXPECT_EQ(*DetectBagFormat(Write("a.bag", mcap)), BagFormat::kMcap);
  EXPECT_EQ(*DetectBagFormat(Write("b.mcap", sqlite)), BagFormat::kRosbag2Sqlite3);
  EXPECT_EQ(*DetectBagFormat(Write("c.db3", "#ROSBAG V2.0\nE")), BagFormat::kRos1);
  auto e = DetectBagFormat(Write("d.mcap", "#ROSBAG V1.2\n"));
  ASSERT_FALSE(e.has_value());
  EXPECT_EQ(e.error().code, BagErrorCode::kUnknownFormat);
  e = DetectBagFormat(Write("e.mcap", std::string("\x89MCAP", 5)));  // a prefix of the magic
  ASSERT_FALSE(e.has_value());
  EXPECT_EQ(e.error().code, BagErrorCode::kUnknownFormat);
  e = DetectBagFormat((dir_ / "missing").string());
  ASSERT_FALSE(e.has_value());
  EXPECT_EQ(e.error().code, BagErrorCode::kIo);
  EXPECT_EQ(e.error().file, (dir_ / "missing").string());
}

TEST_F(RosDetect, BagFolderHasTheFormatOfItsStorageFile) {
  Write("bag/metadata.yaml", "rosbag2_bagfile_information: {}\n");
  Write("bag/bag_0.mcap", std::string("\x89MCAP0\r\n", 8));
  EXPECT_EQ(*DetectBagFormat((dir_ / "bag").string()), BagFormat::kMcap);
  Write("db/metadata.yaml", "rosbag2_bagfile_information: {}\n");
  Write("db/db_0.db3", std::string("SQLite format 3\0", 16));
  EXPECT_EQ(*DetectBagFormat((dir_ / "db").string()), BagFormat::kRosbag2Sqlite3);
  Write("plain/x.mcap", std::string("\x89MCAP0\r\n", 8));
  auto e = DetectBagFormat((dir_ / "plain").string());
  ASSERT_FALSE(e.has_value());
  EXPECT_NE(e.error().message.find("metadata.yaml"), std::string::npos);
}

}  // namespace
}  // namespace semgraph::ros
