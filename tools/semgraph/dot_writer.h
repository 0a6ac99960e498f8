// File: tools/semgraph/dot_writer.h
//
// Graphviz DOT of a scene graph in the style of the paper's Fig. 8: each body is a cluster
// labelled with its name, holding its frames (ellipses labelled {f}) and a small box for the body
// itself; pose edges are solid arrows tail frame -> head frame (the stored pose is the head's
// relative to the tail); twist edges are dashed arrows from the reference body's box to the head
// frame.
//
// Invariants of the output: node ids are synthetic (body_<i>, frame_<i>), so names never need to
// be valid DOT ids; names appear only in quoted labels, escaped. The output is deterministic
// (index order) and valid input for `dot`.
// Cost: O(bodies + frames + edges). Thread safety: reads the graph only.
#pragma once

#include <string>

#include "semgraph/core/scene_graph.h"

namespace semgraph::script {

template <coord::Backend B>
[[nodiscard]] std::string WriteDot(const core::SceneGraph<B>& graph);

/// `text` as a quoted DOT string for a label (quotes and backslashes escaped).
[[nodiscard]] std::string DotLabel(std::string_view text);

extern template std::string WriteDot<coord::QuaternionBackend>(
    const core::SceneGraph<coord::QuaternionBackend>&);
extern template std::string WriteDot<coord::HomogeneousBackend>(
    const core::SceneGraph<coord::HomogeneousBackend>&);

}  // namespace semgraph::script
