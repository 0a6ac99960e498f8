// semgraph echo --ros / check --ros / serve --ros (ros_live_commands.h; docs/ros.md).
#include "ros_live_commands.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "bag_commands.h"
#include "live_command.h"
#include "script_runner.h"
#include "semgraph/ros_dds/broadcaster.h"
#include "semgraph/ros_dds/listener.h"
#include "semgraph/script/scene_script.h"

namespace semgraph::script {
namespace {

using Clock = std::chrono::steady_clock;

constexpr std::string_view kRosUsage =
    R"(Usage: semgraph echo --ros pose OF WRT [--in FRAME] [--rate HZ] [--count N]
                            [OPTIONS]
       semgraph check --ros [--window S] [OPTIONS]
       semgraph serve --ros FILE [--subscribers N] [OPTIONS]

Live ROS 2 over DDS (rt/tf, rt/tf_static, rt/joint_states, rt/robot_description), no ROS
installation needed:
  echo --ros   listen and print, HZ times a second (default 1), the pose of OF relative to WRT
               (expressed in FRAME, default WRT) at the newest time all its transforms have
               (tf2's Time(0)), as a JSON line: position, quaternion [w, x, y, z], stamp (s);
               or the error (unknown_frame while OF or WRT was not seen yet)
  check --ros  listen and print each finding as a JSON line as it happens (a transform the
               graph refuses, or one that differs from the robot model of /robot_description),
               the same line again once a second while its count grows, then a summary line
               at the end; exit 0 clean, 1 findings
  serve --ros  apply the scene script FILE and publish its graph as tf until stopped (Ctrl-C)
               or --seconds pass: stamped edges' samples on /tf (again when a new subscriber
               appears), timeless edges in one /tf_static message; with --subscribers N, the
               first /tf samples wait until N subscribers are matched and in sync

Options:
  --domain N        DDS domain (default: ROS_DOMAIN_ID, else 0)
  --seconds S       stop after S seconds (default: until Ctrl-C)
  --static MODE     same_body (default) or own_body: how /tf_static maps onto bodies
  --bodies MAP.yaml a bodies map {BODY: [frame, ...]}
  --window S        the graph's history window in seconds (default 10, tf2's buffer)
  --pose-topic TOPIC=FRAME   also subscribe to TOPIC (geometry_msgs/PoseWithCovarianceStamped):
                    each message a stamped pose of FRAME with its covariance (repeatable)
  --odom-topic TOPIC         also subscribe to TOPIC (nav_msgs/Odometry): pose and twist with
                    their covariances (repeatable); a bad covariance is a finding
Configure DDS with CYCLONEDDS_URI (interfaces, peers): docs/ros.md, "Live ROS 2".
)";

struct Args {
  std::vector<std::string> positional;
  std::optional<std::uint32_t> domain;
  double seconds = -1;
  double rate = 1.0;
  long count = -1;
  std::uint32_t subscribers = 0;
  double window = 10.0;
  std::string in;
  ros::LiftOptions lift;
  std::vector<std::string> odometry_topics;
  std::string error;
};

bool ParseNumber(const char* text, double* out) {
  char* end = nullptr;
  *out = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(*out);
}

Args Parse(int argc, char** argv) {
  Args a;
  for (int i = 2; i < argc && a.error.empty(); ++i) {
    const std::string_view s = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 < argc) return argv[++i];
      a.error = "option " + std::string(s) + " needs a value";
      return nullptr;
    };
    auto number = [&](double* out, bool positive) {
      const char* v = value();
      if (v == nullptr) return;
      if (!ParseNumber(v, out) || (positive && !(*out > 0))) {
        a.error = std::string(s) + " needs a positive number, got '" + v + "'";
      }
    };
    double n = 0;
    if (s == "--ros") {
      continue;
    } else if (s == "--domain") {
      number(&n, false);
      if (a.error.empty() && (n < 0 || n > 232 || n != std::floor(n))) {
        a.error = "--domain needs an integer from 0 to 232";
      }
      a.domain = static_cast<std::uint32_t>(n);
    } else if (s == "--seconds") {
      number(&a.seconds, true);
    } else if (s == "--rate") {
      number(&a.rate, true);
    } else if (s == "--window") {
      number(&a.window, true);
    } else if (s == "--count") {
      number(&n, true);
      a.count = static_cast<long>(n);
    } else if (s == "--subscribers") {
      number(&n, true);
      if (a.error.empty() && (n > 1000 || n != std::floor(n))) {
        a.error = "--subscribers needs an integer from 1 to 1000";
      }
      a.subscribers = static_cast<std::uint32_t>(n);
    } else if (s == "--in") {
      if (const char* v = value()) a.in = v;
    } else if (s == "--static") {
      const char* v = value();
      if (v == nullptr) continue;
      const auto mode = ros::StaticModeFromString(v);
      if (!mode) a.error = "--static needs same_body or own_body, got '" + std::string(v) + "'";
      if (mode) a.lift.static_mode = *mode;
    } else if (s == "--bodies") {
      const char* v = value();
      if (v != nullptr && !ReadBodiesMap(v, &a.lift.bodies, &a.error)) continue;
    } else if (s == "--pose-topic") {
      const char* v = value();
      if (v == nullptr) continue;
      const std::string_view text = v;
      const std::size_t eq = text.find('=');
      if (eq == std::string_view::npos || eq == 0 || eq + 1 == text.size()) {
        a.error = "--pose-topic must be TOPIC=FRAME, got '" + std::string(text) + "'";
        continue;
      }
      a.lift.pose_topics[std::string(text.substr(0, eq))] = std::string(text.substr(eq + 1));
    } else if (s == "--odom-topic") {
      if (const char* v = value()) a.odometry_topics.emplace_back(v);
    } else if (s.size() > 1 && s[0] == '-') {
      a.error = "unknown option " + std::string(s);
    } else {
      a.positional.emplace_back(s);
    }
  }
  return a;
}

