// File: tools/semgraph/dot_writer.h
//
// Graphviz DOT of a scene graph in the style of the paper's Fig. 8 (WriteDot, declared in the
// public semgraph/script/scene_script.h): each body is a cluster labelled with its name, holding
// its frames (ellipses labelled {f}) and a small box for the body itself; pose edges are solid
// arrows tail frame -> head frame (the stored pose is the head's relative to the tail); twist
// edges are dashed arrows from the reference body's box to the head frame. A joint's pose and
// twist edges are drawn bold, labelled "<type> <joint name>".
//
// Invariants of the output: node ids are synthetic (body_<i>, frame_<i>), so names never need to
// be valid DOT ids; names appear only in quoted labels, escaped. The output is deterministic
// (index order) and valid input for `dot`.
// Cost: O(bodies + frames + edges). Thread safety: reads the graph only.
#pragma once

#include <string>
#include <string_view>

#include "semgraph/script/scene_script.h"

namespace semgraph::script {

/// `text` as a quoted DOT string for a label (quotes and backslashes escaped).
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT std::string DotLabel(std::string_view text);

}  // namespace semgraph::script
