// File: semgraph/ros/bag_loader.h
//
// A bag into a scene graph in two passes (docs/ros.md, "Bags into a graph"):
//   ScanBag    reads the whole bag once, decoding every message of the selected topics: a
//              corrupt file or message is an error here, before anything is applied; it
//              collects every static transform (whatever its log time: static transforms are
//              timeless), the first URDF on /robot_description, the topics, the counts and the
//              time ranges (log times and header stamps).
//   ApplyBag   reads it again and applies, in log-time order, the selected messages within
//              [start, end] of log time plus every static transform, through a TfLift whose
//              BodyPlan knows all static transforms of the bag (so bodies are decided before
//              the first transform is applied).
// LoadBag is the two together.
//
// Invariants: on any error of ScanBag (or of LoadBag's scan) the graph is unchanged. ApplyBag
// on a file changed since its scan may fail half way (the graph then holds what was applied).
// Costs: two sequential reads of the file, bounded memory (the reader's largest chunk, plus the
// static transforms and the findings); one graph add per transform. Build time; not
// thread-safe (the graph's one writer).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "semgraph/ros/bag_reader.h"
#include "semgraph/ros/tf_lift.h"

namespace semgraph::ros {

/// Spec §8's defaults: the topics a `bag` op reads.
[[nodiscard]] SEMGRAPH_ROS_EXPORT std::vector<std::string> DefaultBagTopics();

struct BagLoadOptions {
  /// Read, with the topics of lift.pose_topics. A topic of nav_msgs/Odometry is applied as its
  /// pose and twist with covariances; one of geometry_msgs/PoseWithCovarianceStamped only when
  /// lift.pose_topics names its frame (else skipped).
  std::vector<std::string> topics = DefaultBagTopics();
  LiftOptions lift;
  std::optional<std::int64_t> start_ns, end_ns;  ///< log time, inclusive
  BagReaderOptions reader;
  /// Called every 4096 records of each pass (pass 1 or 2, records read so far, the record's log
  /// time), e.g. for a progress line.
  std::function<void(int pass, std::uint64_t records, std::int64_t log_time_ns)> progress;
};

/// A static transform seen in the scan (lifted frame names).
struct StaticEdge {
  std::string parent, child;
};

struct TopicSummary {
  BagTopic topic;
  std::uint64_t messages = 0;  ///< counted while scanning
};

struct BagScan {
  BagFormat format = BagFormat::kMcap;
  std::vector<TopicSummary> topics;
  std::uint64_t records = 0;                                 ///< every message of the bag
  std::int64_t first_log_time_ns = 0, last_log_time_ns = 0;  ///< of every record
  bool has_stamps = false;  ///< a stamped message was seen on the selected topics
  std::int64_t first_stamp_ns = 0, last_stamp_ns = 0;  ///< header stamps on the selected topics
  std::vector<StaticEdge> statics;                     ///< in log-time order
  /// Dynamic transforms' (parent, child) pairs, first occurrence order (for `bag info`).
  std::vector<StaticEdge> dynamics;
  std::optional<std::string> robot_description;  ///< the first one, when its topic is selected
};

struct BagLoadReport {
  std::uint64_t messages = 0;                                ///< selected-topic messages applied
  std::uint64_t skipped = 0;                                 ///< the bag's other messages
  std::int64_t first_log_time_ns = 0, last_log_time_ns = 0;  ///< of the messages applied
  LiftCounts counts;
  Findings findings;
  bool loaded_robot_description = false;
};

[[nodiscard]] SEMGRAPH_ROS_EXPORT Expected<BagScan, BagError> ScanBag(
    const std::string& path, const BagLoadOptions& options);

/// Pass 2. `robot`: a model already in the graph whose joints cover transforms (nullptr: none;
/// then a scanned /robot_description, if any, is loaded into the graph and covers them).
template <coord::Backend B>
[[nodiscard]] SEMGRAPH_ROS_EXPORT Expected<BagLoadReport, BagError> ApplyBag(
    core::SceneGraph<B>& graph, const std::string& path, const BagScan& scan,
    const BagLoadOptions& options, const models::Robot* robot = nullptr);

template <coord::Backend B>
[[nodiscard]] SEMGRAPH_ROS_EXPORT Expected<BagLoadReport, BagError> LoadBag(
    core::SceneGraph<B>& graph, const std::string& path, const BagLoadOptions& options,
    const models::Robot* robot = nullptr);

}  // namespace semgraph::ros
