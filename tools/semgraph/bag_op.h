// The `bag` op of scene scripts (docs/ros.md, "The bag op"): a ROS bag's tf and joint states
// applied to the graph through semgraph::ros (two passes: a corrupt bag changes nothing).
// Internal to semgraph_script; built when semgraph::ros is (SEMGRAPH_SCRIPT_HAS_ROS).
#pragma once

#include <cstddef>
#include <string_view>

#include "semgraph/script_reader.h"
#include "semgraph/script_runner.h"

namespace semgraph::script {

/// Output: {"op": i, "ok": B, "messages": n, "skipped": k, "transforms": t, "applied": a,
/// "refused": r, "covered": c, "normalized": k, "start": s, "end": e}; not ok (with "error" =
/// the first finding's code and its "message") when a transform was refused or differs from the
/// robot model; a bag that cannot be read is "error": "invalid_bag" and changes nothing.
template <coord::Backend B>
[[nodiscard]] OpOutcome ApplyBagOp(core::SceneGraph<B>& graph, const ScriptOp& op,
                                   std::size_t index, std::string_view base_dir);

}  // namespace semgraph::script
