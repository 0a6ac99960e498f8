// The fixtures written by Foxglove's packages (tests/ros/fixtures/write_fixtures.mjs): paths,
// the expected values of expected.json as semgraph's message structs, and byte-level helpers
// for the hostile-file tests.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <string>
#include <vector>

#include "semgraph/ros/messages.h"

namespace semgraph::ros::testing {

/// The fixture folder (written by the ctest fixture ros.fixtures).
std::string FixturesDir();
/// Whether the fixtures exist (the writer needs node; tests skip without them).
bool HaveFixtures();
/// expected.json, parsed once.
const YAML::Node& Expected();

std::vector<std::uint8_t> ReadBytes(const std::string& path);
void WriteBytes(const std::string& path, const std::vector<std::uint8_t>& bytes);
/// A fresh path under the test's temporary folder.
std::string TempPath(const std::string& name);

/// The JSON value as the message. `ros1`: read Header.seq (ROS 2 headers have none).
template <class M>
M FromJson(const YAML::Node& value, bool ros1);

/// Little-endian field access for patching files.
std::uint64_t LoadU64(const std::vector<std::uint8_t>& b, std::size_t at);
std::uint32_t LoadU32(const std::vector<std::uint8_t>& b, std::size_t at);
void StoreU64(std::vector<std::uint8_t>& b, std::size_t at, std::uint64_t v);
void StoreU32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v);

/// The MCAP records of a file in order (a walk of opcode + length from byte 8, written for the
/// tests from the specification): each record's offset and opcode.
struct RecordAt {
  std::size_t offset;
  std::uint8_t opcode;
  std::uint64_t length;
};
std::vector<RecordAt> McapRecords(const std::vector<std::uint8_t>& file);
/// The first record with `opcode` (offset of its opcode byte); aborts the test if none.
RecordAt FirstRecord(const std::vector<std::uint8_t>& file, std::uint8_t opcode);
/// Recomputes the data-section CRC of the DataEnd record at `data_end` (found before the
/// patch, which may break the record walk) with zlib's crc32.
void ResealDataCrc(std::vector<std::uint8_t>& file, const RecordAt& data_end);

}  // namespace semgraph::ros::testing
