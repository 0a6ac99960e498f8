// OpenBag: the reader for a bag chosen by content (spec: formats by content, never by name).
// A rosbag2 bag folder is opened by its metadata.yaml's storage_identifier: sqlite3 folders by
// the sqlite3 reader, MCAP folders file by file, merged by log time when split.
#include <filesystem>

#include "merged_bag_reader.h"
#include "rosbag2_metadata.h"
#include "semgraph/ros/bag_reader.h"

namespace semgraph::ros {
namespace {

Expected<BagReaderPtr, BagError> OpenMcapFolder(const std::string& folder,
                                                const Rosbag2Metadata& meta,
                                                const BagReaderOptions& options) {
  std::vector<BagReaderPtr> parts;
  for (const std::string& file : meta.relative_file_paths) {
    auto part = OpenMcapBag((std::filesystem::path(folder) / file).string(), options);
    if (!part) return Unexpected{part.error()};
    parts.push_back(std::move(*part));
  }
  return MergeBagReaders(folder, BagFormat::kMcap, std::move(parts));
}

}  // namespace

Expected<BagReaderPtr, BagError> OpenBag(const std::string& path, const BagReaderOptions& options) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    if (!std::filesystem::exists(std::filesystem::path(path) / "metadata.yaml", ec)) {
      return Unexpected{BagError{BagErrorCode::kUnknownFormat, path, 0,
                                 "a folder without metadata.yaml is not a rosbag2 bag"}};
    }
    auto meta = ReadRosbag2Metadata(path);
    if (!meta) return Unexpected{meta.error()};
    if (meta->storage_identifier == "sqlite3") return OpenRosbag2Sqlite3Bag(path, options);
    if (meta->storage_identifier == "mcap") return OpenMcapFolder(path, *meta, options);
    return Unexpected{BagError{
        BagErrorCode::kUnsupported, (std::filesystem::path(path) / "metadata.yaml").string(), 0,
        "storage_identifier '" + meta->storage_identifier + "' (known: sqlite3, mcap)"}};
  }
  auto format = DetectBagFormat(path);
  if (!format) return Unexpected{format.error()};
  switch (*format) {
    case BagFormat::kMcap:
      return OpenMcapBag(path, options);
    case BagFormat::kRosbag2Sqlite3:
      return OpenRosbag2Sqlite3Bag(path, options);
    case BagFormat::kRos1:
      return OpenRos1Bag(path, options);
  }
  return Unexpected{BagError{BagErrorCode::kUnknownFormat, path, 0, "unknown bag format"}};
}

}  // namespace semgraph::ros
