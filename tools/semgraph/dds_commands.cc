// semgraph serve / echo / monitor / dot --live (dds_commands.h; docs/distributed.md).
#include "dds_commands.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "live_command.h"
#include "script_runner.h"
#include "semgraph/dds/mirror.h"
#include "semgraph/dds/publisher.h"
#include "semgraph/script/scene_script.h"

namespace semgraph::script {
namespace {

using Clock = std::chrono::steady_clock;

constexpr std::string_view kDdsUsage = R"(Usage: semgraph serve FILE [--owner NAME] [OPTIONS]
       semgraph echo pose OF WRT [COORD] [--count N] [OPTIONS]
       semgraph echo twist POINT REF_BODY COORD [--count N] [OPTIONS]
       semgraph monitor [OPTIONS]
       semgraph dot --live [OPTIONS]

  serve    apply the scene script FILE and publish its scene as owner NAME (default: the
           file's stem) until stopped (Ctrl-C) or --seconds pass
  echo     mirror the shared scene and print the query's answer as a JSON line each time it
           changes (like tf2_echo); --count N stops after N lines
  monitor  print, every second, each mirrored edge's publisher, update rate, delay (publisher
           stamp to arrival) and age, the publishers' liveliness and the refused relations
  dot --live  print the mirrored graph as Graphviz DOT once the mirror has caught up

Options:
  --domain N     DDS domain id (default: CYCLONEDDS_URI's, else 0)
  --seconds S    stop after S seconds (echo, monitor, dot --live: wait at most S; default 10
                 for dot --live, unlimited otherwise)
Configure DDS with CYCLONEDDS_URI (interfaces, peers): docs/distributed.md.
)";

struct Args {
  std::vector<std::string> positional;
  std::uint32_t domain = dds::kDefaultDomain;
  double seconds = -1;
  long count = -1;
  std::string owner;
  bool live = false;
  std::string error;
};

Args Parse(int argc, char** argv) {
  Args a;
  for (int i = 2; i < argc; ++i) {
    const std::string_view s = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) {
        a.error = "option " + std::string(s) + " needs a value";
        return nullptr;
      }
      return argv[++i];
    };
    if (s == "--domain") {
      if (const char* v = value())
        a.domain = static_cast<std::uint32_t>(std::strtoul(v, nullptr, 10));
    } else if (s == "--seconds") {
      if (const char* v = value()) a.seconds = std::strtod(v, nullptr);
    } else if (s == "--count") {
      if (const char* v = value()) a.count = std::strtol(v, nullptr, 10);
    } else if (s == "--owner") {
      if (const char* v = value()) a.owner = v;
    } else if (s == "--live") {
      a.live = true;
    } else if (s.size() > 1 && s[0] == '-' && s != "-") {
      a.error = "unknown option " + std::string(s);
    } else {
      a.positional.emplace_back(s);
    }
  }
  return a;
}

int Usage(const std::string& problem) {
  std::fprintf(stderr, "semgraph: %s\n%.*s", problem.c_str(), static_cast<int>(kDdsUsage.size()),
               kDdsUsage.data());
  return kExitMalformed;
}

