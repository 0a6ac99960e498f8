// semgraph: the command-line tool of docs/scene-script.md, a thin main over the library
// semgraph::script (semgraph/script/scene_script.h). Reads a scene script, applies it to a
// scene graph and prints JSON Lines (`run`), Graphviz DOT (`dot`) or the resulting graph as a
// scene script that rebuilds it (`export`). Exit 0: every op
// succeeded; 1: an op was rejected or a query failed; 2: malformed script, unreadable file,
// out of memory or bad usage; 3: the output could not be written.
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <initializer_list>
#include <new>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>

#include "semgraph/ellipse_writer.h"
#include "semgraph/script/scene_script.h"
#if SEMGRAPH_WITH_DDS
#include "dds_commands.h"  // serve, echo, monitor, dot --live
#endif
#if SEMGRAPH_WITH_ROS
#include "bag_commands.h"  // bag info, bag check
#endif
#if SEMGRAPH_WITH_ROS_DDS
#include "ros_live_commands.h"  // echo --ros, check --ros, serve --ros
#endif

namespace semgraph::script {
namespace {

constexpr std::string_view kUsage = R"(Usage: semgraph run FILE
       semgraph dot FILE
       semgraph export FILE
       semgraph ellipses FILE --root FRAME [--plane xy|xz|yz] [--sigma S]
       semgraph --help | --version
       semgraph run --help | semgraph dot --help | semgraph export --help
       semgraph serve | echo | monitor | dot --live ... (with DDS; semgraph serve --help)
       semgraph bag info FILE | semgraph bag check FILE ... (ROS bags; semgraph bag --help)
       semgraph echo --ros | check --ros | serve --ros ... (live ROS 2; semgraph check --ros --help)
)";

constexpr std::string_view kRun = R"(
  run FILE   apply the ops in order; print one JSON object per op on stdout (JSON Lines)
)";

constexpr std::string_view kDot = R"(
  dot FILE   apply the ops, then print the resulting graph as Graphviz DOT on stdout: each
             body a cluster holding its frames {f} and a box for the body, pose edges solid
             (tail frame -> head frame), twist edges dashed (reference body -> head frame).
             Rejected ops and failed queries are printed as JSON lines on stderr.
             Render it with Graphviz, e.g. semgraph dot FILE | dot -Tsvg > scene.svg
)";

constexpr std::string_view kExport = R"(
  export FILE
             apply the ops, then print the resulting graph as a scene script that rebuilds
             it: `semgraph run` of the output gives the same names, ids, edges and values
             (17 significant digits), e.g. to save a scene built by a longer script, with its
             updates and removals, as its final state. Queries leave no trace in it.
             Rejected ops and failed queries are printed as JSON lines on stderr.
)";

constexpr std::string_view kEllipses = R"(
  ellipses FILE --root FRAME [--plane xy|xz|yz] [--sigma S]
             apply the ops, then print SVG: for every frame connected to FRAME, its origin's
             position relative to FRAME's, in [FRAME], with the covariance the edges' covariances
             give it (docs/uncertainty.md), projected on the plane (default xy) and drawn as
             the S-sigma ellipse (default 1) at the frame's position, labelled {frame}.
             Rejected ops and failed queries are printed as JSON lines on stderr.
)";

constexpr std::string_view kFileAndExit = R"(
  FILE       a path, or - for standard input

Exit status:
  0  every op succeeded
  1  an op was rejected or a query failed (all ops are still attempted and reported)
  2  the script is malformed (bad YAML, not UTF-8, unknown op or field, missing or mistyped
     field, a field of another op, wrong array length, non-numeric number, unknown
     representation, rotation without exactly one form, over a limit), FILE cannot be read,
     memory ran out, or the command line is wrong. stderr then says FILE:LINE:COLUMN: what is
     wrong; a malformed script applies nothing and prints nothing on stdout.
  3  the output could not be written (a full disk, a closed stdout): the run stops, and
     stderr says "semgraph: cannot write the output: <reason>".
)";

