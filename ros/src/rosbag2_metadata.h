// File: ros/src/rosbag2_metadata.h (internal to semgraph::ros)
//
// The few keys of a rosbag2 bag folder's metadata.yaml that a reader needs (rosbag2_storage's
// `rosbag2_bagfile_information`): storage_identifier, relative_file_paths and the compression
// keys. A full YAML parser (yaml-cpp) is kept out of semgraph::ros (the library depends on base
// only), and rosbag2 writes this file with yaml-cpp's emitter in block style, so a line reader
// of the top-level keys under `rosbag2_bagfile_information:` suffices: `key: scalar` (plain,
// "double" or 'single' quoted), and the sequence `relative_file_paths` as `- item` lines or a
// flow `[a, b]`. Anything else in the file (topics, QoS profiles, durations) is not read.
//
// Invariants: on success storage_identifier is non-empty and relative_file_paths lists at least
// one file, each relative (no leading '/'). Costs: O(file size); the file is at most 16 MiB.
#pragma once

#include <string>
#include <vector>

#include "semgraph/ros/bag_reader.h"

namespace semgraph::ros {

struct Rosbag2Metadata {
  std::string storage_identifier;                // "sqlite3", "mcap"
  std::vector<std::string> relative_file_paths;  // as listed, relative to the folder
  std::string compression_format;                // "" (none), "zstd"
  std::string compression_mode;                  // "" , "file", "message"
};

// Reads FOLDER/metadata.yaml. Errors (kIo, kMalformed) name that file and the line's byte offset.
[[nodiscard]] Expected<Rosbag2Metadata, BagError> ReadRosbag2Metadata(const std::string& folder);

}  // namespace semgraph::ros
