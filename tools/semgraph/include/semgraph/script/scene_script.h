// File: semgraph/script/scene_script.h (library semgraph::script)
//
// Scene scripts from C++: the calls behind the `semgraph` command-line tool, with the same
// results. A scene script is the YAML format of docs/scene-script.md; each op gives one result,
// whose `json` is exactly the line `semgraph run` prints for it.
//
//   RunScene(text)            = `semgraph run`: a fresh graph of the script's representation
//   BuildScene(text)          the same, handing the final graph over (Python's run_script)
//   LoadScene(text, graph)    applies the script to a graph of yours (and leaves it there)
//   RunSceneFile / LoadSceneFile   the same from a file
//   WriteScene(graph)         the graph as a script that rebuilds it (`semgraph export`)
//
// Contract, as the tool's: the whole script is read and checked before anything is applied; a
// malformed one (status kExitMalformed) applies nothing and `error` says FILE:LINE:COLUMN: what
// is wrong. Otherwise every op is applied in order, even after a rejected one (status
// kExitOpFailed then), and a rejected op leaves the graph unchanged (the scene graph's
// atomicity). Running out of memory is reported, not thrown: status kExitMalformed and
// "out of memory ..." in `error`; the graph then holds every op before the failing one, and
// the failing op may be partly applied.
//
// LoadScene ignores the script's `representation` and `time` map (the graph's backend and time
// options decide); RunScene and BuildScene use both. Costs: O(script) to read, then one
// scene-graph call per op. Thread safety: the calls share nothing; a graph passed in must not be
// used by another thread meanwhile.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/script/export.h"

