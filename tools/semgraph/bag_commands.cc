// `semgraph bag info` and `semgraph bag check` (bag_commands.h).
#include "bag_commands.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "semgraph/models/urdf.h"
#include "semgraph/ros/bag_loader.h"
#include "semgraph/yaml_tree.h"

namespace semgraph::script {

namespace {

constexpr std::string_view kBagUsage = R"(Usage: semgraph bag info FILE
       semgraph bag check FILE [--static same_body|own_body] [--bodies MAP.yaml] [--urdf FILE]
                               [--window SECONDS] [--topics /tf,/tf_static,/joint_states]
                               [--pose-topic TOPIC=FRAME]...

  info    the bag's format, topics with types and counts, time range, and its tf frame tree
          with the body of each frame (as `bag check` would lift it)
  check   applies the bag's tf and joint states to a new scene graph and prints one JSON line
          per finding group (a transform the graph refuses, or one that differs from the robot
          model of --urdf), then a summary line. The window covers the whole bag unless
          --window is given (a tf2 buffer of that many seconds). nav_msgs/Odometry topics
          given in --topics, and geometry_msgs/PoseWithCovarianceStamped topics given by
          --pose-topic (the frame whose pose the topic gives), are applied with their
          covariances (a bad covariance is a finding).
  FILE    an MCAP file, a rosbag2 sqlite3 .db3 file or bag folder, or a ROS 1 bag (by content)

Exit status: 0 clean, 1 findings, 2 the file cannot be read, is corrupt, or bad usage.
)";

int UsageError(const std::string& message) {
  std::fprintf(stderr, "semgraph bag: %s\n%s", message.c_str(), kBagUsage.data());
  return 2;
}

std::string Seconds(std::int64_t ns) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9f", static_cast<double>(ns) * 1e-9);
  return buf;
}

/// The progress line on stderr, only when it is a terminal.
std::function<void(int, std::uint64_t, std::int64_t)> Progress() {
  if (isatty(STDERR_FILENO) == 0) return {};
  return [](int pass, std::uint64_t records, std::int64_t log_time_ns) {
    std::fprintf(stderr, "\rpass %d/2: %llu messages, log time %s s   ", pass,
                 static_cast<unsigned long long>(records), Seconds(log_time_ns).c_str());
    std::fflush(stderr);
  };
}

void EndProgress() {
  if (isatty(STDERR_FILENO) != 0) std::fprintf(stderr, "\r%*s\r", 60, "");
}

struct CheckArgs {
  std::string file, urdf;
  ros::BagLoadOptions options;
  std::optional<double> window_s;
};

bool ParseCheckArgs(int argc, char** argv, CheckArgs* args, std::string* error) {
  args->file = argv[3];
  for (int i = 4; i < argc; i += 2) {
    const std::string_view flag = argv[i];
    if (i + 1 >= argc) {
      *error = "option " + std::string(flag) + " needs a value";
      return false;
    }
    const std::string value = argv[i + 1];
    if (flag == "--static") {
      const auto mode = ros::StaticModeFromString(value);
      if (!mode) {
        *error = "--static must be same_body or own_body, got " + value;
        return false;
      }
      args->options.lift.static_mode = *mode;
    } else if (flag == "--bodies") {
      if (!ReadBodiesMap(value, &args->options.lift.bodies, error)) return false;
    } else if (flag == "--urdf") {
      args->urdf = value;
    } else if (flag == "--window") {
      double s = 0;
      if (!ParseCoreNumber(value, &s) || !(s > 0)) {
        *error = "--window must be a positive number of seconds, got " + value;
        return false;
      }
      args->window_s = s;
    } else if (flag == "--pose-topic") {
      const std::size_t eq = value.find('=');
      if (eq == std::string::npos || eq == 0 || eq + 1 == value.size()) {
        *error = "--pose-topic must be TOPIC=FRAME, got " + value;
        return false;
      }
      args->options.lift.pose_topics[value.substr(0, eq)] = value.substr(eq + 1);
    } else if (flag == "--topics") {
      args->options.topics.clear();
      std::stringstream list(value);
      for (std::string t; std::getline(list, t, ',');) args->options.topics.push_back(t);
    } else {
      *error = "unknown option " + std::string(flag);
      return false;
    }
  }
  return true;
}

