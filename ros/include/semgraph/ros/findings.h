// File: semgraph/ros/findings.h
//
// The tf checker's findings (docs/ros.md, "Findings"): each transform the graph refused, and
// each transform covered by a robot model whose value differs from the model's, grouped by
// (code, parent, child), with the topic, how many times, the first and last log time and
// stamp, and the message of the first occurrence.
//
// Invariants: groups keep the order of their first occurrence; count >= 1; first_* <= last_*
// in the order of arrival (not sorted: a bag delivers log times in order, a live stream need
// not). Costs: Add O(1) expected; the message is formatted by the caller only for a group's
// first occurrence (`describe` is called once per group). Not thread-safe.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "semgraph/base/error_code.h"
#include "semgraph/ros/export.h"

namespace semgraph::ros {

/// A finding's code: a graph error code (scene-graph rules, time, kinematics), or
/// model_mismatch (a covered transform that differs from the robot model's pose).
struct FindingCode {
  base::ErrorCode error = base::ErrorCode::kOk;
  bool model_mismatch = false;

  [[nodiscard]] static FindingCode ModelMismatch() noexcept { return {base::ErrorCode::kOk, true}; }
  /// "model_mismatch" or the error code's snake_case name.
  [[nodiscard]] std::string_view name() const noexcept {
    return model_mismatch ? std::string_view("model_mismatch") : base::ToString(error);
  }
  friend auto operator<=>(const FindingCode&, const FindingCode&) = default;
};

/// Where a transform came from: its topic and log time (the bag's or the listener's receive
/// time) and its header stamp, in nanoseconds.
struct TransformOrigin {
  std::string_view topic;
  std::int64_t log_time_ns = 0;
  std::int64_t stamp_ns = 0;
};

struct FindingGroup {
  FindingCode code;
  std::string topic;  ///< of the first occurrence
  std::string parent, child;
  std::uint64_t count = 0;
  std::int64_t first_log_time_ns = 0, last_log_time_ns = 0;
  std::int64_t first_stamp_ns = 0, last_stamp_ns = 0;
  std::string message;  ///< of the first occurrence
};

class SEMGRAPH_ROS_EXPORT Findings {
 public:
  /// Records one occurrence; `describe` gives the message and is called for a new group only.
  /// Returns the group's index.
  std::size_t Add(FindingCode code, std::string_view parent, std::string_view child,
                  const TransformOrigin& origin, const std::function<std::string()>& describe);
  [[nodiscard]] const std::vector<FindingGroup>& groups() const noexcept { return groups_; }
  /// Occurrences over all groups.
  [[nodiscard]] std::uint64_t total() const noexcept { return total_; }
  [[nodiscard]] bool empty() const noexcept { return groups_.empty(); }

 private:
  using Key = std::tuple<FindingCode, std::string, std::string>;
  std::map<Key, std::size_t, std::less<>> index_;
  std::vector<FindingGroup> groups_;
  std::uint64_t total_ = 0;
};

/// One finding group as the JSON line of `semgraph bag check` (docs/ros.md), times in seconds.
[[nodiscard]] SEMGRAPH_ROS_EXPORT std::string ToJsonLine(const FindingGroup& group);

}  // namespace semgraph::ros
