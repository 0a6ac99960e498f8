// Text of the core's messages, formatted only when an operation is rejected or an error is
// described (never on a query's or an accepted add's path). Implemented in describe.cc.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>

#include "add_plan.h"
#include "edge_lookup.h"
#include "semgraph/core/specs.h"
#include "semgraph/topology/rules.h"
#include "semgraph/topology/scene_topology.h"

namespace semgraph::core::text {

/// "{frame}|body".
std::string Braced(std::string_view frame, std::string_view body);
/// "{f}|F" of an existing frame.
std::string Frame(const topology::SceneTopology& t, topology::FrameIndex f);
/// "[x, y, z]" with 9 significant digits.
std::string Vector(const Eigen::Vector3d& v);
/// A rejection: "<what> rejected (<code>): <reason>".
BuildResult Reject(ErrorCode code, const std::string& what, const std::string& reason);
/// The relation of an AddPose as the user wrote it, e.g. "pose of {c}|C wrt {b}|B".
std::string PoseAdd(const PoseSpec& spec);
/// The relation of an AddTwist, e.g. "twist of o1|O1 wrt C in [c]".
std::string TwistAdd(const TwistSpec& spec);
/// The reason of a broken rule of a new pose edge tail {b} -> head {a} (rules.h).
std::string PoseRule(const topology::SceneTopology& t, const topology::RuleViolation& v,
                     const topology::NewPoseEdge& ends, const PoseSpec& spec);
/// The reason of a broken rule of a new twist edge D -> {e}|C.
std::string TwistRule(const topology::SceneTopology& t, const topology::RuleViolation& v,
                      const topology::NewTwistEdge& ends);

/// The reason of a broken rule of a joint's new pose edge {p} -> {c} and twist edge P -> {c}|C
/// (`as_pose`: the joint as the pose of {c}|C wrt {p}|P, for the pose rules' texts).
std::string JointRule(const topology::SceneTopology& t, const topology::RuleViolation& v,
                      const topology::NewPoseEdge& ends, const PoseSpec& as_pose);
/// The rejection of an add whose end {frame}|body failed node resolution (add_plan.h
/// ResolveEnd): frame_body_mismatch or frame_without_body.
BuildResult RejectEnd(const topology::SceneTopology& t, internal::EndProblem p,
                      const internal::AddEnd& end, const std::string& what, std::string_view frame,
                      std::string_view body);
/// Why a lookup of an edge by names failed (edge_lookup.h); `explain` adds, for no_such_edge,
/// the edge that is there instead (removals).
std::string EdgeReason(const topology::SceneTopology& t, const internal::EdgeLookup& l,
                       std::string_view relative_to, bool explain);

/// A stamp in seconds with millisecond digits, "12.480 s"; a range "[12.000, 12.480] s".
std::string StampText(std::int64_t ns);
std::string StampRange(std::int64_t first_ns, std::int64_t last_ns);

/// The reason of a query error, without the "query failed (<code>): " of Describe (for build
/// calls that plan a query and report its failure as their own). `spec` may be null.
std::string QueryReason(const topology::SceneTopology& t, const QueryError& e,
                        const PoseSpec* spec);

}  // namespace semgraph::core::text
