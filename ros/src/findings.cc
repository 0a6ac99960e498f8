// The tf checker's findings, grouped (findings.h).
#include "semgraph/ros/findings.h"

#include <cstdio>

#include "json_text.h"

namespace semgraph::ros {

std::size_t Findings::Add(FindingCode code, std::string_view parent, std::string_view child,
                          const TransformOrigin& origin,
                          const std::function<std::string()>& describe) {
  ++total_;
  Key key{code, std::string(parent), std::string(child)};
  if (const auto it = index_.find(key); it != index_.end()) {
    FindingGroup& g = groups_[it->second];
    ++g.count;
    g.last_log_time_ns = origin.log_time_ns;
    g.last_stamp_ns = origin.stamp_ns;
    return it->second;
  }
  FindingGroup g;
  g.code = code;
  g.topic = std::string(origin.topic);
  g.parent = std::get<1>(key);
  g.child = std::get<2>(key);
  g.count = 1;
  g.first_log_time_ns = g.last_log_time_ns = origin.log_time_ns;
  g.first_stamp_ns = g.last_stamp_ns = origin.stamp_ns;
  g.message = describe ? describe() : std::string();
  groups_.push_back(std::move(g));
  index_.emplace(std::move(key), groups_.size() - 1);
  return groups_.size() - 1;
}

std::string ToJsonLine(const FindingGroup& g) {
  using json::Quoted;
  using json::Seconds;
  return "{\"error\": " + Quoted(g.code.name()) + ", \"topic\": " + Quoted(g.topic) +
         ", \"parent\": " + Quoted(g.parent) + ", \"child\": " + Quoted(g.child) +
         ", \"count\": " + std::to_string(g.count) +
         ", \"first_log_time\": " + Seconds(g.first_log_time_ns) +
         ", \"last_log_time\": " + Seconds(g.last_log_time_ns) +
         ", \"first_stamp\": " + Seconds(g.first_stamp_ns) +
         ", \"last_stamp\": " + Seconds(g.last_stamp_ns) + ", \"message\": " + Quoted(g.message) +
         "}";
}

}  // namespace semgraph::ros
