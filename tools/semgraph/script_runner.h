// File: tools/semgraph/script_runner.h
//
// Applies the ops of a scene script (script_reader.h) to a SceneGraph<B> one at a time and
// renders each outcome as one JSON line of docs/scene-script.md:
//   {"op": i, "ok": true, "kind": K, "line": L}             accepted add / remove
//   {"op": i, "ok": false, "error": "<code>", "message": "<text>", "kind": K, "line": L}
//   {"op": i, "ok": true, "position": [x,y,z], "quaternion": [w,x,y,z], "kind": K, "line": L}
//   ... "position" / "quaternion" / "linear" + "angular" / "linear" / "angular" for the others;
//   a jacobian query: "joints": [names], "linear": [[row x], [row y], [row z]], "angular": [...].
// K is OpLabel(op), L the op's line in the script; they come last, so that the original keys
// keep their order.
// Rules of the rendering: numbers are printed with 17 significant digits (they round-trip), -0
// as 0; quaternions are given with w >= 0 (q and -q are one rotation; when w == 0 the first
// nonzero component is made positive, so the text is deterministic); strings are JSON-escaped,
// control characters as \uXXXX, valid UTF-8 passed through, invalid bytes as U+FFFD. Should a
// query result ever not be finite (the graph bounds its inputs, so it should not happen), it is
// reported as invalid_number rather than printed, since JSON cannot carry it. A name longer
// than kMaxEchoedNameBytes is cut in messages (its first bytes and its length).
//
// Cost: one scene-graph call per op plus the formatting. Thread safety: as the graph's
// (an add needs exclusive access).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "semgraph/core/scene_graph.h"
#include "semgraph/script_reader.h"

namespace semgraph::script {

/// Names longer than this (no valid name is: semantics' kMaxNameBytes) are echoed in messages
/// as their first kEchoedPrefixBytes bytes and their length: "xxxx... (8388608 bytes)".
inline constexpr std::size_t kMaxEchoedNameBytes = 255;
inline constexpr std::size_t kEchoedPrefixBytes = 40;

/// What one op did: whether it succeeded, its error code (snake_case; empty on success) and its
/// JSON line (without newline).
struct OpOutcome {
  bool ok = false;
  std::string error;
  std::string json;
};

/// Applies `op`, the op numbered `index` in its script, to `graph`. Never throws (except
/// std::bad_alloc); a rejection leaves `graph` unchanged (the scene graph's atomicity).
/// `base_dir` resolves a relative `urdf` file (the script's folder; empty: the working folder).
template <coord::Backend B>
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT OpOutcome ApplyOp(core::SceneGraph<B>& graph,
                                                       const ScriptOp& op, std::size_t index,
                                                       std::string_view base_dir = {});

/// The graph options a script's `time` map asks for (the reader checked the window, so
/// SceneGraph<B>::Create accepts them). One conversion for the tool, RunScene and Python.
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT core::TimeOptions TimeOptionsOf(const TimeSettings& time);

/// The op as the output's "kind" names it: "body", "frame", "pose", "twist", "remove pose",
/// "remove twist", "query <kind>" ("query linear_velocity", ...).
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT std::string OpLabel(const ScriptOp& op);

/// `text` as a JSON string literal, quotes included.
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT std::string JsonString(std::string_view text);
/// `value` with 17 significant digits (%.17g), -0 as 0. @pre value is finite.
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT std::string JsonNumber(double value);

extern template OpOutcome ApplyOp<coord::QuaternionBackend>(
    core::SceneGraph<coord::QuaternionBackend>&, const ScriptOp&, std::size_t, std::string_view);
extern template OpOutcome ApplyOp<coord::HomogeneousBackend>(
    core::SceneGraph<coord::HomogeneousBackend>&, const ScriptOp&, std::size_t, std::string_view);

}  // namespace semgraph::script
