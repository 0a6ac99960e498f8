// File: semgraph/core/scene_graph_debug.h
//
// Debug views of a SceneGraph, for tests, fuzzers and tools; not part of the facade and never
// on a production path (both allocate, build strings and walk the whole graph):
//   Dump(graph)             canonical, complete text of the graph: names, ids, bodies, frames
//                           with their pose edge values, twist edges and values, pose-tree
//                           roots, joint records. Two graphs with equal Dump hold the same state
//                           bit for bit, so tests and fuzzers compare it before and after a
//                           rejected operation. O(n + joints) plus the text.
//   CheckInvariants(graph)  verifies every invariant of scene_graph.h (P1-P4, W1-W4, the
//                           topology's bookkeeping, recounted from scratch) and that the edge
//                           values cover the edges. Empty string when all hold, else one line
//                           per broken invariant. O(n log n) and up; slow by design.
// They read the graph's private state through internal::DebugAccess, the class's only friend,
// defined in scene_graph_debug.cc. Explicitly instantiated for both backends (like SceneGraph).
#pragma once

#include <string>

#include "semgraph/core/export.h"
#include "semgraph/core/scene_graph.h"

namespace semgraph::core {

template <coord::Backend B>
[[nodiscard]] SEMGRAPH_CORE_EXPORT std::string Dump(const SceneGraph<B>& graph);

template <coord::Backend B>
[[nodiscard]] SEMGRAPH_CORE_EXPORT std::string CheckInvariants(const SceneGraph<B>& graph);

extern template std::string Dump(const SceneGraph<coord::QuaternionBackend>&);
extern template std::string Dump(const SceneGraph<coord::HomogeneousBackend>&);
extern template std::string CheckInvariants(const SceneGraph<coord::QuaternionBackend>&);
extern template std::string CheckInvariants(const SceneGraph<coord::HomogeneousBackend>&);

}  // namespace semgraph::core
