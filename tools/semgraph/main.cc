// semgraph: the command-line tool of spec/scene-script.md. Reads a scene script, applies it to a
// scene graph and prints JSON Lines (`run`) or Graphviz DOT (`dot`). Exit 0: every op succeeded;
// 1: an op was rejected or a query failed; 2: malformed script, unreadable file or bad usage.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <string_view>

#include "semgraph/script/scene_script.h"

namespace semgraph::script {
namespace {

constexpr std::string_view kHelp = R"(Usage: semgraph run FILE
       semgraph dot FILE
       semgraph --help

Applies a scene script (YAML) to a semgraph pose/twist scene graph.

  run FILE   apply the ops in order; print one JSON object per op on stdout (JSON Lines)
  dot FILE   apply the ops, then print the resulting graph as Graphviz DOT on stdout: each
             body a cluster holding its frames {f} and a box for the body, pose edges solid
             (tail frame -> head frame), twist edges dashed (reference body -> head frame).
             Rejected ops and failed queries are printed as JSON lines on stderr.
  FILE       a path, or - for standard input

Exit status:
  0  every op succeeded
  1  an op was rejected or a query failed (all ops are still attempted and reported)
  2  the script is malformed (bad YAML, unknown op or field, missing or mistyped field, a field
     of another op, wrong array length, non-numeric number, unknown representation, rotation
     without exactly one form), FILE cannot be read, or the command line is wrong. stderr then
     says FILE:LINE:COLUMN: what is wrong; nothing is applied and nothing is printed on stdout.

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

Output, one line per op:
  {"op": i, "ok": true}
  {"op": i, "ok": false, "error": "<code>", "message": "<text>"}
  pose              {"op": i, "ok": true, "position": [x,y,z], "quaternion": [w,x,y,z]}
  position          {"op": i, "ok": true, "position": [x,y,z]}
  orientation       {"op": i, "ok": true, "quaternion": [w,x,y,z]}
  twist             {"op": i, "ok": true, "linear": [vx,vy,vz], "angular": [wx,wy,wz]}
  linear_velocity   {"op": i, "ok": true, "linear": [vx,vy,vz]}
  angular_velocity  {"op": i, "ok": true, "angular": [wx,wy,wz]}
  Quaternions have w >= 0; numbers have 17 significant digits. Error codes (snake_case) and
  the rules behind them: spec/scene-graph.md.

Limits: a script of at most 16 MiB, YAML nested at most 64 levels deep.
)";

enum class Mode { kRun, kDot };

int Usage(std::string_view problem) {
  std::fprintf(stderr,
               "semgraph: %.*s\nUsage: semgraph run FILE | semgraph dot FILE | "
               "semgraph --help\n",
               static_cast<int>(problem.size()), problem.data());
  return kExitMalformed;
}

// One line and its newline; false (errno set) when the stream refuses it.
bool PrintLine(std::FILE* stream, const std::string& line) {
  return std::fwrite(line.data(), 1, line.size(), stream) == line.size() &&
         std::fputc('\n', stream) != EOF;
}

int Main(int argc, char** argv) {
  if (argc == 2 && (std::string_view(argv[1]) == "--help" || std::string_view(argv[1]) == "-h")) {
    std::fwrite(kHelp.data(), 1, kHelp.size(), stdout);
    return std::fflush(stdout) == 0 ? kExitOk : kExitOutputFailed;
  }
  if (argc != 3) return Usage("expected a command and a FILE");
  const std::string_view command = argv[1];
  Mode mode;
  if (command == "run") {
    mode = Mode::kRun;
  } else if (command == "dot") {
    mode = Mode::kDot;
  } else {
    return Usage("unknown command '" + std::string(command) + "'");
  }
  // The JSON lines are printed as the ops run, so that output starts at once and a large
  // script is never held twice; a failed write stops the run (nobody would see the rest).
  int write_errno = 0;
  RunOptions options;
  options.dot = mode == Mode::kDot;
  options.on_op = [&](const OpResult& result) {
    if (mode == Mode::kDot) {
      if (!result.ok) PrintLine(stderr, result.json);  // stdout carries only the DOT text
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
  if (write_errno == 0 && mode == Mode::kDot &&
      std::fwrite(run.dot.data(), 1, run.dot.size(), stdout) != run.dot.size()) {
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
