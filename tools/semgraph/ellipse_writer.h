// File: tools/semgraph/ellipse_writer.h
//
// `semgraph ellipses`: the picture of a scene's position uncertainty (docs/uncertainty.md). For
// every frame f connected to the root frame r: the position of f's origin relative to r's, in
// [r], with its 3x3 covariance (SceneGraph::GetPositionWithCovariance), projected on a plane of
// [r] (xy, xz or yz: the 2x2 block of those two axes), drawn as an SVG ellipse at f's projected
// position: semi-axes sigma * sqrt(eigenvalues) along the eigenvectors of the 2x2 block (the
// 1-sigma ellipse for sigma = 1), a dot and the label {f}. Frames with no path to r are left
// out; an exact position (zero covariance) is drawn as its dot only.
//
// Invariants of the output: deterministic (frame index order); names appear only in escaped
// text; each ellipse carries its values in metres and radians as data attributes (data-frame,
// data-x, data-y: the centre; data-major, data-minor: the semi-axes; data-angle: the major
// axis's angle from the plane's first axis, in (-pi/2, pi/2]), so that a reader can check it.
// The drawing maps the plane's first axis right and its second axis up.
// Cost: O(frames * d log n) queries (d: path length). Thread safety: reads the graph only.
#pragma once

#include <cstdint>
#include <string>

#include "semgraph/base/expected.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/script/export.h"

namespace semgraph::script {

enum class EllipsePlane : std::uint8_t { kXY, kXZ, kYZ };

struct EllipseOptions {
  std::string root;                        ///< the frame the positions are relative to, in
  EllipsePlane plane = EllipsePlane::kXY;  ///< the plane of [root] drawn
  double sigma = 1.0;                      ///< the ellipses' size in standard deviations
};

/// The SVG document; the error names an unknown root frame or a sigma that is not positive.
template <coord::Backend B>
[[nodiscard]] SEMGRAPH_SCRIPT_EXPORT base::Expected<std::string, std::string> WriteEllipses(
    const core::SceneGraph<B>& graph, const EllipseOptions& options);

}  // namespace semgraph::script
