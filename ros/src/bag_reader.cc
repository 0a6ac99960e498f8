// The format-independent parts of the bag readers: names, errors, format detection.
#include "semgraph/ros/bag_reader.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace semgraph::ros {

BagReader::~BagReader() = default;

MessageKind MessageKindOf(std::string_view type_name) noexcept {
  if (type_name == "tf2_msgs/msg/TFMessage" || type_name == "tf2_msgs/TFMessage" ||
      type_name == "tf/tfMessage") {
    return MessageKind::kTfMessage;
  }
  if (type_name == "sensor_msgs/msg/JointState" || type_name == "sensor_msgs/JointState") {
    return MessageKind::kJointState;
  }
  if (type_name == "std_msgs/msg/String" || type_name == "std_msgs/String") {
    return MessageKind::kString;
  }
  if (type_name == "geometry_msgs/msg/PoseWithCovarianceStamped" ||
      type_name == "geometry_msgs/PoseWithCovarianceStamped") {
    return MessageKind::kPoseWithCovarianceStamped;
  }
  if (type_name == "nav_msgs/msg/Odometry" || type_name == "nav_msgs/Odometry") {
    return MessageKind::kOdometry;
  }
  return MessageKind::kOther;
}

MessageEncoding MessageEncodingOf(std::string_view name) noexcept {
  if (name == "cdr") return MessageEncoding::kCdr;
  if (name == "ros1") return MessageEncoding::kRos1;
  return MessageEncoding::kOther;
}

std::string_view ToString(BagFormat format) noexcept {
  switch (format) {
    case BagFormat::kMcap:
      return "mcap";
    case BagFormat::kRosbag2Sqlite3:
      return "rosbag2_sqlite3";
    case BagFormat::kRos1:
      return "ros1";
  }
  return "unknown";
}

std::string_view ToString(MessageEncoding encoding) noexcept {
  switch (encoding) {
    case MessageEncoding::kCdr:
      return "cdr";
    case MessageEncoding::kRos1:
      return "ros1";
    case MessageEncoding::kOther:
      return "other";
  }
  return "other";
}

std::string_view ToString(BagErrorCode code) noexcept {
  switch (code) {
    case BagErrorCode::kIo:
      return "io";
    case BagErrorCode::kUnknownFormat:
      return "unknown_format";
    case BagErrorCode::kTruncated:
      return "truncated";
    case BagErrorCode::kMalformed:
      return "malformed";
    case BagErrorCode::kCrcMismatch:
      return "crc_mismatch";
    case BagErrorCode::kOverLimit:
      return "over_limit";
    case BagErrorCode::kDecompression:
      return "decompression";
    case BagErrorCode::kUnsupported:
      return "unsupported";
  }
  return "unknown";
}

std::string Describe(const BagError& error) {
  std::string s = error.file;
  s += ": byte ";
  s += std::to_string(error.offset);
  s += ": ";
  s += error.message;
  s += " (";
  s += ToString(error.code);
  s += ")";
  return s;
}

namespace {

constexpr std::array<unsigned char, 8> kMcapMagic = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr std::string_view kSqliteMagic{"SQLite format 3\0", 16};
constexpr std::string_view kRos1Magic = "#ROSBAG V2.0\n";

// The format of a regular file from its first 16 bytes; kUnknownFormat when none matches.
Expected<BagFormat, BagError> DetectFileFormat(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return Unexpected{BagError{BagErrorCode::kIo, path, 0, "cannot open the file"}};
  }
  std::array<char, 16> head{};
  in.read(head.data(), head.size());
  const auto n = static_cast<std::size_t>(in.gcount());
  const std::string_view got(head.data(), n);
  if (n >= kMcapMagic.size() &&
      std::memcmp(head.data(), kMcapMagic.data(), kMcapMagic.size()) == 0) {
    return BagFormat::kMcap;
  }
  if (got.starts_with(kSqliteMagic)) return BagFormat::kRosbag2Sqlite3;
  if (got.starts_with(kRos1Magic)) return BagFormat::kRos1;
  return Unexpected{BagError{BagErrorCode::kUnknownFormat, path, 0,
                             "not a bag: the file starts with none of the MCAP, sqlite3 or "
                             "ROS 1 bag v2.0 magic bytes"}};
}

}  // namespace

Expected<BagFormat, BagError> DetectBagFormat(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(path, ec)) return DetectFileFormat(path);
  if (!fs::exists(fs::path(path) / "metadata.yaml", ec)) {
    return Unexpected{BagError{BagErrorCode::kUnknownFormat, path, 0,
                               "a folder without metadata.yaml is not a rosbag2 bag"}};
  }
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(path, ec)) {
    if (entry.is_regular_file(ec) && entry.path().filename() != "metadata.yaml") {
      files.push_back(entry.path());
    }
  }
  if (ec) return Unexpected{BagError{BagErrorCode::kIo, path, 0, "cannot list the folder"}};
  std::sort(files.begin(), files.end());
  for (const auto& file : files) {
    auto format = DetectFileFormat(file.string());
    if (format && *format != BagFormat::kRos1) return format;
  }
  return Unexpected{BagError{BagErrorCode::kUnknownFormat, path, 0,
                             "the bag folder holds no MCAP or sqlite3 storage file"}};
}

}  // namespace semgraph::ros