int Usage(const std::string& problem) {
  std::fprintf(stderr, "semgraph: %s\n%.*s", problem.c_str(), static_cast<int>(kRosUsage.size()),
               kRosUsage.data());
  return kExitMalformed;
}

std::string Vec(const Eigen::Vector3d& v) {
  return "[" + JsonNumber(v.x()) + ", " + JsonNumber(v.y()) + ", " + JsonNumber(v.z()) + "]";
}

// A graph with tf2's time behaviour: linear interpolation, a window of `window` seconds.
base::Expected<core::SceneGraph<>, std::string> TfGraph(double window) {
  core::TimeOptions time;
  time.window = *core::DurationFromSeconds(window);
  time.interpolation = core::Interpolation::kLinear;
  auto graph = core::SceneGraph<>::Create(time);
  if (!graph) return base::Unexpected{graph.error().message};
  return std::move(*graph);
}

ros_dds::ListenerOptions ListenOptions(const Args& a) {
  ros_dds::ListenerOptions o;
  o.domain = a.domain;
  o.lift = a.lift;
  o.odometry_topics = a.odometry_topics;
  return o;
}

// One answer of echo: the JSON line.
std::string EchoLine(const core::SceneGraph<>& g, const core::PoseSpec& spec) {
  const auto X = g.GetPose(spec, core::LatestCommon());
  if (!X) {
    return "{\"ok\": false, \"error\": " + JsonString(base::ToString(X.error().code)) +
           ", \"message\": " + JsonString(g.Describe(X.error(), spec)) + "}";
  }
  Eigen::Quaterniond q = X->value.value.rotation;
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  std::string stamp = "null";
  if (X->time.time) stamp = JsonNumber(X->time.time->seconds());
  return "{\"ok\": true, \"stamp\": " + stamp +
         ", \"position\": " + Vec(X->value.value.translation) + ", \"quaternion\": [" +
         JsonNumber(q.w()) + ", " + JsonNumber(q.x()) + ", " + JsonNumber(q.y()) + ", " +
         JsonNumber(q.z()) + "]}";
}

int Echo(const Args& a) {
  const auto& p = a.positional;
  if (p.size() != 3 || p[0] != "pose") return Usage("echo --ros needs: pose OF WRT");
  auto graph = TfGraph(a.window);
  if (!graph) return Usage(graph.error());
  auto listener = ros_dds::Listener::Create(*graph, ListenOptions(a));
  if (!listener) return Usage(listener.error());
  core::PoseSpec spec = core::PoseSpec::Of(p[1]).RelativeTo(p[2]);
  if (!a.in.empty()) spec.ExpressedIn(a.in);
  const auto start = Clock::now();
  const auto period = std::chrono::duration<double>(1.0 / a.rate);
  long printed = 0, answered = 0;
  auto next = Clock::now();
  while (!live::TimeUp(start, a.seconds) && (a.count < 0 || printed < a.count)) {
    std::this_thread::sleep_until(next);
    next += std::chrono::duration_cast<Clock::duration>(period);
    std::string line;
    (*listener)->WithGraph([&](const core::SceneGraph<>& g) { line = EchoLine(g, spec); });
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
    ++printed;
    if (line.rfind("{\"ok\": true", 0) == 0) ++answered;
  }
  return answered > 0 ? kExitOk : kExitOpFailed;
}

