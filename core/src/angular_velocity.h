// Private to core/src: the angular velocity query as the angular part of a twist query, for the
// one-shot and the timed GetAngularVelocity (scene_graph.cc, time_query.cc): one spec rewrite, one
// error mapping.
#pragma once

#include "semgraph/core/specs.h"

namespace semgraph::core::internal {

/// The twist that holds the angular velocity of `spec` (TwistSpec::Of("", body)...): the
/// angular velocity needs no point, so the coordinate frame's origin is taken. get_twist(s)
/// answers the twist query s (a QueryResult); an error names the field of `spec` it is about
/// (kPoint, which `spec` does not have, becomes kCoordinateFrame). noexcept, no allocation.
template <class GetTwist>
auto TwistOfAngularVelocity(const TwistSpec& spec, GetTwist&& get_twist) noexcept {
  using Result = decltype(get_twist(spec));
  TwistSpec s = spec;
  s.point = spec.coordinate_frame;
  if (s.body.empty()) {
    QueryError e;
    e.code = ErrorCode::kInvalidName;
    e.field = spec.coordinate_frame.empty() ? semantics::Field::kCoordinateFrame
                                            : semantics::Field::kBody;
    return Result{base::Unexpected{e}};
  }
  Result twist = get_twist(s);
  if (!twist && twist.error().field == semantics::Field::kPoint) {
    QueryError e = twist.error();
    e.field = semantics::Field::kCoordinateFrame;  // the point was [r]'s origin
    return Result{base::Unexpected{e}};
  }
  return twist;
}

}  // namespace semgraph::core::internal