constexpr std::string_view kScript = R"(
Script:
  representation: quaternion      # optional: quaternion (default) | homogeneous
  ops:                            # applied in order; op i of the output counts from 0
    - {op: body, name: B}
    - {op: frame, name: b, body: B}
    - {op: pose, of: c, body: C, wrt: b, position: [1, 0, 0.5], rotation: {rpy: [0, 0, 0.3]}}
    - {op: twist, point: c, ref_body: B, coord: b, linear: [0.1, 0, 0], angular: [0, 0, 0.2]}
    - {op: query, kind: pose, of: c, wrt: b}
    - {op: query, kind: twist, point: c, body: C, ref_body: B, coord: c}
    - {op: remove, kind: twist, point: c, ref_body: B}
    - {op: remove, kind: pose, of: c, wrt: b}

Ops and their fields:
  body                      name
  frame                     name, body (a missing body is the op error frame_without_body)
  pose                      point, orientation, body, ref_point, ref_orientation, ref_body,
                            coord; position, rotation. Adds the pose, or updates the value of
                            the existing edge (an edge inside one body is constant).
  twist                     point, body, ref_body, coord; linear, angular. Adds or updates.
  remove, kind: pose        of, wrt (the edge's head and tail frames)
  remove, kind: twist       point, ref_body
  query, kind: pose         point, orientation, body, ref_point, ref_orientation, ref_body, coord
  query, kind: position     point, body, ref_point, ref_body, coord
  query, kind: orientation  orientation, body, ref_orientation, ref_body, coord
  query, kind: twist        point, body, ref_body, coord
  query, kind: linear_velocity    point, body, ref_body, coord
  query, kind: angular_velocity   body, ref_body, coord
  Shorthand (pose ops, pose/position/orientation queries): of: X sets point = orientation = X;
  wrt: Y sets ref_point = ref_orientation = coord = Y; explicit fields override it.
  body and ref_body may be omitted when the frames exist (they are checked when given); frames
  and bodies named by a pose or twist that do not exist yet are created. A twist's body
  defaults to the body of its point's frame; point, ref_body and coord are required.

Values (metres, radians, seconds):
  position: [x, y, z]                              default [0, 0, 0]
  rotation: exactly one of                         default identity
    {quaternion: [w, x, y, z]}
    {rpy: [roll, pitch, yaw]}                      R = Rz(yaw) Ry(pitch) Rx(roll)
    {matrix: [[r00, r01, r02], [r10, r11, r12], [r20, r21, r22]]}   rows as written
  linear: [vx, vy, vz], angular: [wx, wy, wz]      default [0, 0, 0]
  .nan and .inf are YAML numbers; the scene graph rejects them (invalid_number), as it rejects
  non-unit quaternions and improper matrices (invalid_rotation).

Time (seconds; kept as whole nanoseconds):
  time: {window: 10, interpolation: screw | linear, duplicate_stamp: replace | reject}
                            optional top-level map, each key optional (a window that is not a
                            finite positive time is a malformed script)
  stamp: t                  on pose, twist, joints and wrench ops: the value is a sample at t
  at: t | latest_common     on queries (none: each edge's newest sample)
  max_extrapolation: h      on queries: allow t up to h outside an edge's samples
  not_before: t             on queries: fail with stale if a used edge has nothing since t
  ref_at: t2, fixed: f      pose/position/orientation queries: the reference side at t2,
                            through frame f (time travel; both, with a numeric at)
  source: twists | poses    twist/linear_velocity/angular_velocity queries
  A time field on an op that does not take it is a malformed script; a non-finite or
  out-of-range time, or a negative horizon, is the op error invalid_number.

)";

constexpr std::string_view kOutput = R"(
Output, one line per op (i counts ops from 0; K is the op, e.g. "body", "remove twist",
"query position"; L is the op's line in the script):
  {"op": i, "ok": true, "kind": K, "line": L}
  {"op": i, "ok": false, "error": "<code>", "message": "<text>", "kind": K, "line": L}
  query pose              {"op": i, "ok": true, "position": [x,y,z], "quaternion": [w,x,y,z], ...}
  query position          {"op": i, "ok": true, "position": [x,y,z], ...}
  query orientation       {"op": i, "ok": true, "quaternion": [w,x,y,z], ...}
  query twist             {"op": i, "ok": true, "linear": [vx,vy,vz], "angular": [wx,wy,wz], ...}
  query linear_velocity   {"op": i, "ok": true, "linear": [vx,vy,vz], ...}
  query angular_velocity  {"op": i, "ok": true, "angular": [wx,wy,wz], ...}
  (each ending in "kind" and "line"). A query that asked a time or read stamped data adds
  the keys that apply: "time", "ref_time", "oldest", "newest" (seconds), "extrapolated": true.
  Quaternions have w >= 0; numbers have 17 significant
  digits. Error codes (snake_case), the rules behind them, and the whole format:
  docs/scene-script.md in the semgraph sources.
)";

constexpr std::string_view kLimits = R"(
Limits: a script of at most 16 MiB of UTF-8, YAML nested at most 64 levels deep, at most
32 MiB with its aliases expanded; names longer than 255 bytes are cut in messages.
)";