int Check(int argc, char** argv) {
  CheckArgs args;
  if (std::string error; !ParseCheckArgs(argc, argv, &args, &error)) return UsageError(error);
  args.options.progress = Progress();
  auto scan = ros::ScanBag(args.file, args.options);
  EndProgress();
  if (!scan) {
    std::fprintf(stderr, "semgraph bag check: %s\n", ros::Describe(scan.error()).c_str());
    return 2;
  }
  core::TimeOptions time;  // a window over the whole bag, unless --window
  const std::int64_t span = scan->has_stamps ? scan->last_stamp_ns - scan->first_stamp_ns : 0;
  time.window = args.window_s ? *core::DurationFromSeconds(*args.window_s)
                              : core::Duration::Nanoseconds(span + 1'000'000'000);
  time.interpolation = core::Interpolation::kLinear;  // tf2's
  auto graph = core::SceneGraph<>::Create(time);
  if (!graph) return UsageError(graph.error().message);
  std::optional<models::Robot> robot;
  if (!args.urdf.empty()) {
    auto loaded = models::LoadUrdfFile(*graph, args.urdf);
    if (!loaded) {
      std::fprintf(stderr, "semgraph bag check: %s\n", loaded.error().message.c_str());
      return 2;
    }
    robot = std::move(*loaded);
  }
  auto report = ros::ApplyBag(*graph, args.file, *scan, args.options, robot ? &*robot : nullptr);
  EndProgress();
  if (!report) {
    std::fprintf(stderr, "semgraph bag check: %s\n", ros::Describe(report.error()).c_str());
    return 2;
  }
  for (const ros::FindingGroup& g : report->findings.groups()) {
    std::printf("%s\n", ros::ToJsonLine(g).c_str());
  }
  std::printf(
      "{\"summary\": true, \"messages\": %llu, \"transforms\": %llu, \"findings\": %llu, "
      "\"groups\": %zu}\n",
      static_cast<unsigned long long>(report->messages),
      static_cast<unsigned long long>(report->counts.transforms),
      static_cast<unsigned long long>(report->findings.total()), report->findings.groups().size());
  return report->findings.empty() ? 0 : 1;
}

/// Prints the frame tree: each root, then its children indented, with the lifted body.
void PrintTree(const ros::BagScan& scan, const ros::BodyPlan& plan) {
  std::map<std::string, std::vector<std::pair<std::string, bool>>>
      children;  // parent -> (child, static)
  std::map<std::string, bool> has_parent;
  for (const auto& [edges, is_static] : {std::pair{&scan.statics, true}, {&scan.dynamics, false}}) {
    for (const ros::StaticEdge& e : *edges) {
      if (has_parent[e.child]) continue;  // a second parent: shown once, refused by check
      has_parent[e.child] = true;
      children[e.parent].emplace_back(e.child, is_static);
      has_parent.try_emplace(e.parent, false);
    }
  }
  const ros::BodyPlan::ExistingBody none;
  std::function<void(const std::string&, int, bool, int)> print =
      [&](const std::string& f, int depth, bool is_static, int guard) {
        std::printf("  %*s%s%s  [body %s]\n", depth * 2, "",
                    depth == 0 ? "" : (is_static ? "= " : "~ "), f.c_str(),
                    plan.BodyOf(f, none).c_str());
        if (guard > 1000) return;
        for (const auto& [c, s] : children[f]) print(c, depth + 1, s, guard + 1);
      };
  std::printf("frames (= static, ~ dynamic):\n");
  for (const auto& [f, parent] : has_parent) {
    if (!parent) print(f, 0, false, 0);
  }
}

int Info(int argc, char** argv) {
  if (argc != 4) return UsageError("bag info takes one FILE");
  ros::BagLoadOptions options;
  options.progress = Progress();
  auto scan = ros::ScanBag(argv[3], options);
  EndProgress();
  if (!scan) {
    std::fprintf(stderr, "semgraph bag info: %s\n", ros::Describe(scan.error()).c_str());
    return 2;
  }
  std::printf("file:      %s\nformat:    %s\nmessages:  %llu\n", argv[3],
              std::string(ros::ToString(scan->format)).c_str(),
              static_cast<unsigned long long>(scan->records));
  if (scan->records > 0) {
    std::printf("log time:  %s .. %s s\n", Seconds(scan->first_log_time_ns).c_str(),
                Seconds(scan->last_log_time_ns).c_str());
  }
  if (scan->has_stamps) {
    std::printf("stamps:    %s .. %s s\n", Seconds(scan->first_stamp_ns).c_str(),
                Seconds(scan->last_stamp_ns).c_str());
  }
  std::printf("topics:\n");
  for (const ros::TopicSummary& t : scan->topics) {
    std::printf("  %-24s %-32s %8llu  (%s)\n", t.topic.name.c_str(), t.topic.type_name.c_str(),
                static_cast<unsigned long long>(t.messages),
                std::string(ros::ToString(t.topic.encoding)).c_str());
  }
  auto plan = ros::BodyPlan::Make({});
  for (const ros::StaticEdge& e : scan->statics) plan->AddStatic(e.parent, e.child);
  PrintTree(*scan, *plan);
  return 0;
}

}  // namespace