int Serve(const Args& a) {
  if (a.positional.size() != 1) return Usage("serve needs one FILE");
  const std::string& path = a.positional[0];
  core::SceneGraph<> graph;
  RunOptions options;
  options.on_op = [](const OpResult& r) {
    std::printf("%s\n", r.json.c_str());
    return true;
  };
  const SceneRun run = LoadSceneFile(path, graph, options);
  if (run.status == kExitMalformed) {
    std::fprintf(stderr, "%s\n", run.error.c_str());
    return kExitMalformed;
  }
  std::string owner = a.owner;
  if (owner.empty()) {
    const std::size_t slash = path.find_last_of('/');
    owner = path.substr(slash == std::string::npos ? 0 : slash + 1);
    owner = owner.substr(0, owner.find('.'));
    if (owner.empty() || owner == "-") owner = "serve";
  }
  auto pub = dds::Publisher::Create(graph, {owner, a.domain});
  if (!pub) {
    std::fprintf(stderr, "semgraph: %s\n", pub.error().c_str());
    return kExitMalformed;
  }
  if (auto ok = (*pub)->PublishStructure(); !ok) {
    std::fprintf(stderr, "semgraph: %s\n", ok.error().c_str());
    return kExitMalformed;
  }
  std::printf("{\"serving\": %s, \"pose_edges\": %zu, \"twist_edges\": %zu}\n",
              JsonString(owner).c_str(), graph.num_pose_edges(), graph.num_twist_edges());
  std::fflush(stdout);
  const auto start = Clock::now();
  while (!live::TimeUp(start, a.seconds)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return run.status;
}

std::string Vec(const Eigen::Vector3d& v) {
  return "[" + JsonNumber(v.x()) + ", " + JsonNumber(v.y()) + ", " + JsonNumber(v.z()) + "]";
}

int Echo(const Args& a) {
  const auto& p = a.positional;
  const bool pose = !p.empty() && p[0] == "pose" && (p.size() == 3 || p.size() == 4);
  const bool twist = !p.empty() && p[0] == "twist" && p.size() == 4;
  if (!pose && !twist) return Usage("echo needs: pose OF WRT [COORD] | twist POINT REF_BODY COORD");
  std::atomic<bool> changed{true};
  dds::MirrorOptions options;
  options.name = "echo";
  options.domain = a.domain;
  options.on_change = [&] { changed.store(true); };
  auto mirror = dds::Mirror::Create(options);
  if (!mirror) {
    std::fprintf(stderr, "semgraph: %s\n", mirror.error().c_str());
    return kExitMalformed;
  }
  const auto start = Clock::now();
  std::string last;
  long printed = 0;
  while (!live::TimeUp(start, a.seconds) && (a.count < 0 || printed < a.count)) {
    if (!changed.exchange(false)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      continue;
    }
    std::string line;
    (*mirror)->WithGraph([&](const core::SceneGraph<>& g) {
      if (pose) {
        core::PoseSpec spec = core::PoseSpec::Of(p[1]).RelativeTo(p[2]);
        if (p.size() == 4) spec.ExpressedIn(p[3]);
        auto X = g.GetPose(spec);
        if (!X) {
          if (X.error().code != base::ErrorCode::kUnknownFrame) {
            line = "{\"ok\": false, \"error\": " + JsonString(base::ToString(X.error().code)) +
                   ", \"message\": " + JsonString(g.Describe(X.error(), spec)) + "}";
          }
          return;
        }
        Eigen::Quaterniond q = X->value.rotation;
        if (q.w() < 0) q.coeffs() = -q.coeffs();
        line = "{\"ok\": true, \"position\": " + Vec(X->value.translation) + ", \"quaternion\": [" +
               JsonNumber(q.w()) + ", " + JsonNumber(q.x()) + ", " + JsonNumber(q.y()) + ", " +
               JsonNumber(q.z()) + "]}";
      } else {
        const core::TwistSpec spec = core::TwistSpec::Of(p[1]).RelativeTo(p[2]).ExpressedIn(p[3]);
        auto V = g.GetTwist(spec);
        if (!V) {
          if (V.error().code != base::ErrorCode::kUnknownFrame &&
              V.error().code != base::ErrorCode::kUnknownBody) {
            line = "{\"ok\": false, \"error\": " + JsonString(base::ToString(V.error().code)) +
                   ", \"message\": " + JsonString(g.Describe(V.error(), spec)) + "}";
          }
          return;
        }
        line = "{\"ok\": true, \"linear\": " + Vec(V->linear) +
               ", \"angular\": " + Vec(V->angular) + "}";
      }
    });
    if (line.empty() || line == last) continue;
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
    last = line;
    ++printed;
  }
  return printed > 0 ? kExitOk : kExitOpFailed;
}

int Monitor(const Args& a) {
  auto mirror = dds::Mirror::Create({"monitor", a.domain, {}, {}, {}, {}});
  if (!mirror) {
    std::fprintf(stderr, "semgraph: %s\n", mirror.error().c_str());
    return kExitMalformed;
  }
  const auto start = Clock::now();
  std::map<std::string, std::uint64_t> previous;
  auto last = Clock::now();
  while (!live::TimeUp(start, a.seconds)) {
    std::this_thread::sleep_for(std::chrono::seconds(1));
    const auto now = Clock::now();
    const double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    const std::int64_t now_ns = dds::NowNs();
    std::printf("%-16s %-6s %-28s %10s %12s %10s\n", "publisher", "kind", "edge", "rate_hz",
                "delay_us", "age_ms");
    for (const dds::EdgeState& e : (*mirror)->Edges()) {
      const char* kind = e.wrench ? "wrench" : e.joint ? "joint" : e.twist ? "twist" : "pose";
      const std::string key = std::string(kind) + ":" + e.head;
      const double rate = (e.received - previous[key]) / dt;
      previous[key] = e.received;
      const std::string edge = e.head + " <- " + e.tail;
      const double delay_us =
          e.last_stamp_ns > 0 ? (e.last_receive_ns - e.last_stamp_ns) / 1e3 : 0.0;
      const double age_ms = e.last_receive_ns > 0 ? (now_ns - e.last_receive_ns) / 1e6 : -1.0;
      std::printf("%-16s %-6s %-28s %10.1f %12.1f %10.1f\n", e.owner.c_str(), kind, edge.c_str(),
                  rate, delay_us, age_ms);
    }
    for (const dds::OwnerState& o : (*mirror)->Owners()) {
      std::printf("publisher %s: %s, revision %llu, %zu elements\n", o.owner.c_str(),
                  o.alive ? "alive" : "gone", static_cast<unsigned long long>(o.revision),
                  o.elements);
    }
    for (const dds::Report& r : (*mirror)->Refusals())
      std::printf("refused (%s): %s\n", r.code.c_str(), r.message.c_str());
    std::printf("\n");
    std::fflush(stdout);
  }
  return kExitOk;
}

int DotLive(const Args& a) {
  auto mirror = dds::Mirror::Create({"dot", a.domain, {}, {}, {}, {}});
  if (!mirror) {
    std::fprintf(stderr, "semgraph: %s\n", mirror.error().c_str());
    return kExitMalformed;
  }
  const double seconds = a.seconds >= 0 ? a.seconds : 10.0;
  const bool caught_up =
      (*mirror)->WaitUntil([&] { return live::StopRequested() || (*mirror)->CaughtUp(); },
                           std::chrono::milliseconds(static_cast<long>(seconds * 1000)));
  std::string dot;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& g) { dot = WriteDot(g); });
  std::fwrite(dot.data(), 1, dot.size(), stdout);
  if (!caught_up)
    std::fprintf(stderr, "semgraph: no complete scene on the domain within %g s\n", seconds);
  return caught_up ? kExitOk : kExitOpFailed;
}

}  // namespace

bool IsDdsCommand(int argc, char** argv) {
  if (argc < 2) return false;
  const std::string_view c = argv[1];
  if (c == "serve" || c == "echo" || c == "monitor") return true;
  return c == "dot" && live::HasFlag(argc, argv, "--live");
}

int RunDdsCommand(int argc, char** argv) {
  if (live::PrintedHelp(argc, argv, kDdsUsage)) return kExitOk;
  const Args a = Parse(argc, argv);
  if (!a.error.empty()) return Usage(a.error);
  live::StopOnSignals();
  const std::string_view c = argv[1];
  if (c == "serve") return Serve(a);
  if (c == "echo") return Echo(a);
  if (c == "monitor") return Monitor(a);
  if (!a.positional.empty()) return Usage("dot --live takes no FILE");
  return DotLive(a);
}

}  // namespace semgraph::script