constexpr std::string_view kMore = R"(
The script format: semgraph --help, or docs/scene-script.md in the semgraph sources.
)";

enum class Mode { kRun, kDot, kExport };

int Usage(std::string_view problem) {
  std::fprintf(stderr,
               "semgraph: %.*s\nUsage: semgraph run FILE | semgraph dot FILE | "
               "semgraph export FILE | semgraph --help | semgraph --version\n",
               static_cast<int>(problem.size()), problem.data());
  return kExitMalformed;
}

// One line and its newline; false (errno set) when the stream refuses it.
bool PrintLine(std::FILE* stream, const std::string& line) {
  return std::fwrite(line.data(), 1, line.size(), stream) == line.size() &&
         std::fputc('\n', stream) != EOF;
}

// Writes the texts to stdout: kExitOk, or kExitOutputFailed (with the message) if it cannot.
int Print(std::initializer_list<std::string_view> texts) {
  for (const std::string_view text : texts) std::fwrite(text.data(), 1, text.size(), stdout);
  if (std::fflush(stdout) == 0 && !std::ferror(stdout)) return kExitOk;
  std::fprintf(stderr, "semgraph: cannot write the output: %s\n", std::strerror(errno));
  return kExitOutputFailed;
}

// `semgraph ellipses FILE --root FRAME [--plane P] [--sigma S]` (ellipse_writer.h).
int Ellipses(int argc, char** argv) {
  EllipseOptions options;
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string_view flag = argv[i], value = argv[i + 1];
    if (flag == "--root") {
      options.root = value;
    } else if (flag == "--plane" && (value == "xy" || value == "xz" || value == "yz")) {
      options.plane = value == "xy" ? EllipsePlane::kXY
                                    : (value == "xz" ? EllipsePlane::kXZ : EllipsePlane::kYZ);
    } else if (flag == "--sigma") {
      char* end = nullptr;
      options.sigma = std::strtod(argv[i + 1], &end);
      if (end == argv[i + 1] || *end != '\0') options.sigma = -1;  // refused below
    } else {
      return Usage("ellipses: unknown option '" + std::string(flag) + " " + std::string(value) +
                   "' (--root FRAME, --plane xy|xz|yz, --sigma S)");
    }
  }
  if (argc < 5 || argc % 2 == 0 || options.root.empty()) {
    return Usage("ellipses needs FILE and --root FRAME");
  }
  std::string text, reason;
  const std::string path = argv[2];
  if (!ReadScriptFile(path, &text, &reason)) {
    std::fprintf(stderr, "%s: cannot read: %s\n", path.c_str(), reason.c_str());
    return kExitMalformed;
  }
  RunOptions run_options;
  run_options.display_name = path == "-" ? "<stdin>" : path;
  run_options.on_op = [](const OpResult& r) {
    if (!r.ok) PrintLine(stderr, r.json);  // stdout carries only the SVG
    return true;
  };
  const BuiltScene built = BuildScene(text, run_options);
  if (built.run.status == kExitMalformed) {
    PrintLine(stderr, built.run.error);
    return kExitMalformed;
  }
  const auto svg = std::visit(
      [&](const auto& g) -> base::Expected<std::string, std::string> {
        if constexpr (std::is_same_v<std::decay_t<decltype(g)>, std::monostate>) {
          return base::Unexpected{std::string("no scene was built")};
        } else {
          return WriteEllipses(g, options);
        }
      },
      built.graph);
  if (!svg) {
    std::fprintf(stderr, "semgraph: ellipses: %s\n", svg.error().c_str());
    return kExitMalformed;
  }
  const int printed = Print({*svg});
  return printed != kExitOk ? printed : built.run.status;
}

