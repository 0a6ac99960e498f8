// File: ros/src/merged_bag_reader.h (internal to semgraph::ros)
//
// One BagReader over several (a rosbag2 bag folder split into files): a k-way merge by log time.
//
// Invariants: records come in non-decreasing log time; equal log times keep the order of the
// parts (the folder's file order), then each part's own order. Each part holds one pending
// record, so memory is the sum of the parts' (each bounded). The record returned last stays valid
// until the next Next() (its part is advanced only then). The first error of a part finishes
// the merged reader with that error (which names the part's file).
// Costs: Next is O(parts) (bags have a handful of files) plus the part's own Next.
#pragma once

#include <vector>

#include "semgraph/ros/bag_reader.h"

namespace semgraph::ros {

// `parts` non-empty; `path` is reported as the merged reader's path (the bag folder).
[[nodiscard]] BagReaderPtr MergeBagReaders(std::string path, BagFormat format,
                                           std::vector<BagReaderPtr> parts);

}  // namespace semgraph::ros