int Check(const Args& a) {
  if (!a.positional.empty()) return Usage("check --ros takes no FILE (bags: semgraph bag check)");
  auto graph = TfGraph(a.window);
  if (!graph) return Usage(graph.error());
  std::mutex mutex;
  std::set<std::size_t> grown;  // groups whose count grew since their last line
  std::vector<std::string> keys;
  ros_dds::ListenerOptions options = ListenOptions(a);
  options.on_finding = [&](const ros::FindingGroup& group, bool first) {
    std::lock_guard<std::mutex> lock(mutex);
    const std::string key =
        std::string(group.code.name()) + "\n" + group.parent + "\n" + group.child;
    if (first) {
      keys.push_back(key);
      std::printf("%s\n", ros::ToJsonLine(group).c_str());
      std::fflush(stdout);
      return;
    }
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (keys[i] == key) grown.insert(i);
    }
  };
  auto listener = ros_dds::Listener::Create(*graph, options);
  if (!listener) return Usage(listener.error());
  const auto start = Clock::now();
  auto last = start;  // the last time grown groups were printed again
  while (!live::TimeUp(start, a.seconds)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (Clock::now() - last < std::chrono::seconds(1)) continue;
    last = Clock::now();
    const std::vector<ros::FindingGroup> groups = (*listener)->findings();
    std::lock_guard<std::mutex> lock(mutex);
    for (const std::size_t i : grown) {
      if (i < groups.size()) std::printf("%s\n", ros::ToJsonLine(groups[i]).c_str());
    }
    grown.clear();
    std::fflush(stdout);
  }
  const ros_dds::ListenerStats stats = (*listener)->stats();
  const std::vector<ros::FindingGroup> groups = (*listener)->findings();
  std::uint64_t total = 0;
  for (const ros::FindingGroup& g : groups) total += g.count;
  std::printf(
      "{\"summary\": true, \"messages\": %llu, \"transforms\": %llu, \"findings\": %llu, "
      "\"groups\": %zu}\n",
      static_cast<unsigned long long>(stats.tf + stats.tf_static + stats.joint_states +
                                      stats.robot_descriptions + stats.poses_with_covariance +
                                      stats.odometry),
      static_cast<unsigned long long>(stats.counts.transforms),
      static_cast<unsigned long long>(total), groups.size());
  return groups.empty() ? kExitOk : kExitOpFailed;
}

int Serve(const Args& a) {
  if (a.positional.size() != 1) return Usage("serve --ros needs one FILE");
  core::SceneGraph<> graph;
  RunOptions options;
  options.on_op = [](const OpResult& r) {
    std::printf("%s\n", r.json.c_str());
    return true;
  };
  const SceneRun run = LoadSceneFile(a.positional[0], graph, options);
  if (run.status == kExitMalformed) {
    std::fprintf(stderr, "%s\n", run.error.c_str());
    return kExitMalformed;
  }
  auto broadcaster = ros_dds::Broadcaster::Create(graph, {a.domain, {}});
  if (!broadcaster) return Usage(broadcaster.error());
  ros_dds::Broadcaster& b = **broadcaster;
  const auto start = Clock::now();
  // --subscribers N: the first /tf samples go out once N readers are matched and in sync (they
  // reach them); waited for in short slices so that Ctrl-C and --seconds still stop it.
  while (a.subscribers > 0 && !live::TimeUp(start, a.seconds) &&
         !b.WaitForSubscribers(a.subscribers, std::chrono::milliseconds(200))) {
  }
  auto sent = b.Broadcast();
  if (!sent) {
    std::fprintf(stderr, "semgraph: %s\n", sent.error().c_str());
    return kExitMalformed;
  }
  std::printf("{\"serving\": \"ros\", \"domain\": %u, \"tf\": %zu, \"tf_static\": %zu}\n",
              b.domain(), sent->tf_transforms, b.last_static().transforms.size());
  std::fflush(stdout);
  // rt/tf is volatile: each new subscriber gets the stored samples again, once the matched
  // readers are in sync (WaitForSubscribers), so that they reach it; the others get identical
  // restatements.
  std::uint32_t subscribers = b.subscribers_matched();
  while (!live::TimeUp(start, a.seconds)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const std::uint32_t now = b.subscribers_matched();
    if (now == subscribers) continue;
    subscribers = now;
    if (auto synced = b.WaitForSubscribers(1, std::chrono::seconds(2)); !synced) {
      std::fprintf(stderr, "semgraph: %s\n", synced.error().c_str());
    }
    b.Rewind();
    if (auto again = b.Broadcast(); !again) {
      std::fprintf(stderr, "semgraph: %s\n", again.error().c_str());
    }
  }
  return run.status;
}

}  // namespace

bool IsRosLiveCommand(int argc, char** argv) {
  if (argc < 2) return false;
  const std::string_view c = argv[1];
  return (c == "echo" || c == "check" || c == "serve") && live::HasFlag(argc, argv, "--ros");
}

int RunRosLiveCommand(int argc, char** argv) {
  if (live::PrintedHelp(argc, argv, kRosUsage)) return kExitOk;
  const Args a = Parse(argc, argv);
  if (!a.error.empty()) return Usage(a.error);
  live::StopOnSignals();
  const std::string_view c = argv[1];
  if (c == "echo") return Echo(a);
  if (c == "check") return Check(a);
  return Serve(a);
}

}  // namespace semgraph::script