int Main(int argc, char** argv) {
  const auto is_help = [](std::string_view arg) { return arg == "--help" || arg == "-h"; };
  if (argc == 2 && is_help(argv[1])) {
    return Print({kUsage, kRun, kDot, kExport, kEllipses, kFileAndExit, kScript, kOutput, kLimits});
  }
  if (argc == 2 && std::string_view(argv[1]) == "--version") {
    return Print({"semgraph " SEMGRAPH_VERSION "\n"});
  }
  // `semgraph run --help`: the command's help, not a file named --help (./--help is one).
  if (argc == 3 && is_help(argv[2])) {
    if (std::string_view(argv[1]) == "run") {
      return Print({"Usage: semgraph run FILE\n", kRun, kFileAndExit, kOutput, kLimits, kMore});
    }
    if (std::string_view(argv[1]) == "dot") {
      return Print({"Usage: semgraph dot FILE\n", kDot, kFileAndExit, kLimits, kMore});
    }
    if (std::string_view(argv[1]) == "export") {
      return Print({"Usage: semgraph export FILE\n", kExport, kFileAndExit, kLimits, kMore});
    }
  }
  if (argc >= 2 && std::string_view(argv[1]) == "ellipses") {
    if (argc == 3 && is_help(argv[2])) {
      return Print({"Usage: semgraph ellipses FILE --root FRAME [--plane xy|xz|yz] [--sigma S]\n",
                    kEllipses, kFileAndExit, kLimits, kMore});
    }
    return Ellipses(argc, argv);
  }
#if SEMGRAPH_WITH_ROS_DDS
  if (IsRosLiveCommand(argc, argv)) return RunRosLiveCommand(argc, argv);
#endif
#if SEMGRAPH_WITH_DDS
  if (IsDdsCommand(argc, argv)) return RunDdsCommand(argc, argv);
#endif
#if SEMGRAPH_WITH_ROS
  if (IsBagCommand(argc, argv)) return RunBagCommand(argc, argv);
#endif
  if (argc != 3) return Usage("expected a command and a FILE");
  const std::string_view command = argv[1];
  Mode mode;
  if (command == "run") {
    mode = Mode::kRun;
  } else if (command == "dot") {
    mode = Mode::kDot;
  } else if (command == "export") {
    mode = Mode::kExport;
  } else {
    return Usage("unknown command '" + std::string(command) + "'");
  }
  // The JSON lines are printed as the ops run, so that output starts at once and a large
  // script is never held twice; a failed write stops the run (nobody would see the rest).
  int write_errno = 0;
  RunOptions options;
  options.dot = mode == Mode::kDot;
  options.scene = mode == Mode::kExport;
  options.on_op = [&](const OpResult& result) {
    if (mode != Mode::kRun) {
      if (!result.ok) PrintLine(stderr, result.json);  // stdout carries only the DOT / script
      return true;
    }
    if (PrintLine(stdout, result.json)) return true;
    write_errno = errno;
    return false;
  };
  const SceneRun run = RunSceneFile(argv[2], options);
  if (run.status == kExitMalformed) {
    PrintLine(stderr, run.error);
    return kExitMalformed;
  }
  const std::string& text = mode == Mode::kDot ? run.dot : run.scene;
  if (write_errno == 0 && mode != Mode::kRun &&
      std::fwrite(text.data(), 1, text.size(), stdout) != text.size()) {
    write_errno = errno;
  }
  if (write_errno == 0 && std::fflush(stdout) != 0) write_errno = errno;
  if (write_errno != 0) {
    std::fprintf(stderr, "semgraph: cannot write the output: %s\n", std::strerror(write_errno));
    return kExitOutputFailed;
  }
  return run.status;
}

}  // namespace
}  // namespace semgraph::script

int main(int argc, char** argv) {
  // The library reports running out of memory itself (with the file and the op); this catches
  // what is left, e.g. building a message.
  try {
    return semgraph::script::Main(argc, argv);
  } catch (const std::bad_alloc&) {
    std::fputs("semgraph: out of memory\n", stderr);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "semgraph: %s\n", e.what());
  }
  return semgraph::script::kExitMalformed;
}
