// The `bag` op (bag_op.h).
#include "semgraph/bag_op.h"

#include "semgraph/ros/bag_loader.h"

namespace semgraph::script {

namespace {

std::string Seconds(std::int64_t ns) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9f", static_cast<double>(ns) * 1e-9);
  return buf;
}

OpOutcome Failed(std::size_t index, std::string_view code, const std::string& message,
                 const std::string& counts = {}) {
  return OpOutcome{false, std::string(code),
                   "{\"op\": " + std::to_string(index) + ", \"ok\": false, \"error\": " +
                       JsonString(code) + ", \"message\": " + JsonString(message) + counts + "}"};
}

/// The op's fields as loader options; false with the reason when a time is not valid.
bool OptionsOf(const ScriptOp& op, ros::BagLoadOptions* options, std::string* reason) {
  if (op.has_topics) options->topics = op.topics;
  if (op.static_mode == "own_body") options->lift.static_mode = ros::StaticMode::kOwnBody;
  for (const auto& [body, frames] : op.bodies) options->lift.bodies[body] = frames;
  for (const auto& [topic, frame] : op.pose_topics) options->lift.pose_topics[topic] = frame;
  const std::pair<const std::optional<double>*, std::optional<std::int64_t>*> times[] = {
      {&op.start, &options->start_ns}, {&op.end, &options->end_ns}};
  for (const auto& [seconds, ns] : times) {
    if (!*seconds) continue;
    *ns = core::NanosecondsFromSeconds(**seconds);
    if (!*ns) {
      *reason = "'" + std::string(seconds == &op.start ? "start" : "end") + "' is not a time";
      return false;
    }
  }
  return true;
}

}  // namespace

template <coord::Backend B>
OpOutcome ApplyBagOp(core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index,
                     std::string_view base_dir) {
  std::string path = op.file;
  if (!path.empty() && path.front() != '/' && !base_dir.empty()) {
    path = std::string(base_dir) + "/" + path;
  }
  ros::BagLoadOptions options;
  if (std::string reason; !OptionsOf(op, &options, &reason)) {
    return Failed(index, "invalid_number", "bag " + op.file + " rejected: " + reason);
  }
  if (auto plan = ros::BodyPlan::Make(options.lift); !plan) {
    return Failed(index, "invalid_name", "bag " + op.file + " rejected: " + plan.error());
  }
  auto report = ros::LoadBag(graph, path, options);
  if (!report) {
    ros::BagError error = report.error();
    if (error.file == path) error.file = op.file;  // as the script wrote it
    return Failed(index, "invalid_bag", "bag rejected (invalid_bag): " + ros::Describe(error));
  }
  const ros::LiftCounts& c = report->counts;
  const bool any = report->messages > 0;
  const std::string counts =
      ", \"messages\": " + std::to_string(report->messages) +
      ", \"skipped\": " + std::to_string(report->skipped) +
      ", \"transforms\": " + std::to_string(c.transforms) +
      ", \"applied\": " + std::to_string(c.applied) +
      ", \"refused\": " + std::to_string(c.refused) +
      ", \"covered\": " + std::to_string(c.covered) +
      ", \"normalized\": " + std::to_string(c.normalized) +
      ", \"poses_with_covariance\": " + std::to_string(c.poses_with_covariance) +
      ", \"odometry\": " + std::to_string(c.odometry) +
      ", \"covariance_refused\": " + std::to_string(c.covariance_refused) +
      ", \"start\": " + (any ? Seconds(report->first_log_time_ns) : "null") +
      ", \"end\": " + (any ? Seconds(report->last_log_time_ns) : "null");
  if (report->findings.empty()) {
    return OpOutcome{true, "",
                     "{\"op\": " + std::to_string(index) + ", \"ok\": true" + counts + "}"};
  }
  const ros::FindingGroup& first = report->findings.groups().front();
  return Failed(index, first.code.name(), first.message, counts);
}

template OpOutcome ApplyBagOp(core::SceneGraph<coord::QuaternionBackend>&, const ScriptOp&,
                              std::size_t, std::string_view);
template OpOutcome ApplyBagOp(core::SceneGraph<coord::HomogeneousBackend>&, const ScriptOp&,
                              std::size_t, std::string_view);

}  // namespace semgraph::script
