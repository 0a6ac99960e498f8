// File: semgraph/script/scene_script.h (library semgraph::script)
//
// Scene scripts from C++: the calls behind the `semgraph` command-line tool, with the same
// results. A scene script is the YAML format of docs/scene-script.md; each op gives one result,
// whose `json` is exactly the line `semgraph run` prints for it.
//
//   RunScene(text)            = `semgraph run`: a fresh graph of the script's representation
//   LoadScene(text, graph)    applies the script to a graph of yours (and leaves it there)
//   RunSceneFile / LoadSceneFile   the same from a file
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
// options decide); RunScene uses both. Costs: O(script) to read, then one scene-graph call per op. Thread safety: the calls share
// nothing; a graph passed in must not be used by another thread meanwhile.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "semgraph/core/scene_graph.h"

namespace semgraph::script {

/// Exit statuses of the tool, and `SceneRun::status`.
inline constexpr int kExitOk = 0;         // every op succeeded
inline constexpr int kExitOpFailed = 1;   // an op was rejected or a query failed
inline constexpr int kExitMalformed = 2;  // malformed or unreadable script, out of memory
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
  std::string error;            // status kExitMalformed: "FILE:LINE:COLUMN: message"
  std::vector<OpResult> ops;    // one per op applied, in order (unless on_op took them)
  std::string dot;              // RunOptions::dot: the final graph in Graphviz DOT
};

struct RunOptions {
  /// The name used in `error` ("FILE" above).
  std::string display_name = "<script>";
  /// Also render the final graph (RunScene*: into SceneRun::dot).
  bool dot = false;
  /// When set, each result is handed here as soon as its op is applied, instead of being kept
  /// in SceneRun::ops; returning false stops the run (the remaining ops are not applied).
  std::function<bool(const OpResult&)> on_op;
  /// The folder a relative `urdf` file is read from; empty: the working folder. The *File
  /// calls set it to the script's folder when it is empty (not for standard input).
  std::string base_dir;
};

/// `semgraph run` on a script held in memory.
[[nodiscard]] SceneRun RunScene(std::string_view text, const RunOptions& options = {});
/// The same on a file ("-" reads standard input); an unreadable file is status kExitMalformed
/// with "FILE: cannot read: <reason>". display_name defaults to the path (<stdin> for "-").
[[nodiscard]] SceneRun RunSceneFile(const std::string& path, RunOptions options = {});

/// Applies a script to `graph`. RunOptions::dot is ignored (see WriteDot).
template <coord::Backend B>
[[nodiscard]] SceneRun LoadScene(std::string_view text, core::SceneGraph<B>& graph,
                                 const RunOptions& options = {});
template <coord::Backend B>
[[nodiscard]] SceneRun LoadSceneFile(const std::string& path, core::SceneGraph<B>& graph,
                                     RunOptions options = {});

/// The graph in Graphviz DOT, as `semgraph dot` prints it: bodies as clusters holding their
/// frames, pose edges solid (tail frame -> head frame), twist edges dashed (reference body ->
/// head frame). Deterministic; names appear only in escaped labels.
template <coord::Backend B>
[[nodiscard]] std::string WriteDot(const core::SceneGraph<B>& graph);

/// Reads a script file ("-": standard input) without holding more than one byte beyond the
/// script size limit (16 MiB), so that an oversized file is reported without being read whole.
/// False, with the system's reason in *error, when it cannot be read.
[[nodiscard]] bool ReadScriptFile(const std::string& path, std::string* text, std::string* error);

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

}  // namespace semgraph::script