namespace semgraph::script {

/// Exit statuses of the tool, and `SceneRun::status`.
inline constexpr int kExitOk = 0;            // every op succeeded
inline constexpr int kExitOpFailed = 1;      // an op was rejected or a query failed
inline constexpr int kExitMalformed = 2;     // malformed or unreadable script, out of memory
inline constexpr int kExitOutputFailed = 3;  // the tool could not write its output (CLI only)

/// What one op did.
struct OpResult {
  std::size_t index = 0;  // 0-based position in the script's ops
  bool ok = false;
  std::string error;  // the snake_case error code when !ok ("duplicate_body", ...), else empty
  std::string json;   // the tool's JSON line for the op (no newline)
  std::string kind;   // "body", "frame", "pose", "twist", "remove pose", "query position", ...
  int line = 0;       // the op's line in the script (1-based)
};

struct SceneRun {
  int status = kExitOk;
  std::string error;  // status kExitMalformed: "FILE:LINE:COLUMN: message"
  // A malformed script, apart: the 1-based line and column of the node at fault and the message
  // without its place. 0, 0 and "" when no place in the script is at fault (an unreadable file,
  // out of memory).
  int error_line = 0;
  int error_column = 0;
  std::string error_message;
  bool out_of_memory = false;  // status kExitMalformed because memory ran out (see error)
  std::vector<OpResult> ops;   // one per op applied, in order (unless on_op took them)
  std::string dot;             // RunOptions::dot: the final graph in Graphviz DOT
  std::string scene;           // RunOptions::scene: the final graph as a script (WriteScene)
};

struct RunOptions {
  /// The name used in `error` ("FILE" above).
  std::string display_name = "<script>";
  /// Also render the final graph (RunScene*: into SceneRun::dot).
  bool dot = false;
  /// Also write the final graph as a scene script (RunScene*: into SceneRun::scene).
  bool scene = false;
  /// When set, each result is handed here as soon as its op is applied, instead of being kept
  /// in SceneRun::ops; returning false stops the run (the remaining ops are not applied).
  std::function<bool(const OpResult&)> on_op;
  /// The folder a relative `urdf` file is read from; empty: the working folder. The *File
  /// calls set it to the script's folder when it is empty (not for standard input).
  std::string base_dir;
};

/// `semgraph run` on a script held in memory.
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT SceneRun RunScene(std::string_view text,
                                                       const RunOptions& options = {});
/// The same on a file ("-" reads standard input); an unreadable file is status kExitMalformed
/// with "FILE: cannot read: <reason>". display_name defaults to the path (<stdin> for "-").
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT SceneRun RunSceneFile(const std::string& path,
                                                           RunOptions options = {});

/// A graph of either backend, as a script's `representation` picks it; empty before one is made.
using AnySceneGraph = std::variant<std::monostate, core::SceneGraph<coord::QuaternionBackend>,
                                   core::SceneGraph<coord::HomogeneousBackend>>;

/// RunScene's results and the graph it built.
struct BuiltScene {
  SceneRun run;
  /// The fresh graph (the script's representation and time options) after the ops; empty when
  /// the script is malformed. Out of memory: the ops before the failing one (the contract above).
  AnySceneGraph graph;
};

/// `semgraph run` on a script held in memory, handing the final graph over instead of dropping
/// it (to query it further). RunScene(text, options) is BuildScene(text, options).run.
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT BuiltScene BuildScene(std::string_view text,
                                                           const RunOptions& options = {});

/// Applies a script to `graph`. RunOptions::dot and ::scene are ignored (see WriteDot,
/// WriteScene).
template <coord::Backend B>
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT SceneRun LoadScene(std::string_view text,
                                                        core::SceneGraph<B>& graph,
                                                        const RunOptions& options = {});
template <coord::Backend B>
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT SceneRun LoadSceneFile(const std::string& path,
                                                            core::SceneGraph<B>& graph,
                                                            RunOptions options = {});

/// The graph in Graphviz DOT, as `semgraph dot` prints it: bodies as clusters holding their
/// frames, pose edges solid (tail frame -> head frame), twist edges dashed (reference body ->
/// head frame). Deterministic; names appear only in escaped labels.
template <coord::Backend B>
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT std::string WriteDot(const core::SceneGraph<B>& graph);

/// The graph as a scene script (YAML, docs/scene-script.md) that rebuilds it: running the text
/// on a fresh graph of the same backend (RunScene, LoadScene, `semgraph run`) gives a graph
/// with the same names, bodies and frames under the same ids, the same pose and twist edges and
/// the same values bit for bit (Dump of scene_graph_debug.h is identical), for every graph built
/// through the public calls. Save and load: write the text to a file, LoadSceneFile it later.
/// The script has `body` and `frame` ops, each pose edge once in edge form (position and the
/// stored rotation: a quaternion [w, x, y, z], or the matrix for the homogeneous backend) and
/// each twist edge once as its stored screw twist (coord = its head frame), with numbers in 17
/// significant digits; where the order of ids needs it, an edge creates its frames or an edge
/// added and removed at once does. Time is not written: a stamped edge is written with its
/// newest value and no stamp (the current state, no history; docs/scene-script.md, Export).
/// Cost: O(graph) text. Thread safety: reads the graph only.
template <coord::Backend B>
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT std::string WriteScene(const core::SceneGraph<B>& graph);

/// Reads a script file ("-": standard input) without holding more than one byte beyond the
/// script size limit (16 MiB), so that an oversized file is reported without being read whole.
/// False, with the system's reason in *error, when it cannot be read.
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT bool ReadScriptFile(const std::string& path, std::string* text,
                                                         std::string* error);

extern template SceneRun LoadScene(std::string_view, core::SceneGraph<coord::QuaternionBackend>&,
                                   const RunOptions&);
extern template SceneRun LoadScene(std::string_view, core::SceneGraph<coord::HomogeneousBackend>&,
                                   const RunOptions&);
extern template SceneRun LoadSceneFile(const std::string&,
                                       core::SceneGraph<coord::QuaternionBackend>&, RunOptions);
extern template SceneRun LoadSceneFile(const std::string&,
                                       core::SceneGraph<coord::HomogeneousBackend>&, RunOptions);
extern template std::string WriteDot(const core::SceneGraph<coord::QuaternionBackend>&);
extern template std::string WriteDot(const core::SceneGraph<coord::HomogeneousBackend>&);
extern template std::string WriteScene(const core::SceneGraph<coord::QuaternionBackend>&);
extern template std::string WriteScene(const core::SceneGraph<coord::HomogeneousBackend>&);

}  // namespace semgraph::script