bool ReadBodiesMap(const std::string& file, ros::BodiesMap* out, std::string* error) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    *error = "cannot read the bodies map " + file;
    return false;
  }
  std::stringstream text;
  text << in.rdbuf();
  auto tree = ParseYaml(text.str());
  if (!tree) {
    *error = file + ": " + tree.error().message;
    return false;
  }
  const NodeView root = tree->At(tree->root());
  if (root.kind != NodeKind::kMap) {
    *error = file + ": the bodies map must be a map {BODY: [frame, ...]}";
    return false;
  }
  for (std::size_t k = 0; k + 1 < root.children.size(); k += 2) {
    const NodeView key = tree->At(root.children[k]);
    const NodeView frames = tree->At(root.children[k + 1]);
    if (key.kind != NodeKind::kScalar || frames.kind != NodeKind::kSequence) {
      *error = file + ": line " + std::to_string(key.location.line) +
               ": each body must map to a list of frame names";
      return false;
    }
    std::vector<std::string>& list = (*out)[std::string(key.text)];
    for (const NodeId f : frames.children) {
      const NodeView frame = tree->At(f);
      if (frame.kind != NodeKind::kScalar) {
        *error = file + ": line " + std::to_string(frame.location.line) + ": not a frame name";
        return false;
      }
      list.emplace_back(frame.text);
    }
  }
  return true;
}

bool IsBagCommand(int argc, char** argv) { return argc >= 2 && std::string_view(argv[1]) == "bag"; }

int RunBagCommand(int argc, char** argv) {
  if (argc == 2 ||
      (argc == 3 && (std::string_view(argv[2]) == "--help" || std::string_view(argv[2]) == "-h"))) {
    std::fputs(kBagUsage.data(), argc == 2 ? stderr : stdout);
    return argc == 2 ? 2 : 0;
  }
  const std::string_view sub = argv[2];
  if (argc < 4) return UsageError("expected bag info FILE or bag check FILE");
  if (sub == "info") return Info(argc, argv);
  if (sub == "check") return Check(argc, argv);
  return UsageError("unknown bag command '" + std::string(sub) + "'");
}

}  // namespace semgraph::script
