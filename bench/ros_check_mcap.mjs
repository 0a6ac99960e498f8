// Reads an MCAP file with Foxglove's @mcap/core (McapStreamReader, CRCs validated) and prints
// the record counts: an independent check of the bench's MCAP writer (bench/ros_bench_data.cc).
// Uncompressed files only (no zstd handler here). Run from a folder with @mcap/core installed,
// e.g. the ROS fixtures' (after `ctest -R ros.fixtures`):
//   cp bench/ros_check_mcap.mjs build/tests/ros/fixture_writer/ &&
//   node build/tests/ros/fixture_writer/ros_check_mcap.mjs FILE.mcap
import { McapStreamReader } from "@mcap/core";
import { readFileSync } from "node:fs";

const reader = new McapStreamReader({ validateCrcs: true });
reader.append(readFileSync(process.argv[2]));
const counts = {};
let record;
while ((record = reader.nextRecord())) counts[record.type] = (counts[record.type] ?? 0) + 1;
if (!reader.done()) throw new Error("the file ended before its footer");
console.log(JSON.stringify(counts));
