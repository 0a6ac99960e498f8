// File: fuzz/support/scene_differential.h
//
// Differential<B>: one SceneGraph<B> (the kernel) and one ReferenceModel (the oracle,
// tests/reference) driven by the same operations, checked after every single one. Used by
// scene_ops_fuzzer (random op sequences) and exhaustive_small_scope (all short sequences).
//
// Checks after every operation (any failure prints the whole op sequence in scene-script
// notation, then aborts):
//   - kernel and model accept or reject alike, with the same error code (the order of docs/rules.md
//   §7);
//   - a rejected operation and every query leave the kernel's Dump() byte-identical;
//   - CheckInvariants(kernel) is empty;
//   - the kernel's topology and stored values equal the model's (frames and their bodies, pose
//     parents and X_PF, twist parents and screw twists, counts);
//   - every query: same code; same value within the state tolerance (1e-9 relative to the
//     scene's magnitude); Compile*() gives the same code and Evaluate() the same value;
//   - kept compiled queries (Keep): after each op Evaluate() returns kQueryInvalidated exactly
//     when an edge they use (ReferenceModel::UsedEdges) was removed since they were compiled,
//     and otherwise the value of the one-shot query of that moment. (Exception, a reported spec
//     ambiguity: a velocity of a body relative to itself stays valid and zero; see Keep.)
//
//   - repairing adds (PoseRepair, TwistRepair): the same strategy, number of reversed edges and
//     discrepancy; kept compiled queries reading a reversed edge invalidated;
//   - joints (Joint, SetJoints, MakeGroup, SetGroup; stamped: SetJoints with a stamp, with or
//     without q'', SetGroupStamped through every real-time stamped setter): codes, joint states,
//     edge values (the timed queries then read the joints' samples);
//     AskJacobian: the columns' joints in order and the matrix, one-shot and compiled;
//   - time (StampedPose, StampedTwist, AskTimed): codes, values, and the TimeReport (time
//     answered, extrapolated, stamps read when not extrapolated), one-shot and compiled.
//   - covariances (Pose, Twist with a CovarianceIn): codes; every edge's stored covariance
//     (pose_covariance / twist_covariance) equal to the model's edge form within 1e-12 of
//     max(1, max|S|) and symmetric; a nonzero one asked back for the edge alone
//     (GetPoseWithCovariance of head wrt tail, GetTwistWithCovariance at head in [head]) within
//     1e-9; a rejected op leaves every stored covariance bit-identical (Dump() has none).
//   - wrenches: codes, stored pairs and values, queries one-shot, compiled and kept, handles.
//   - accelerations (TwistWithAcceleration, Acceleration, TwistHandle, ConvertingTwistHandle,
//     SetByTwistHandle, SetTwistConverted, AskAcceleration, KeepAcceleration): codes; every
//     twist edge's acceleration present exactly when the model's, equal to its edge form; query
//     answers within 1e-9 of AccelerationScale(), one-shot and compiled; kept compiled ones
//     invalidated exactly when an edge of their twist query was removed, else the model's
//     answer of the moment (no_acceleration included); the light final sweep asks them too.
//     Stamped (StampedTwistWithAcceleration, Acceleration and SetByTwistHandle with a stamp,
//     AskAccelerationTimed): the same codes; timed queries as AskTimed (code, value, report),
//     one-shot and compiled.
//
// Scope: the model's (edge-form pose adds; twist adds in the point's or another frame of its
// tree; repair, joints, time); see tests/reference/reference_model.h.
// Cost: each op costs the model's from-scratch checks, O(scene^2) with maps; fine for scenes
// of a few dozen frames. Not thread-safe.
#pragma once

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "reference_model.h"
#include "semgraph/base/error_code.h"
#include "semgraph/core/compiled_acceleration.h"
#include "semgraph/core/compiled_query.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"

namespace semgraph::fuzz {

using base::ErrorCode;
using reference::Answer;
using reference::Query;
using reference::QueryKind;
using reference::ReferenceModel;
using reference::RotationInput;

// ------------------------------------------------------------------ scene-script text

/// A name as a YAML scalar: bare when it is [A-Za-z0-9_.]+, else double-quoted with escapes.
inline std::string YamlName(std::string_view s) {
  bool bare = !s.empty();
  for (unsigned char c : s) bare = bare && (std::isalnum(c) || c == '_' || c == '.');
  if (bare) return std::string(s);
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c >= 0x7F) {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\x%02x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

inline std::string YamlNumber(double x) {
  if (std::isnan(x)) return ".nan";
  if (std::isinf(x)) return x > 0 ? ".inf" : "-.inf";
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.17g", x);
  return buf;
}

inline std::string YamlVector(const Eigen::Vector3d& v) {
  return "[" + YamlNumber(v.x()) + ", " + YamlNumber(v.y()) + ", " + YamlNumber(v.z()) + "]";
}

inline std::string YamlRotation(const RotationInput& r) {
  if (!r.is_matrix) {
    return "{quaternion: [" + YamlNumber(r.q.w()) + ", " + YamlNumber(r.q.x()) + ", " +
           YamlNumber(r.q.y()) + ", " + YamlNumber(r.q.z()) + "]}";
  }
  std::string s = "{matrix: [";
  for (int i = 0; i < 3; ++i) {
    s += std::string(i ? ", " : "") + "[" + YamlNumber(r.R(i, 0)) + ", " + YamlNumber(r.R(i, 1)) +
         ", " + YamlNumber(r.R(i, 2)) + "]";
  }
  return s + "]}";
}

/// A covariance as scene-script.md's `covariance: {matrix, order, convention}` value.
inline std::string YamlCovariance(const reference::CovarianceIn& c) {
  std::string m = "[";
  for (int i = 0; i < 6; ++i) {
    m += i ? ", [" : "[";
    for (int j = 0; j < 6; ++j) m += (j ? ", " : "") + YamlNumber(c.S(i, j));
    m += "]";
  }
  return ", covariance: {matrix: " + m +
         "], order: " + (c.angular_linear ? "angular_linear" : "linear_angular") +
         ", convention: " + (c.body ? "body" : "coordinates") + "}";
}

/// `, key: value` when value is not empty.
inline std::string Field(const char* key, const std::string& value) {
  return value.empty() ? std::string() : std::string(", ") + key + ": " + YamlName(value);
}

inline const char* KindName(QueryKind k) {
  switch (k) {
    case QueryKind::kPose:
      return "pose";
    case QueryKind::kPosition:
      return "position";
    case QueryKind::kOrientation:
      return "orientation";
    case QueryKind::kTwist:
      return "twist";
    case QueryKind::kLinearVelocity:
      return "linear_velocity";
    case QueryKind::kAngularVelocity:
      return "angular_velocity";
  }
  return "?";
}

inline std::string QueryText(const Query& q) {
  std::string s = std::string("{op: query, kind: ") + KindName(q.kind);
  switch (q.kind) {
    case QueryKind::kPose:
      s += Field("point", q.point) + Field("orientation", q.orientation) + Field("body", q.body) +
           Field("ref_point", q.ref_point) + Field("ref_orientation", q.ref_orientation) +
           Field("ref_body", q.ref_body);
      break;
    case QueryKind::kPosition:
      s += Field("point", q.point) + Field("body", q.body) + Field("ref_point", q.ref_point) +
           Field("ref_body", q.ref_body);
      break;
    case QueryKind::kOrientation:
      s += Field("orientation", q.orientation) + Field("body", q.body) +
           Field("ref_orientation", q.ref_orientation) + Field("ref_body", q.ref_body);
      break;
    case QueryKind::kAngularVelocity:
      s += Field("body", q.body) + Field("ref_body", q.ref_body);
      break;
    default:
      s += Field("point", q.point) + Field("body", q.body) + Field("ref_body", q.ref_body);
      break;
  }
  return s + Field("coord", q.coord) + "}";
}

/// An acceleration query (the twist query's fields; kind kTwist: acceleration, kLinearVelocity:
/// linear_acceleration, kAngularVelocity: angular_acceleration) in scene-script notation.
inline std::string AccelerationQueryText(const Query& q) {
  const char* kind = q.kind == QueryKind::kLinearVelocity    ? "linear_acceleration"
                     : q.kind == QueryKind::kAngularVelocity ? "angular_acceleration"
                                                             : "acceleration";
  std::string s = std::string("{op: query, kind: ") + kind;
  if (q.kind != QueryKind::kAngularVelocity) s += Field("point", q.point);
  return s + Field("body", q.body) + Field("ref_body", q.ref_body) + Field("coord", q.coord) + "}";
}

// ------------------------------------------------------------------ the differential runner

template <coord::Backend B>
class Differential {
 public:
  using Graph = core::SceneGraph<B>;
  static constexpr bool kHomogeneous = std::is_same_v<B, coord::HomogeneousBackend>;

  explicit Differential(const reference::TimeOptions& time = reference::TimeOptions{})
      : model_(kHomogeneous ? reference::Representation::kHomogeneous
                            : reference::Representation::kQuaternion,
               time),
        time_(time) {
    core::TimeOptions options;
    options.window = core::Duration::Nanoseconds(time.window_ns);
    options.sample_capacity = time.capacity;
    options.interpolation =
        time.linear ? core::Interpolation::kLinear : core::Interpolation::kScrew;
    options.duplicate_stamp =
        time.reject_duplicates ? core::DuplicatePolicy::kReject : core::DuplicatePolicy::kReplace;
    auto g = Graph::Create(options);
    if (!g) Fail("SceneGraph::Create refused the time options: " + g.error().message);
    graph_ = std::move(*g);
  }

  const ReferenceModel& model() const { return model_; }
  const Graph& graph() const { return graph_; }

  /// Prints the trace so far (for a harness's own failure), then aborts.
  [[noreturn]] void Fail(const std::string& why) const {
    std::fprintf(stderr, "\n==== semgraph differential check FAILED (%s backend) ====\n%s\n",
                 B::kName, why.c_str());
    PrintTrace(stderr);
    std::fflush(stderr);
    std::abort();
  }

  /// The op sequence so far, one line per op in scene-script notation with the kernel's result.
  void PrintTrace(std::FILE* out) const {
    std::fprintf(out,
                 "---- the op sequence (scene-script notation; '# kernel:' is the result) ----\n");
    std::fprintf(out, "representation: %s\n", B::kName);
    std::fprintf(out,
                 "# time options: window %lld ns, capacity %zu, %s interpolation, duplicate "
                 "stamps: %s\nops:\n",
                 static_cast<long long>(time_.window_ns), time_.capacity,
                 time_.linear ? "linear" : "screw", time_.reject_duplicates ? "reject" : "replace");
    for (const TraceLine& t : trace_) {
      const std::string line =
          t.render() + (t.code ? "   # kernel: " + std::string(base::ToString(*t.code)) : "") +
          (t.note.empty() ? "" : " (" + t.note + ")");
      std::fprintf(out, line[0] == '#' ? "  %s\n" : "  - %s\n", line.c_str());
    }
    std::fprintf(out, "==== end of trace ====\n");
  }

  // ---------------------------------------------------------------- operations

  ErrorCode Body(const std::string& name) {
    Begin([=] { return "{op: body, name: " + YamlName(name) + "}"; });
    return Finish(graph_.AddBody(name), model_.AddBody(name));
  }

  ErrorCode Frame(const std::string& name, const std::string& body) {
    Begin([=] { return "{op: frame, name: " + YamlName(name) + Field("body", body) + "}"; });
    return Finish(graph_.AddFrame(name, body), model_.AddFrame(name, body));
  }

  /// Edge-form pose tail -> head: PoseCoord({head}|head_body, {tail}|tail_body, [tail]); with
  /// a covariance when `cov` is set (docs/uncertainty.md).
  ErrorCode Pose(const std::string& head, const std::string& head_body, const std::string& tail,
                 const std::string& tail_body, const RotationInput& rotation,
                 const Eigen::Vector3d& p, const reference::CovarianceIn* cov = nullptr) {
    const std::string cov_text = cov ? YamlCovariance(*cov) : std::string();
    Begin([=] {
      return "{op: pose, of: " + YamlName(head) + Field("body", head_body) +
             ", wrt: " + YamlName(tail) + Field("ref_body", tail_body) +
             ", position: " + YamlVector(p) + ", rotation: " + YamlRotation(rotation) + cov_text +
             "}";
    });
    core::PoseSpec spec = core::PoseSpec::Of(head, head_body).RelativeTo(tail, tail_body);
    const core::CovarianceInput in = KernelCovariance(cov);
    const auto result = !cov ? (rotation.is_matrix ? graph_.AddPose(spec, rotation.R, p)
                                                   : graph_.AddPose(spec, rotation.q, p))
                             : (rotation.is_matrix ? graph_.AddPose(spec, rotation.R, p, in)
                                                   : graph_.AddPose(spec, rotation.q, p, in));
    return Finish(result,
                  model_.AddPose(head, head_body, tail, tail_body, rotation, p, std::nullopt, cov));
  }

  ErrorCode Twist(const std::string& point, const std::string& body, const std::string& ref_body,
                  const std::string& coord, const Eigen::Vector3d& v, const Eigen::Vector3d& w,
                  const reference::CovarianceIn* cov = nullptr) {
    const std::string cov_text = cov ? YamlCovariance(*cov) : std::string();
    Begin([=] {
      return "{op: twist, point: " + YamlName(point) + Field("body", body) +
             ", ref_body: " + YamlName(ref_body) + ", coord: " + YamlName(coord) +
             ", linear: " + YamlVector(v) + ", angular: " + YamlVector(w) + cov_text + "}";
    });
    core::TwistSpec spec = core::TwistSpec::Of(point, body).RelativeTo(ref_body).ExpressedIn(coord);
    const auto result =
        cov ? graph_.AddTwist(spec, v, w, KernelCovariance(cov)) : graph_.AddTwist(spec, v, w);
    return Finish(result, model_.AddTwist(point, body, ref_body, coord, v, w, std::nullopt, cov));
  }

  /// Edge-form pose add with repair (docs/repair.md): besides the checks of Pose, the same
  /// repair applied (none / inverted / rerooted / consistent), the same number of reversed
  /// edges, the same discrepancy (reported on a consistent check and on a refused one), kept
  /// compiled queries that read a reversed edge invalidated. A consistency check whose
  /// discrepancy is within rounding of a tolerance may go either way (no change either way).
  ErrorCode PoseRepair(const std::string& head, const std::string& head_body,
                       const std::string& tail, const std::string& tail_body,
                       const Eigen::Quaterniond& q, const Eigen::Vector3d& p,
                       const reference::RepairPolicy& policy) {
    Begin([=] {
      return "{op: pose, of: " + YamlName(head) + Field("body", head_body) +
             ", wrt: " + YamlName(tail) + Field("ref_body", tail_body) +
             ", position: " + YamlVector(p) + ", rotation: " + YamlRotation(RotationOf(q)) +
             ", repair: true}" + PolicyComment(policy);
    });
    const reference::RepairOutcome expected =
        model_.AddPoseRepair(head, head_body, tail, tail_body, q, p, policy);
    for (const std::string& key : expected.reversed_keys) Removed(key);  // before CheckKept
    const core::PoseSpec spec = core::PoseSpec::Of(head, head_body).RelativeTo(tail, tail_body);
    return FinishRepair(graph_.AddPose(spec, q, p, KernelPolicy(policy)), expected);
  }

  /// Twist add with repair; the inverse twist's frame is the kernel's choice among the model's
  /// candidates (docs/repair.md does not say which frame of the reference body).
  ErrorCode TwistRepair(const std::string& point, const std::string& body,
                        const std::string& ref_body, const std::string& coord,
                        const Eigen::Vector3d& v, const Eigen::Vector3d& w,
                        const reference::RepairPolicy& policy) {
    Begin([=] {
      return "{op: twist, point: " + YamlName(point) + Field("body", body) +
             ", ref_body: " + YamlName(ref_body) + ", coord: " + YamlName(coord) +
             ", linear: " + YamlVector(v) + ", angular: " + YamlVector(w) + ", repair: true}" +
             PolicyComment(policy);
    });
    const core::TwistSpec spec =
        core::TwistSpec::Of(point, body).RelativeTo(ref_body).ExpressedIn(coord);
    auto result = graph_.AddTwist(spec, v, w, KernelPolicy(policy));
    const auto kernel_choice = [&](const std::vector<std::string>& candidates) {
      for (const std::string& h : candidates) {
        const core::FrameIndex f = graph_.FindFrame(h);
        if (f.is_valid() && graph_.twist_parent(f).is_valid()) return h;  // the one it just added
      }
      return candidates.front();  // the kernel refused: any candidate gives the same decision
    };
    return FinishRepair(std::move(result), model_.AddTwistRepair(point, body, ref_body, coord, v, w,
                                                                 policy, kernel_choice));
  }

  // ---------------------------------------------------------------- joints

  ErrorCode Joint(const reference::JointInput& in) {
    Begin([=] {
      std::string s = "{op: joint, name: " + YamlName(in.name) +
                      ", type: " + JointTypeName(in.type) + ", parent: " + YamlName(in.parent) +
                      Field("parent_body", in.parent_body) + ", child: " + YamlName(in.child) +
                      Field("child_body", in.child_body) +
                      ", position: " + YamlVector(in.p_origin) +
                      ", rotation: " + YamlRotation(RotationOf(in.q_origin)) +
                      ", axis: " + YamlVector(in.axis) + ", lower: " + YamlNumber(in.lower) +
                      ", upper: " + YamlNumber(in.upper);
      if (!in.mimic.empty()) {
        s += ", mimic: {joint: " + YamlName(in.mimic) +
             ", multiplier: " + YamlNumber(in.multiplier) + ", offset: " + YamlNumber(in.offset) +
             "}";
      }
      return s + "}";
    });
    core::JointSpec spec;
    spec.name = in.name;
    spec.type = static_cast<core::JointType>(static_cast<int>(in.type));  // same order
    spec.parent = in.parent;
    spec.parent_body = in.parent_body;
    spec.child = in.child;
    spec.child_body = in.child_body;
    spec.q_origin = in.q_origin;
    spec.p_origin = in.p_origin;
    spec.axis = in.axis;
    spec.lower = in.lower;
    spec.upper = in.upper;
    spec.mimic = in.mimic;
    spec.multiplier = in.multiplier;
    spec.offset = in.offset;
    return Finish(graph_.AddJoint(spec), model_.AddJoint(in));
  }

  using JointValues = std::vector<std::pair<std::string, double>>;
  /// SetJoints by name; with accelerations (q'') when any is given.
  ErrorCode SetJoints(const JointValues& positions, const JointValues& velocities,
                      const JointValues& accelerations = {}) {
    Begin([=] {
      const auto map = [](const JointValues& list) {
        std::string s = "{";
        for (std::size_t i = 0; i < list.size(); ++i) {
          s += (i ? ", " : "") + YamlName(list[i].first) + ": " + YamlNumber(list[i].second);
        }
        return s + "}";
      };
      return "{op: joints, positions: " + map(positions) + ", velocities: " + map(velocities) +
             (accelerations.empty() ? "" : ", accelerations: " + map(accelerations)) + "}";
    });
    std::vector<core::JointValue> q, qdot, qddot;
    for (const auto& [name, value] : positions) q.push_back(core::JointValue{name, value});
    for (const auto& [name, value] : velocities) qdot.push_back(core::JointValue{name, value});
    for (const auto& [name, value] : accelerations) qddot.push_back(core::JointValue{name, value});
    const ErrorCode expected = model_.SetJoints(positions, velocities, accelerations);
    return Finish(
        accelerations.empty() ? graph_.SetJoints(q, qdot) : graph_.SetJoints(q, qdot, qddot),
        expected);
  }

  /// Stamped SetJoints by name (docs/dynamics.md "Stamped accelerations"); with accelerations
  /// when any is given.
  ErrorCode SetJoints(const JointValues& positions, const JointValues& velocities,
                      const JointValues& accelerations, std::int64_t stamp) {
    Begin([=] {
      const auto map = [](const JointValues& list) {
        std::string s = "{";
        for (std::size_t i = 0; i < list.size(); ++i) {
          s += (i ? ", " : "") + YamlName(list[i].first) + ": " + YamlNumber(list[i].second);
        }
        return s + "}";
      };
      return "{op: joints, positions: " + map(positions) + ", velocities: " + map(velocities) +
             (accelerations.empty() ? "" : ", accelerations: " + map(accelerations)) +
             ", stamp: " + StampText(stamp) + "}";
    });
    std::vector<core::JointValue> q, qdot, qddot;
    for (const auto& [name, value] : positions) q.push_back(core::JointValue{name, value});
    for (const auto& [name, value] : velocities) qdot.push_back(core::JointValue{name, value});
    for (const auto& [name, value] : accelerations) qddot.push_back(core::JointValue{name, value});
    const ErrorCode expected = model_.SetJoints(positions, velocities, accelerations, stamp);
    const core::Stamp at = core::Stamp::Nanoseconds(stamp);
    return Finish(accelerations.empty() ? graph_.SetJoints(q, qdot, at)
                                        : graph_.SetJoints(q, qdot, qddot, at),
                  expected);
  }

  /// MakeJointGroup(names): the same code; on success the group is kept for SetGroup.
  ErrorCode MakeGroup(const std::vector<std::string>& names) {
    Begin([=] {
      std::string s = "# MakeJointGroup([";
      for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + YamlName(names[i]);
      return s + "])";
    });
    std::vector<std::string_view> views(names.begin(), names.end());
    auto kernel = graph_.MakeJointGroup(views);
    std::vector<std::uint64_t> serials;
    const ErrorCode expected = model_.MakeGroup(names, &serials);
    const ErrorCode code = kernel ? ErrorCode::kOk : kernel.error().code;
    Annotate(code);
    if (code != expected) {
      Fail("MakeJointGroup: kernel says " + std::string(base::ToString(code)) + ", model says " +
           std::string(base::ToString(expected)));
    }
    if (kernel) {
      group_ = std::move(*kernel);
      model_group_ = std::move(serials);
    }
    return code;
  }

  /// The model's names of the kept group's joints (a removed one: empty), in group order.
  std::vector<std::string> GroupJoints() const {
    std::vector<std::string> names;
    for (const std::uint64_t serial : model_group_) {
      names.emplace_back();
      for (const reference::Joint& j : model_.joints()) {
        if (j.serial == serial) names.back() = j.name;
      }
    }
    return names;
  }
  bool has_group() const { return group_.has_value(); }

  /// The kept group's SetJointPositions (q only), SetJointVelocities (qdot only) or
  /// SetJointState (both); `values` has two numbers per joint (q, qdot). No group: nothing.
  ErrorCode SetGroup(int which, const std::vector<double>& values) {
    if (!group_) return ErrorCode::kOk;
    const std::size_t n = group_->size();
    std::vector<double> q(n), qdot(n);
    for (std::size_t i = 0; i < n; ++i) q[i] = values[2 * i], qdot[i] = values[2 * i + 1];
    Begin([=] {
      std::string s = std::string("# ") +
                      (which == 0   ? "SetJointPositions"
                       : which == 1 ? "SetJointVelocities"
                                    : "SetJointState") +
                      "(group, [";
      for (std::size_t i = 0; i < n; ++i) s += (i ? ", " : "") + YamlNumber(q[i]);
      s += "], [";
      for (std::size_t i = 0; i < n; ++i) s += (i ? ", " : "") + YamlNumber(qdot[i]);
      return s + "])";
    });
    const double* mq = which != 1 ? q.data() : nullptr;
    const double* mqdot = which != 0 ? qdot.data() : nullptr;
    const ErrorCode expected = model_.SetGroup(model_group_, mq, mqdot);
    const ErrorCode code = which == 0   ? graph_.SetJointPositions(*group_, q)
                           : which == 1 ? graph_.SetJointVelocities(*group_, qdot)
                                        : graph_.SetJointState(*group_, q, qdot);
    core::BuildResult result = base::Ok{};
    if (code != ErrorCode::kOk)
      result = base::Unexpected{core::BuildError{code, "(real-time setter: a code only)"}};
    return Finish(result, expected);
  }

  /// The kept group's real-time stamped setters at `stamp`: `which` 0 SetJointPositions, 1
  /// SetJointVelocities, 2 SetJointState (q, qdot), 3 SetJointAccelerations, 4 SetJointState
  /// (q, qdot, qddot); `values` has three numbers per joint (q, qdot, qddot). No group: nothing.
  ErrorCode SetGroupStamped(int which, const std::vector<double>& values, std::int64_t stamp) {
    if (!group_) return ErrorCode::kOk;
    const std::size_t n = group_->size();
    std::vector<double> q(n), qdot(n), qddot(n);
    for (std::size_t i = 0; i < n; ++i) {
      q[i] = values[3 * i], qdot[i] = values[3 * i + 1], qddot[i] = values[3 * i + 2];
    }
    static const char* const kNames[] = {"SetJointPositions", "SetJointVelocities", "SetJointState",
                                         "SetJointAccelerations", "SetJointState"};
    Begin([=] {
      std::string s = std::string("# ") + kNames[which] + "(group";
      const auto list = [&](const std::vector<double>& x) {
        s += ", [";
        for (std::size_t i = 0; i < n; ++i) s += (i ? ", " : "") + YamlNumber(x[i]);
        s += "]";
      };
      if (which == 0 || which == 2 || which == 4) list(q);
      if (which == 1 || which == 2 || which == 4) list(qdot);
      if (which == 3 || which == 4) list(qddot);
      return s + ", stamp " + StampText(stamp) + ")";
    });
    const double* mq = which == 0 || which == 2 || which == 4 ? q.data() : nullptr;
    const double* mqdot = which == 1 || which == 2 || which == 4 ? qdot.data() : nullptr;
    const double* mqddot = which >= 3 ? qddot.data() : nullptr;
    const ErrorCode expected = model_.SetGroup(model_group_, mq, mqdot, mqddot, stamp);
    const core::Stamp at = core::Stamp::Nanoseconds(stamp);
    const ErrorCode code = which == 0   ? graph_.SetJointPositions(*group_, q, at)
                           : which == 1 ? graph_.SetJointVelocities(*group_, qdot, at)
                           : which == 2 ? graph_.SetJointState(*group_, q, qdot, at)
                           : which == 3 ? graph_.SetJointAccelerations(*group_, qddot, at)
                                        : graph_.SetJointState(*group_, q, qdot, qddot, at);
    core::BuildResult result = base::Ok{};
    if (code != ErrorCode::kOk)
      result = base::Unexpected{core::BuildError{code, "(real-time setter: a code only)"}};
    return Finish(result, expected);
  }

  /// A Jacobian query (the twist query's arguments): same code as the model's twist query, same
  /// column joints in order, same matrix (one-shot and compiled).
  void AskJacobian(const Query& query) {
    Begin([=] {
      return "{op: query, kind: jacobian, point: " + YamlName(query.point) +
             Field("body", query.body) + ", ref_body: " + YamlName(query.ref_body) +
             ", coord: " + YamlName(query.coord) + "}";
    });
    const reference::JacobianAnswer expected = model_.Jacobian(query);
    Query twist = query;
    twist.kind = QueryKind::kTwist;
    const core::TwistSpec spec = TwistSpecOf(twist);
    const auto one_shot = graph_.GetJacobian(spec);
    Annotate(one_shot ? ErrorCode::kOk : one_shot.error().code);
    const auto compare = [&](const char* what, ErrorCode code,
                             const std::vector<core::JointHandle>& joints,
                             const core::JacobianMatrix& J) {
      if (code != expected.code) {
        Fail(std::string(what) + ": kernel says " + std::string(base::ToString(code)) +
             ", model says " + std::string(base::ToString(expected.code)));
      }
      if (code != ErrorCode::kOk) return;
      std::string kernel_joints, model_joints;
      for (const core::JointHandle h : joints)
        kernel_joints += std::string(graph_.joint_name(h)) + " ";
      for (const std::string& j : expected.joints) model_joints += j + " ";
      if (kernel_joints != model_joints)
        Fail(std::string(what) + ": columns [" + kernel_joints + "] vs model [" + model_joints +
             "]");
      const double tol = 1e-9 * PositionScale();
      if (J.cols() != expected.J.cols() || (J.cols() > 0 && !Near(J, expected.J, tol))) {
        const Eigen::IOFormat fmt(17, Eigen::DontAlignCols, ", ", "; ", "", "", "[", "]");
        std::ostringstream out;
        out << what << ": values differ\n  kernel " << J.format(fmt) << "\n  model  "
            << expected.J.format(fmt);
        Fail(out.str());
      }
    };
    if (one_shot) {
      compare("jacobian", ErrorCode::kOk, one_shot->joints, one_shot->J);
    } else {
      compare("jacobian", one_shot.error().code, {}, core::JacobianMatrix(6, 0));
    }
    const auto compiled = graph_.CompileJacobian(spec);
    if (!compiled) {
      compare("compiled jacobian", compiled.error().code, {}, core::JacobianMatrix(6, 0));
    } else {
      core::JacobianMatrix J(6, static_cast<Eigen::Index>(compiled->num_columns()));
      const ErrorCode code = compiled->Evaluate(J);
      compare("compiled jacobian", code, compiled->joints(), J);
    }
  }

  // ---------------------------------------------------------------- time

  /// A stamped edge-form pose add (the quaternion or matrix overload, as given).
  ErrorCode StampedPose(const std::string& head, const std::string& head_body,
                        const std::string& tail, const std::string& tail_body,
                        const RotationInput& rotation, const Eigen::Vector3d& p,
                        std::int64_t stamp) {
    Begin([=] {
      return "{op: pose, of: " + YamlName(head) + Field("body", head_body) +
             ", wrt: " + YamlName(tail) + Field("ref_body", tail_body) +
             ", position: " + YamlVector(p) + ", rotation: " + YamlRotation(rotation) +
             ", stamp: " + StampText(stamp) + "}";
    });
    const core::PoseSpec spec = core::PoseSpec::Of(head, head_body).RelativeTo(tail, tail_body);
    const core::Stamp s = core::Stamp::Nanoseconds(stamp);
    const auto result = rotation.is_matrix ? graph_.AddPose(spec, rotation.R, p, s)
                                           : graph_.AddPose(spec, rotation.q, p, s);
    return Finish(result, model_.AddPose(head, head_body, tail, tail_body, rotation, p, stamp));
  }

  ErrorCode StampedTwist(const std::string& point, const std::string& body,
                         const std::string& ref_body, const std::string& coord,
                         const Eigen::Vector3d& v, const Eigen::Vector3d& w, std::int64_t stamp) {
    Begin([=] {
      return "{op: twist, point: " + YamlName(point) + Field("body", body) +
             ", ref_body: " + YamlName(ref_body) + ", coord: " + YamlName(coord) +
             ", linear: " + YamlVector(v) + ", angular: " + YamlVector(w) +
             ", stamp: " + StampText(stamp) + "}";
    });
    const core::TwistSpec spec =
        core::TwistSpec::Of(point, body).RelativeTo(ref_body).ExpressedIn(coord);
    return Finish(graph_.AddTwist(spec, v, w, core::Stamp::Nanoseconds(stamp)),
                  model_.AddTwist(point, body, ref_body, coord, v, w, stamp));
  }

  /// A query under a time policy, one-shot and compiled: same code, same value (unless the
  /// model reports an interpolation across a half turn, which the spec leaves open), the same
  /// time answered and extrapolated flag, and when not extrapolated the same oldest / newest
  /// stamps read.
  void AskTimed(const Query& q, const reference::TimeQuery& policy) {
    Begin([=] { return QueryText(q) + "   # time: " + PolicyText(policy); });
    const std::string before = CurrentDump();
    const reference::TimedAnswer expected = model_.AskAt(q, policy);
    const core::TimePolicy kernel_policy = KernelTimePolicy(policy);
    core::TimeReport report;
    const Outcome got = OneShotTimed(q, kernel_policy, &report);
    Annotate(got.code);
    CompareTimed("timed query", expected, got, report);
    if (CompileComparable(q)) {
      // Compiling fails as the untimed query does; the policy's errors come at evaluation.
      core::TimeReport compiled_report;
      bool compile_failed = false;
      const Outcome compiled = CompiledTimed(q, kernel_policy, &compiled_report, &compile_failed);
      if (compile_failed) {
        CompareAnswer("compiling the timed query", model_.Ask(q), compiled);
      } else {
        CompareTimed("compiled timed query", expected, compiled, compiled_report);
      }
    }
    if (Dump(graph_) != before) Fail("a timed query changed the graph's Dump()");
  }

  ErrorCode RemovePose(const std::string& of, const std::string& wrt) {
    Begin([=] {
      return "{op: remove, kind: pose, of: " + YamlName(of) + ", wrt: " + YamlName(wrt) + "}";
    });
    std::string joint_twist;  // the joint's twist edge goes with its pose edge
    for (const reference::Joint& j : model_.joints()) {
      if (j.child == of && j.parent == wrt)
        joint_twist = ReferenceModel::TwistKey(j.parent_body, of);
    }
    const ErrorCode expected = model_.RemovePose(of, wrt);
    if (expected == ErrorCode::kOk) Removed(ReferenceModel::PoseKey(wrt, of));  // before CheckKept
    if (expected == ErrorCode::kOk && !joint_twist.empty()) Removed(joint_twist);
    return Finish(graph_.RemovePose(of, wrt), expected);
  }

  ErrorCode RemoveTwist(const std::string& point, const std::string& ref_body) {
    Begin([=] {
      return "{op: remove, kind: twist, point: " + YamlName(point) +
             ", ref_body: " + YamlName(ref_body) + "}";
    });
    const ErrorCode expected = model_.RemoveTwist(point, ref_body);
    if (expected == ErrorCode::kOk) Removed(ReferenceModel::TwistKey(ref_body, point));
    return Finish(graph_.RemoveTwist(point, ref_body), expected);
  }

  // ---------------------------------------------------------------- wrenches

  /// WrenchCoord(point|on, by, [coord]) = (f, m) added or updated (docs/dynamics.md §7).
  ErrorCode Wrench(const std::string& on, const std::string& by, const std::string& point,
                   const std::string& coord, const Eigen::Vector3d& f, const Eigen::Vector3d& m) {
    Begin([=] {
      return "{op: wrench, on: " + YamlName(on) + ", by: " + YamlName(by) +
             ", point: " + YamlName(point) + ", coord: " + YamlName(coord) +
             ", force: " + YamlVector(f) + ", moment: " + YamlVector(m) + "}";
    });
    const auto spec = core::WrenchSpec::On(on).By(by).At(point).ExpressedIn(coord);
    return Finish(graph_.AddWrench(spec, f, m), model_.AddWrench(on, by, point, coord, f, m));
  }

  ErrorCode RemoveWrench(const std::string& on, const std::string& by) {
    Begin([=] {
      return "{op: remove, kind: wrench, on: " + YamlName(on) + ", by: " + YamlName(by) + "}";
    });
    std::uint64_t serial = 0;
    const bool stored = model_.FindWrench(on, by, &serial) == ErrorCode::kOk;
    const ErrorCode expected = model_.RemoveWrench(on, by);
    if (expected == ErrorCode::kOk && stored) {  // kept compiled queries summing it: invalid
      for (KeptWrench& k : kept_wrenches_) {
        if (std::find(k.serials.begin(), k.serials.end(), serial) != k.serials.end()) {
          k.invalidated = true;
        }
      }
    }
    return Finish(graph_.RemoveWrench(on, by), expected);
  }

  /// A wrench query compiled and kept: re-evaluated after every later op (CheckKept) against
  /// the model's sum of the same terms with their current values; query_invalidated once one
  /// of its wrenches or a pose edge on a term's path (the pose of s wrt the point and [r]) was
  /// removed.
  void KeepWrench(const std::string& on, const std::string& by, const std::string& point,
                  const std::string& coord) {
    Begin([=] {
      return "# keep compiled {kind: wrench, on: " + YamlName(on) + Field("by", by) +
             ", point: " + YamlName(point) + ", coord: " + YamlName(coord) + "}";
    });
    const reference::WrenchAnswer expected = model_.AskWrench(on, by, point, coord);
    auto compiled =
        graph_.CompileWrench(core::WrenchSpec::On(on).By(by).At(point).ExpressedIn(coord));
    Eigen::Vector3d f = Eigen::Vector3d::Zero(), m = Eigen::Vector3d::Zero();
    const ErrorCode code = compiled ? compiled->Evaluate(f, m) : compiled.error().code;
    Annotate(code);
    CompareWrench("kept compiled wrench query", expected, code, f, m);
    if (code != ErrorCode::kOk) return;
    KeptWrench k{on, point, coord, model_.WrenchTerms(on, by), {}, false, std::move(*compiled)};
    for (const reference::WrenchEntry& w : model_.wrenches()) {
      if (std::find(k.serials.begin(), k.serials.end(), w.serial) == k.serials.end()) continue;
      Query q;  // the pose of (s, [s]) wrt (point, [coord]): the term's pose path
      q.kind = QueryKind::kPose;
      q.point = q.orientation = w.frame;
      q.ref_point = point;
      q.ref_orientation = q.coord = coord;
      const std::set<std::string> used = model_.UsedEdges(q);
      k.used.insert(used.begin(), used.end());
    }
    if (kept_wrenches_.size() >= kMaxKept) kept_wrenches_.pop_front();
    kept_wrenches_.push_back(std::move(k));
  }

  /// FindWrench(on, by): the same code as the model; a handle found is kept (at most 8) for
  /// SetWrenchByHandle.
  ErrorCode WrenchHandle(const std::string& on, const std::string& by) {
    const std::size_t kept = wrench_handles_.size();
    Begin([=] {
      return "# handle of the wrench on " + YamlName(on) + " by " + YamlName(by) + " (kept " +
             std::to_string(kept) + ")";
    });
    std::uint64_t serial = 0;
    const ErrorCode expected = model_.FindWrench(on, by, &serial);
    const auto h = graph_.FindWrench(on, by);
    const ErrorCode code = h ? ErrorCode::kOk : h.error().code;
    Annotate(code);
    if (code != expected) {
      Fail("FindWrench: kernel says " + std::string(base::ToString(code)) + ", model says " +
           std::string(base::ToString(expected)));
    }
    if (h && wrench_handles_.size() < 8) wrench_handles_.push_back({on, by, serial, *h});
    return code;
  }

  /// SetWrench through kept handle `which` (modulo their number; none kept: nothing), in the
  /// stored form: the model's code, the graph's Dump() unchanged when refused, the state after.
  ErrorCode SetWrenchByHandle(std::uint32_t which, const Eigen::Vector3d& f,
                              const Eigen::Vector3d& m) {
    if (wrench_handles_.empty()) return ErrorCode::kOk;
    const KeptWrenchHandle& k = wrench_handles_[which % wrench_handles_.size()];
    Begin([=] {
      return "# SetWrench by the handle of the wrench on " + YamlName(k.on) + " by " +
             YamlName(k.by) + ": force " + YamlVector(f) + ", moment " + YamlVector(m);
    });
    const std::string before = CurrentDump();
    const ErrorCode expected = model_.SetWrench(k.on, k.by, k.serial, f, m);
    const ErrorCode code = graph_.SetWrench(k.handle, f, m);
    Annotate(code);
    if (code != expected) {
      Fail("SetWrench: kernel says " + std::string(base::ToString(code)) + ", model says " +
           std::string(base::ToString(expected)));
    }
    if (code != ErrorCode::kOk) {
      if (Dump(graph_) != before) Fail("a refused SetWrench changed the graph's Dump()");
      return code;
    }
    dump_valid_ = false;
    if (checks_) {
      CompareState();
      CheckKept();
    }
    return code;
  }

  /// A wrench query (by empty: the net wrench), one-shot and compiled.
  void AskWrench(const std::string& on, const std::string& by, const std::string& point,
                 const std::string& coord) {
    Begin([=] {
      return "# query {kind: wrench, on: " + YamlName(on) + Field("by", by) +
             ", point: " + YamlName(point) + ", coord: " + YamlName(coord) + "}";
    });
    const std::string before = CurrentDump();
    const reference::WrenchAnswer expected = model_.AskWrench(on, by, point, coord);
    const auto spec = core::WrenchSpec::On(on).By(by).At(point).ExpressedIn(coord);
    const auto got = graph_.GetWrench(spec);
    const ErrorCode code = got ? ErrorCode::kOk : got.error().code;
    Annotate(code);
    CompareWrench("wrench query", expected, code, got ? got->force : Eigen::Vector3d::Zero(),
                  got ? got->moment : Eigen::Vector3d::Zero());
    const auto compiled = graph_.CompileWrench(spec);
    if (!compiled) {
      CompareWrench("compiled wrench query", expected, compiled.error().code,
                    Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    } else {
      Eigen::Vector3d f, m;
      CompareWrench("compiled wrench query", expected, compiled->Evaluate(f, m), f, m);
    }
    if (Dump(graph_) != before) Fail("a wrench query changed the graph's Dump()");
    CheckKept();
  }

  // ---------------------------------------------------------------- accelerations

  /// AddTwist with an acceleration (a, alpha) at the same point, in the same frame.
  ErrorCode TwistWithAcceleration(const std::string& point, const std::string& body,
                                  const std::string& ref_body, const std::string& coord,
                                  const Eigen::Vector3d& v, const Eigen::Vector3d& w,
                                  const Eigen::Vector3d& a, const Eigen::Vector3d& alpha) {
    Begin([=] {
      return "{op: twist, point: " + YamlName(point) + Field("body", body) +
             ", ref_body: " + YamlName(ref_body) + ", coord: " + YamlName(coord) +
             ", linear: " + YamlVector(v) + ", angular: " + YamlVector(w) +
             ", acceleration: {linear: " + YamlVector(a) + ", angular: " + YamlVector(alpha) + "}}";
    });
    const core::TwistSpec spec =
        core::TwistSpec::Of(point, body).RelativeTo(ref_body).ExpressedIn(coord);
    const reference::AccelerationIn acc{a, alpha};
    return Finish(graph_.AddTwist(spec, v, w, core::AccelerationInput{a, alpha}),
                  model_.AddTwist(point, body, ref_body, coord, v, w, std::nullopt, nullptr, &acc));
  }

  /// A stamped twist sample with its acceleration (docs/dynamics.md §7.2).
  ErrorCode StampedTwistWithAcceleration(const std::string& point, const std::string& body,
                                         const std::string& ref_body, const std::string& coord,
                                         const Eigen::Vector3d& v, const Eigen::Vector3d& w,
                                         const Eigen::Vector3d& a, const Eigen::Vector3d& alpha,
                                         std::int64_t stamp) {
    Begin([=] {
      return "{op: twist, point: " + YamlName(point) + Field("body", body) +
             ", ref_body: " + YamlName(ref_body) + ", coord: " + YamlName(coord) +
             ", linear: " + YamlVector(v) + ", angular: " + YamlVector(w) +
             ", acceleration: {linear: " + YamlVector(a) + ", angular: " + YamlVector(alpha) +
             "}, stamp: " + StampText(stamp) + "}";
    });
    const core::TwistSpec spec =
        core::TwistSpec::Of(point, body).RelativeTo(ref_body).ExpressedIn(coord);
    const reference::AccelerationIn acc{a, alpha};
    return Finish(graph_.AddTwist(spec, v, w, core::Stamp::Nanoseconds(stamp),
                                  core::AccelerationInput{a, alpha}),
                  model_.AddTwist(point, body, ref_body, coord, v, w, stamp, nullptr, &acc));
  }

  /// AddAcceleration: AccelerationCoord(point|body, ref_body, [coord]) = (a, alpha); with a
  /// stamp, the acceleration of the twist sample at that stamp.
  ErrorCode Acceleration(const std::string& point, const std::string& body,
                         const std::string& ref_body, const std::string& coord,
                         const Eigen::Vector3d& a, const Eigen::Vector3d& alpha,
                         std::optional<std::int64_t> stamp = std::nullopt) {
    Begin([=] {
      return "{op: acceleration, point: " + YamlName(point) + Field("body", body) +
             ", ref_body: " + YamlName(ref_body) + ", coord: " + YamlName(coord) +
             ", linear: " + YamlVector(a) + ", angular: " + YamlVector(alpha) +
             (stamp ? ", stamp: " + StampText(*stamp) : std::string()) + "}";
    });
    const core::TwistSpec spec =
        core::TwistSpec::Of(point, body).RelativeTo(ref_body).ExpressedIn(coord);
    return Finish(stamp ? graph_.AddAcceleration(spec, a, alpha, core::Stamp::Nanoseconds(*stamp))
                        : graph_.AddAcceleration(spec, a, alpha),
                  model_.AddAcceleration(point, body, ref_body, coord, a, alpha, stamp));
  }

  /// FindTwistEdge(of, wrt): the model's code; a handle found is kept (at most 8).
  ErrorCode TwistHandle(const std::string& of, const std::string& wrt) {
    const std::size_t kept = twist_handles_.size();
    Begin([=] {
      return "# handle of the twist edge " + YamlName(wrt) + " -> " + YamlName(of) + " (kept " +
             std::to_string(kept) + ")";
    });
    std::uint64_t serial = 0;
    const ErrorCode expected = model_.FindTwist(of, wrt, &serial);
    const auto h = graph_.FindTwistEdge(of, wrt);
    const ErrorCode code = h ? ErrorCode::kOk : h.error().code;
    Annotate(code);
    if (code != expected) {
      Fail("FindTwistEdge: kernel says " + std::string(base::ToString(code)) + ", model says " +
           std::string(base::ToString(expected)));
    }
    if (h && twist_handles_.size() < 8) twist_handles_.push_back({of, wrt, serial, *h});
    return code;
  }

  /// FindTwistEdge(of, wrt, coord), a converting handle: the codes of FindTwistEdge, then
  /// invalid_name / unknown_frame (coord), twist_not_convertible; kept (at most 8) with the pose
  /// edges of its conversion ([coord] wrt [of]) for SetTwistConverted.
  ErrorCode ConvertingTwistHandle(const std::string& of, const std::string& wrt,
                                  const std::string& coord) {
    const std::size_t kept = converting_handles_.size();
    Begin([=] {
      return "# converting handle of the twist edge " + YamlName(wrt) + " -> " + YamlName(of) +
             " taking twists in [" + YamlName(coord) + "] (kept " + std::to_string(kept) + ")";
    });
    std::uint64_t serial = 0;
    ErrorCode expected = model_.FindTwist(of, wrt, &serial);
    if (expected == ErrorCode::kOk && !ReferenceModel::ValidName(coord)) {
      expected = ErrorCode::kInvalidName;
    } else if (expected == ErrorCode::kOk && !model_.frames().count(coord)) {
      expected = ErrorCode::kUnknownFrame;
    }
    std::set<std::string> used;
    if (expected == ErrorCode::kOk && coord != of) {
      Query q;  // the orientation of [coord] wrt [of]: the pose edges between them
      q.kind = QueryKind::kOrientation;
      q.orientation = coord;
      q.ref_orientation = q.coord = of;
      if (model_.Ask(q).code != ErrorCode::kOk) {
        expected = ErrorCode::kTwistNotConvertible;
      } else {
        used = model_.UsedEdges(q);
      }
    }
    const auto h = graph_.FindTwistEdge(of, wrt, coord);
    const ErrorCode code = h ? ErrorCode::kOk : h.error().code;
    Annotate(code);
    if (code != expected) {
      Fail("FindTwistEdge (converting): kernel says " + std::string(base::ToString(code)) +
           ", model says " + std::string(base::ToString(expected)));
    }
    if (h && converting_handles_.size() < 8) {
      converting_handles_.push_back({of, wrt, coord, serial, std::move(used), false, *h});
    }
    return code;
  }

  /// SetTwist through kept converting handle `which` (none kept: nothing): (v, w) in [coord]
  /// rotated into [of] with the current poses; invalid_number -> query_invalidated (a pose
  /// edge of the conversion removed or reversed since the handle was made) -> SetTwist's codes.
  ErrorCode SetTwistConverted(std::uint32_t which, const Eigen::Vector3d& v,
                              const Eigen::Vector3d& w) {
    if (converting_handles_.empty()) return ErrorCode::kOk;
    const KeptConvertingHandle& k = converting_handles_[which % converting_handles_.size()];
    Begin([=] {
      return "# SetTwist by the converting handle of the twist edge " + YamlName(k.wrt) + " -> " +
             YamlName(k.of) + " in [" + YamlName(k.coord) + "]: " + YamlVector(v) + ", " +
             YamlVector(w);
    });
    const std::string before = CurrentDump();
    ErrorCode expected = ErrorCode::kOk;
    if (!std::isfinite(v.sum()) || !std::isfinite(w.sum()) || v.cwiseAbs().maxCoeff() > 1e12 ||
        w.cwiseAbs().maxCoeff() > 1e12) {
      expected = ErrorCode::kInvalidNumber;
    } else if (k.invalidated) {
      expected = ErrorCode::kQueryInvalidated;
    } else {
      Query q;
      q.kind = QueryKind::kOrientation;
      q.orientation = k.coord;
      q.ref_orientation = q.coord = k.of;
      const Answer R = model_.Ask(q);  // R_HR (ok: no edge of the conversion was removed)
      expected = R.code != ErrorCode::kOk ? R.code : model_.SetTwist(k.serial, R.M * v, R.M * w);
    }
    const ErrorCode code = graph_.SetTwist(k.handle, v, w);
    Annotate(code);
    if (code != expected) {
      Fail("SetTwist (converting): kernel says " + std::string(base::ToString(code)) +
           ", model says " + std::string(base::ToString(expected)));
    }
    if (code != ErrorCode::kOk) {
      if (Dump(graph_) != before) Fail("a refused handle update changed the graph's Dump()");
      return code;
    }
    dump_valid_ = false;
    if (checks_) {
      CompareState();
      CheckKept();
    }
    return code;
  }

  /// Through kept twist handle `which` (modulo their number; none kept: nothing): SetTwist
  /// (`acceleration` false, clears the edge's acceleration) or SetAcceleration, edge form.
  /// With `stamp` (acceleration only): SetAcceleration of the twist sample at that stamp.
  ErrorCode SetByTwistHandle(std::uint32_t which, bool acceleration, const Eigen::Vector3d& x,
                             const Eigen::Vector3d& y,
                             std::optional<std::int64_t> stamp = std::nullopt) {
    if (twist_handles_.empty()) return ErrorCode::kOk;
    const KeptTwistHandle& k = twist_handles_[which % twist_handles_.size()];
    Begin([=] {
      return std::string("# ") + (acceleration ? "SetAcceleration" : "SetTwist") +
             " by the handle of the twist edge " + YamlName(k.wrt) + " -> " + YamlName(k.of) +
             ": " + YamlVector(x) + ", " + YamlVector(y) +
             (stamp ? ", stamp " + StampText(*stamp) : std::string());
    });
    const std::string before = CurrentDump();
    const ErrorCode expected = acceleration ? model_.SetAcceleration(k.serial, x, y, stamp)
                                            : model_.SetTwist(k.serial, x, y);
    const ErrorCode code =
        acceleration
            ? (stamp ? graph_.SetAcceleration(k.handle, x, y, core::Stamp::Nanoseconds(*stamp))
                     : graph_.SetAcceleration(k.handle, x, y))
            : graph_.SetTwist(k.handle, x, y);
    Annotate(code);
    if (code != expected) {
      Fail(std::string(acceleration ? "SetAcceleration" : "SetTwist") + ": kernel says " +
           std::string(base::ToString(code)) + ", model says " +
           std::string(base::ToString(expected)));
    }
    if (code != ErrorCode::kOk) {
      if (Dump(graph_) != before) Fail("a refused handle update changed the graph's Dump()");
      return code;
    }
    dump_valid_ = false;
    if (checks_) {
      CompareState();
      CheckKept();
    }
    return code;
  }

  /// An acceleration query (q.kind kTwist / kLinearVelocity / kAngularVelocity: acceleration,
  /// linear, angular), one-shot through its own call and compiled (CompileAcceleration; the
  /// angular one at the coordinate frame's origin, as angular velocities).
  void AskAcceleration(const Query& q) {
    Begin([=] { return AccelerationQueryText(q); });
    const std::string before = CurrentDump();
    const reference::AccelerationAnswer expected = model_.AskAcceleration(q);
    const Outcome got = OneShotAcceleration(q);
    Annotate(got.code);
    CompareAcceleration("acceleration query", expected, got);
    if (CompileComparable(q)) {
      CompareAcceleration("compiled acceleration query", expected,
                          CompiledAccelerationOutcome(q, nullptr));
    }
    if (Dump(graph_) != before) Fail("an acceleration query changed the graph's Dump()");
    CheckKept();
  }

  /// An acceleration query under a time policy, one-shot (GetAcceleration / GetLinear... /
  /// GetAngular... with the policy) and compiled (Evaluate with the policy): the model's code,
  /// value (unless it interpolated a pose across a half turn), time answered, extrapolated flag
  /// and, when not extrapolated, the stamps read.
  void AskAccelerationTimed(const Query& q, const reference::TimeQuery& policy) {
    Begin([=] { return AccelerationQueryText(q) + "   # time: " + PolicyText(policy); });
    const std::string before = CurrentDump();
    const ReferenceModel::TimedAcceleration expected = model_.AskAccelerationAt(q, policy);
    const core::TimePolicy kernel_policy = KernelTimePolicy(policy);
    core::TimeReport report;
    const Outcome got = OneShotTimedAcceleration(q, kernel_policy, &report);
    Annotate(got.code);
    CompareTimedAcceleration("timed acceleration query", expected, got, report);
    if (CompileComparable(q)) {
      core::TwistSpec spec = TwistSpecOf(q);
      if (q.kind == QueryKind::kAngularVelocity) spec.point = spec.coordinate_frame;
      auto compiled = graph_.CompileAcceleration(spec);
      if (!compiled) {  // as the untimed query's compile
        Outcome c = Code(compiled);
        reference::AccelerationAnswer untimed = model_.AskAcceleration(q);
        if (untimed.code == ErrorCode::kNoAcceleration) untimed.code = ErrorCode::kOk;
        if (c.code != untimed.code) {
          Fail("compiling the timed acceleration query: kernel says " +
               std::string(base::ToString(c.code)) + ", model says " +
               std::string(base::ToString(untimed.code)));
        }
      } else {
        Outcome c;
        core::TimeReport compiled_report;
        c.code = compiled->Evaluate(c.v, c.w, kernel_policy, compiled_report);
        if (q.kind == QueryKind::kLinearVelocity) c.w.setZero();
        if (q.kind == QueryKind::kAngularVelocity) c.v.setZero();
        CompareTimedAcceleration("compiled timed acceleration query", expected, c, compiled_report);
      }
    }
    if (Dump(graph_) != before) Fail("a timed acceleration query changed the graph's Dump()");
    CheckKept();
  }

  /// An acceleration query compiled and kept: re-evaluated after every later op (CheckKept),
  /// query_invalidated exactly when an edge of its twist query (UsedEdges) was removed, else
  /// the model's answer of that moment (no_acceleration included).
  void KeepAcceleration(const Query& q) {
    Begin([=] { return "# keep compiled " + AccelerationQueryText(q); });
    Kept k;
    k.query = q;
    k.acceleration = true;
    const reference::AccelerationAnswer expected = model_.AskAcceleration(q);
    const Outcome compiled = CompiledAccelerationOutcome(q, &k.compiled);
    Annotate(compiled.code);
    if (!CompileComparable(q)) return;
    CompareAcceleration("kept compiled acceleration query", expected, compiled);
    if (std::holds_alternative<std::monostate>(k.compiled)) return;  // compiling failed
    const std::string& own = q.kind == QueryKind::kAngularVelocity ? q.coord : q.point;
    k.zero_twist = (q.body.empty() ? model_.frames().at(own) : q.body) == q.ref_body;
    if (!k.zero_twist) k.used = model_.UsedEdges(q);
    if (kept_.size() >= kMaxKept) kept_.pop_front();
    kept_.push_back(std::move(k));
  }

  /// A one-shot query, and the same query compiled and evaluated once.
  void Ask(const Query& q) {
    Begin([=] { return QueryText(q); });
    const std::string before = CurrentDump();
    const Answer expected = model_.Ask(q);
    const Outcome got = OneShot(q);
    Annotate(got.code);
    CompareAnswer("query", expected, got);
    const Outcome compiled = Compiled(q, nullptr);
    if (CompileComparable(q)) CompareAnswer("compiled query", expected, compiled);
    if (Dump(graph_) != before) Fail("a query changed the graph's Dump()");
    CheckKept();
  }

  /// Compiles `q` and keeps it: it is re-evaluated after every later op (see the file comment).
  void Keep(const Query& q) {
    Begin([=] { return "# keep compiled " + QueryText(q); });
    Kept k;
    k.query = q;
    const Answer expected = model_.Ask(q);
    const Outcome compiled = Compiled(q, &k.compiled);
    Annotate(compiled.code);
    if (!CompileComparable(q)) return;
    CompareAnswer("compiled query", expected, compiled);
    if (compiled.code != ErrorCode::kOk) return;
    // A velocity of C relative to C is zero. The library's compiled form reads no edge then, so
    // it never becomes invalid, even when a removal puts the point and [r] in different trees
    // (where the one-shot query says no_pose_path). The spec does not say whether such a query
    // "uses" the pose edges between e and [r] (reported as an ambiguity): accept zero, valid.
    const bool twist_kind = q.kind == QueryKind::kTwist || q.kind == QueryKind::kLinearVelocity ||
                            q.kind == QueryKind::kAngularVelocity;
    const std::string& own = q.kind == QueryKind::kAngularVelocity ? q.coord : q.point;
    k.zero_twist = twist_kind && (q.body.empty() ? model_.frames().at(own) : q.body) == q.ref_body;
    if (!k.zero_twist) k.used = model_.UsedEdges(q);
    if (kept_.size() >= kMaxKept) kept_.pop_front();
    kept_.push_back(std::move(k));
  }

  /// The final comparison. kFull: the edge-form pose of every frame wrt every frame, and the
  /// twist of every body wrt every other body at every frame (in its axes). kLight (for the
  /// fuzzer's throughput): the pose of every frame wrt every frame of its tree, and at the
  /// first frame of each tree the twist of every body wrt every other body that has a twist
  /// edge in that tree.
  enum class Sweep { kFull, kLight };
  void SweepQueries(Sweep mode = Sweep::kFull) {
    std::map<std::string, std::string> tree;  // frame -> first frame of its tree
    for (const auto& [f, body] : model_.frames()) tree[f] = f;
    for (bool changed = true; changed;) {  // smallest frame name per tree, by relaxation
      changed = false;
      for (const reference::PoseEdge& e : model_.poses()) {
        const std::string m = std::min(tree[e.tail], tree[e.head]);
        if (tree[e.tail] != m || tree[e.head] != m) tree[e.tail] = tree[e.head] = m, changed = true;
      }
    }
    for (const auto& [x, tx] : tree) {
      for (const auto& [y, ty] : tree) {
        if (mode == Sweep::kLight && tx != ty) continue;
        Query q;
        q.kind = QueryKind::kPose;
        q.point = q.orientation = x;
        q.ref_point = q.ref_orientation = q.coord = y;
        Check(q);
      }
      std::set<std::string> bodies(model_.bodies().begin(), model_.bodies().end());
      if (mode == Sweep::kLight) {
        if (tx != x) continue;
        bodies.clear();
        for (const reference::TwistEdge& t : model_.twists()) {
          if (tree[t.head] == tx) bodies.insert({t.tail_body, model_.frames().at(t.head)});
        }
      }
      for (const std::string& C : bodies) {
        for (const std::string& D : bodies) {
          if (C == D) continue;
          Query q;
          q.kind = QueryKind::kTwist;
          q.point = q.coord = x;
          q.body = C;
          q.ref_body = D;
          Check(q);
          if (mode == Sweep::kLight) CheckAcceleration(q);
        }
      }
    }
  }

  std::size_t num_ops() const { return trace_.size(); }
  /// With checks off, an op only compares the kernel's code with the model's: for replaying a
  /// prefix that was checked before (exhaustive_small_scope). Queries always check everything.
  void set_checks(bool on) { checks_ = on; }

  /// Forgets the last op's trace line (a caller that explores alternatives after a rejection).
  void PopTrace() { trace_.pop_back(); }

 private:
  static constexpr std::size_t kMaxKept = 6;
  using CompiledAny = std::variant<std::monostate, core::CompiledPose<B>, core::CompiledPosition<B>,
                                   core::CompiledOrientation<B>, core::CompiledTwist<B>,
                                   core::CompiledAcceleration<B>>;
  struct Outcome {
    ErrorCode code = ErrorCode::kOk;
    Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
    Eigen::Vector3d p = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero(),
                    w = Eigen::Vector3d::Zero();
  };
  struct Kept {
    Query query;
    CompiledAny compiled;
    std::set<std::string> used;
    bool invalidated = false;   // an edge in `used` was removed since compiling
    bool zero_twist = false;    // a velocity of a body relative to itself (see Keep)
    bool acceleration = false;  // an acceleration query (KeepAcceleration)
  };
  struct KeptTwistHandle {
    std::string of, wrt;
    std::uint64_t serial = 0;
    core::TwistHandle handle;
  };
  std::vector<KeptTwistHandle> twist_handles_;
  struct KeptConvertingHandle {
    std::string of, wrt, coord;
    std::uint64_t serial = 0;
    std::set<std::string> used;  // the pose edges of its conversion
    bool invalidated = false;    // one of them removed or reversed since it was made
    core::ConvertingTwistHandle<B> handle;
  };
  std::vector<KeptConvertingHandle> converting_handles_;

  // An acceleration query through its own call (GetAcceleration, GetLinearAcceleration,
  // GetAngularAcceleration); the value as Outcome's v (a) and w (alpha).
  Outcome OneShotAcceleration(const Query& q) const {
    Outcome o;
    const core::TwistSpec spec = TwistSpecOf(q);
    switch (q.kind) {
      case QueryKind::kLinearVelocity: {
        const auto r = graph_.GetLinearAcceleration(spec);
        if (!r) return Code(r);
        o.v = r->value;
        return o;
      }
      case QueryKind::kAngularVelocity: {
        const auto r = graph_.GetAngularAcceleration(spec);
        if (!r) return Code(r);
        o.w = r->value;
        return o;
      }
      default: {
        const auto r = graph_.GetAcceleration(spec);
        if (!r) return Code(r);
        o.v = r->linear;
        o.w = r->angular;
        return o;
      }
    }
  }

  // The timed one-shot acceleration queries; the value as Outcome's v (a) and w (alpha).
  Outcome OneShotTimedAcceleration(const Query& q, const core::TimePolicy& policy,
                                   core::TimeReport* report) const {
    Outcome o;
    const core::TwistSpec spec = TwistSpecOf(q);
    const auto take = [&](const auto& r) {
      if (!r) {
        o.code = r.error().code;
        return false;
      }
      *report = r->time;
      return true;
    };
    switch (q.kind) {
      case QueryKind::kLinearVelocity: {
        const auto r = graph_.GetLinearAcceleration(spec, policy);
        if (take(r)) o.v = r->value.value;
        return o;
      }
      case QueryKind::kAngularVelocity: {
        const auto r = graph_.GetAngularAcceleration(spec, policy);
        if (take(r)) o.w = r->value.value;
        return o;
      }
      default: {
        const auto r = graph_.GetAcceleration(spec, policy);
        if (take(r)) o.v = r->value.linear, o.w = r->value.angular;
        return o;
      }
    }
  }

  void CompareTimedAcceleration(const std::string& what,
                                const ReferenceModel::TimedAcceleration& expected,
                                const Outcome& got, const core::TimeReport& report) {
    if (expected.ambiguous) {  // only the decision
      if (got.code != expected.answer.code) {
        Fail(what + ": kernel says " + std::string(base::ToString(got.code)) + ", model says " +
             std::string(base::ToString(expected.answer.code)));
      }
    } else {
      CompareAcceleration(what, expected.answer, got);
    }
    if (got.code != ErrorCode::kOk) return;
    reference::TimedAnswer t;  // the report's checks, as for a timed twist query
    t.time = expected.time, t.oldest = expected.oldest, t.newest = expected.newest;
    t.extrapolated = expected.extrapolated;
    CompareReport(what, t, report);
  }

  // CompileAcceleration (an angular one at the coordinate frame's origin), kept in *keep when
  // compiled, and evaluated once.
  Outcome CompiledAccelerationOutcome(const Query& q, CompiledAny* keep) const {
    core::TwistSpec spec = TwistSpecOf(q);
    if (q.kind == QueryKind::kAngularVelocity) spec.point = spec.coordinate_frame;
    auto r = graph_.CompileAcceleration(spec);
    if (!r) return Code(r);
    CompiledAny c = std::move(*r);
    const Outcome o = Evaluate(c, q.kind);
    if (keep) *keep = std::move(c);
    return o;
  }

  // Rounding of composed accelerations: every edge's own numbers, moved along lever arms up to
  // the scene's positions (alpha x r, w x (w x r)), and the products of angular velocities with
  // the twists of the other edges (Coriolis, w x w).
  double AccelerationScale() const {
    const double lever = PositionScale();
    double own = 1.0, W = 0.0, V = 0.0;
    for (const reference::TwistEdge& t : model_.twists()) {
      const double w = t.w.norm();
      own += t.a.norm() + t.alpha.norm() * lever + w * w * lever;
      W += w;
      V += t.v.norm() + w * lever;
    }
    return own + 2.0 * W * (V + W);
  }

  void CompareAcceleration(const std::string& what, const reference::AccelerationAnswer& expected,
                           const Outcome& got) {
    if (got.code != expected.code) {
      Fail(what + ": kernel says " + std::string(base::ToString(got.code)) + ", model says " +
           std::string(base::ToString(expected.code)));
    }
    if (got.code != ErrorCode::kOk) return;
    const double tol = 1e-9 * std::max(AccelerationScale(), expected.a.norm());
    if (!Near(got.v, expected.a, tol) || !Near(got.w, expected.alpha, tol)) {
      const Eigen::IOFormat fmt(17, Eigen::DontAlignCols, ", ", "; ", "", "", "[", "]");
      std::ostringstream out;
      out << what << ": values differ (tolerance " << tol << ")\n  kernel a "
          << got.v.transpose().format(fmt) << " alpha " << got.w.transpose().format(fmt)
          << "\n  model  a " << expected.a.transpose().format(fmt) << " alpha "
          << expected.alpha.transpose().format(fmt);
      Fail(out.str());
    }
  }

  // Every twist edge's acceleration: present in the kernel exactly when in the model, the same
  // edge-form values.
  void CompareAccelerations() {
    const double tol = 1e-9 * AccelerationScale();
    for (const reference::TwistEdge& t : model_.twists()) {
      const auto A = graph_.acceleration_value(graph_.FindFrame(t.head));
      const std::string edge = "the twist edge " + t.tail_body + " -> " + t.head;
      if (A.has_value() != t.has_A) {
        Fail(edge + (t.has_A ? " has no acceleration in the kernel, one in the model"
                             : " has an acceleration in the kernel, none in the model"));
      }
      if (A && (!Near(A->linear, t.a, tol) || !Near(A->angular, t.alpha, tol))) {
        const Eigen::IOFormat fmt(17, Eigen::DontAlignCols, ", ", "; ", "", "", "[", "]");
        std::ostringstream out;
        out << "stored acceleration of " << edge << " differs\n  kernel a "
            << A->linear.transpose().format(fmt) << " alpha " << A->angular.transpose().format(fmt)
            << "\n  model  a " << t.a.transpose().format(fmt) << " alpha "
            << t.alpha.transpose().format(fmt);
        Fail(out.str());
      }
    }
  }

  // The trace keeps each op's text unrendered (formatting every number of every op would cost
  // more than the checks) and the kernel's result.
  struct TraceLine {
    std::function<std::string()> render;
    std::optional<ErrorCode> code;
    std::string note;  // e.g. the repair applied
  };
  void Begin(std::function<std::string()> render) {
    trace_.push_back(TraceLine{std::move(render), std::nullopt, {}});
    if (checks_) {
      before_ = CurrentDump();
      covariances_before_ = Covariances();  // Dump() does not show covariances
    }
  }
  static core::CovarianceInput KernelCovariance(const reference::CovarianceIn* cov) {
    core::CovarianceInput in;
    if (cov == nullptr) return in;
    in.matrix = &cov->S;
    in.order = cov->angular_linear ? core::CovarianceOrder::kAngularLinear
                                   : core::CovarianceOrder::kLinearAngular;
    in.convention = cov->body ? core::PoseCovarianceConvention::kBody
                              : core::PoseCovarianceConvention::kCoordinates;
    return in;
  }
  // The kernel's stored covariance of every edge the model knows, by edge key.
  std::map<std::string, coord::Covariance6> Covariances() const {
    std::map<std::string, coord::Covariance6> out;
    for (const reference::PoseEdge& e : model_.poses()) {
      out[ReferenceModel::PoseKey(e.tail, e.head)] =
          graph_.pose_covariance(graph_.FindFrame(e.head));
    }
    for (const reference::TwistEdge& t : model_.twists()) {
      out[ReferenceModel::TwistKey(t.tail_body, t.head)] =
          graph_.twist_covariance(graph_.FindFrame(t.head));
    }
    return out;
  }
  void Annotate(ErrorCode code) { trace_.back().code = code; }
  // Dump() of the graph before the current op, cached: only an accepted op changes it.
  const std::string& CurrentDump() {
    if (!dump_valid_) dump_ = Dump(graph_);
    dump_valid_ = true;
    return dump_;
  }

  ErrorCode Finish(const core::BuildResult& result, ErrorCode expected) {
    const ErrorCode code = result ? ErrorCode::kOk : result.error().code;
    Annotate(code);
    if (code != expected) {
      Fail("kernel says " + std::string(base::ToString(code)) + ", model says " +
           std::string(base::ToString(expected)) +
           (result ? std::string() : "\nkernel message: " + result.error().message));
    }
    if (!checks_) {
      if (result) dump_valid_ = false;
      return code;
    }
    if (!result && result.error().message.empty()) Fail("a rejection without a message");
    if (!result && Dump(graph_) != before_) Fail("a rejected op changed the graph's Dump()");
    if (!result && Covariances() != covariances_before_) {
      Fail("a rejected op changed a stored covariance");
    }
    if (result) dump_valid_ = false;
    if (const std::string broken = CheckInvariants(graph_); !broken.empty()) {
      Fail("CheckInvariants() after the op:\n" + broken);
    }
    CompareState();
    CheckKept();
    return code;
  }

  static std::string StampText(std::int64_t ns) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.9f", static_cast<double>(ns) * 1e-9);
    return buf;
  }
  static std::string PolicyText(const reference::TimeQuery& p) {
    std::string s = p.kind == reference::TimeQuery::Kind::kLatest ? "latest"
                    : p.kind == reference::TimeQuery::Kind::kAt
                        ? "at " + StampText(p.t) + " horizon " + StampText(p.horizon)
                        : "latest_common";
    if (p.not_before) s += ", not_before " + StampText(*p.not_before);
    return s;
  }
  static core::TimePolicy KernelTimePolicy(const reference::TimeQuery& p) {
    std::optional<core::Stamp> not_before;
    if (p.not_before) not_before = core::Stamp::Nanoseconds(*p.not_before);
    switch (p.kind) {
      case reference::TimeQuery::Kind::kAt:
        return core::At(core::Stamp::Nanoseconds(p.t), core::Duration::Nanoseconds(p.horizon),
                        not_before);
      case reference::TimeQuery::Kind::kLatestCommon:
        return core::LatestCommon(not_before);
      default:
        return core::Latest(not_before);
    }
  }

  Outcome OneShotTimed(const Query& q, const core::TimePolicy& policy,
                       core::TimeReport* report) const {
    Outcome o;
    const auto take = [&](const auto& r) {
      if (!r) {
        o.code = r.error().code;
        return false;
      }
      *report = r->time;
      return true;
    };
    switch (q.kind) {
      case QueryKind::kPose: {
        const auto r = graph_.GetPose(PoseSpecOf(q), policy);
        if (take(r))
          o.M = B::ToMatrix(B::RotationOf(r->value.value)), o.p = B::TranslationOf(r->value.value);
        break;
      }
      case QueryKind::kPosition: {
        const auto r = graph_.GetPosition(PoseSpecOf(q), policy);
        if (take(r)) o.p = r->value.value;
        break;
      }
      case QueryKind::kOrientation: {
        const auto r = graph_.GetOrientation(PoseSpecOf(q), policy);
        if (take(r)) o.M = B::ToMatrix(r->value.value);
        break;
      }
      case QueryKind::kTwist: {
        const auto r = graph_.GetTwist(TwistSpecOf(q), policy);
        if (take(r)) o.v = r->value.linear, o.w = r->value.angular;
        break;
      }
      case QueryKind::kLinearVelocity: {
        const auto r = graph_.GetLinearVelocity(TwistSpecOf(q), policy);
        if (take(r)) o.v = r->value.value;
        break;
      }
      case QueryKind::kAngularVelocity: {
        const auto r = graph_.GetAngularVelocity(TwistSpecOf(q), policy);
        if (take(r)) o.w = r->value.value;
        break;
      }
    }
    return o;
  }

  Outcome CompiledTimed(const Query& q, const core::TimePolicy& policy, core::TimeReport* report,
                        bool* compile_failed) const {
    Outcome o;
    CompiledAny c;
    {
      const Outcome compiled = Compiled(q, &c);  // the compile's code (and an untimed evaluation)
      if (compiled.code != ErrorCode::kOk && std::holds_alternative<std::monostate>(c)) {
        *compile_failed = true;
        return compiled;
      }
    }
    if (const auto* pose = std::get_if<core::CompiledPose<B>>(&c)) {
      typename B::PoseCoords X;
      o.code = pose->Evaluate(X, policy, *report);
      if (o.code == ErrorCode::kOk) o.M = B::ToMatrix(B::RotationOf(X)), o.p = B::TranslationOf(X);
    } else if (const auto* position = std::get_if<core::CompiledPosition<B>>(&c)) {
      o.code = position->Evaluate(o.p, policy, *report);
    } else if (const auto* orientation = std::get_if<core::CompiledOrientation<B>>(&c)) {
      typename B::Rotation M;
      o.code = orientation->Evaluate(M, policy, *report);
      if (o.code == ErrorCode::kOk) o.M = B::ToMatrix(M);
    } else if (const auto* twist = std::get_if<core::CompiledTwist<B>>(&c)) {
      o.code = twist->Evaluate(o.v, o.w, policy, *report);
      if (q.kind == QueryKind::kLinearVelocity) o.w.setZero();
      if (q.kind == QueryKind::kAngularVelocity) o.v.setZero();
    }
    return o;
  }

  void CompareTimed(const std::string& what, const reference::TimedAnswer& expected,
                    const Outcome& got, const core::TimeReport& report) {
    if (expected.ambiguous) {  // only the decision
      if (got.code != expected.answer.code) {
        Fail(what + ": kernel says " + std::string(base::ToString(got.code)) + ", model says " +
             std::string(base::ToString(expected.answer.code)));
      }
    } else {
      CompareAnswer(what, expected.answer, got);
    }
    if (got.code != ErrorCode::kOk) return;
    CompareReport(what, expected, report);
  }
  // The time answered, the extrapolated flag and, when not extrapolated, the stamps read.
  void CompareReport(const std::string& what, const reference::TimedAnswer& expected,
                     const core::TimeReport& report) {
    const auto ns = [](const std::optional<core::Stamp>& s) {
      return s ? std::optional<std::int64_t>(s->nanoseconds()) : std::nullopt;
    };
    const auto text = [](const std::optional<std::int64_t>& s) {
      return s ? std::to_string(*s) : std::string("none");
    };
    if (ns(report.time) != expected.time) {
      Fail(what + ": time answered: kernel " + text(ns(report.time)) + ", model " +
           text(expected.time));
    }
    if (report.extrapolated != expected.extrapolated) {
      Fail(what + ": extrapolated: kernel " + std::to_string(report.extrapolated) + ", model " +
           std::to_string(expected.extrapolated));
    }
    if (!expected.extrapolated &&
        (ns(report.oldest) != expected.oldest || ns(report.newest) != expected.newest)) {
      Fail(what + ": stamps read: kernel [" + text(ns(report.oldest)) + ", " +
           text(ns(report.newest)) + "], model [" + text(expected.oldest) + ", " +
           text(expected.newest) + "]");
    }
  }

  static const char* JointTypeName(reference::JointType t) {
    switch (t) {
      case reference::JointType::kRevolute:
        return "revolute";
      case reference::JointType::kContinuous:
        return "continuous";
      case reference::JointType::kPrismatic:
        return "prismatic";
      case reference::JointType::kFixed:
        return "fixed";
    }
    return "?";
  }
  static core::RepairPolicy KernelPolicy(const reference::RepairPolicy& p) {
    core::RepairPolicy k;
    k.invert = p.invert;
    k.reroot = p.reroot;
    k.check_consistency = p.check_consistency;
    k.position_tolerance = p.position_tolerance;
    k.angle_tolerance = p.angle_tolerance;
    return k;
  }
  static RotationInput RotationOf(const Eigen::Quaterniond& q) {
    RotationInput r;
    r.q = q;
    return r;
  }
  static std::string PolicyComment(const reference::RepairPolicy& p) {
    const reference::RepairPolicy d;
    if (p.invert == d.invert && p.reroot == d.reroot &&
        p.check_consistency == d.check_consistency &&
        p.position_tolerance == d.position_tolerance && p.angle_tolerance == d.angle_tolerance) {
      return "";
    }
    return "   # RepairPolicy{invert " + std::to_string(p.invert) + ", reroot " +
           std::to_string(p.reroot) + ", check_consistency " + std::to_string(p.check_consistency) +
           ", position_tolerance " + YamlNumber(p.position_tolerance) + ", angle_tolerance " +
           YamlNumber(p.angle_tolerance) + "}";
  }
  static reference::RepairKind KindOf(core::RepairKind k) {
    switch (k) {
      case core::RepairKind::kNone:
        return reference::RepairKind::kNone;
      case core::RepairKind::kInverted:
        return reference::RepairKind::kInverted;
      case core::RepairKind::kRerooted:
        return reference::RepairKind::kRerooted;
      case core::RepairKind::kConsistent:
        return reference::RepairKind::kConsistent;
    }
    return reference::RepairKind::kNone;
  }
  static const char* KindText(reference::RepairKind k) {
    switch (k) {
      case reference::RepairKind::kNone:
        return "none";
      case reference::RepairKind::kInverted:
        return "inverted";
      case reference::RepairKind::kRerooted:
        return "rerooted";
      case reference::RepairKind::kConsistent:
        return "consistent";
    }
    return "?";
  }

  // A repairing add: the decision and the report, then every check of Finish.
  ErrorCode FinishRepair(base::Expected<core::RepairReport, core::BuildError> result,
                         const reference::RepairOutcome& expected) {
    const ErrorCode code = result ? ErrorCode::kOk : result.error().code;
    // A consistency check at its tolerance's boundary: either decision (neither changes anything).
    const bool either =
        expected.borderline &&
        (code == ErrorCode::kOk ? result->applied == core::RepairKind::kConsistent
                                : expected.applied == reference::RepairKind::kConsistent);
    if (code != expected.code && !either) {
      Annotate(code);
      Fail("repairing add: kernel says " + std::string(base::ToString(code)) + ", model says " +
           std::string(base::ToString(expected.code)) +
           " (model repair: " + KindText(expected.applied) + ")" +
           (result ? std::string() : "\nkernel message: " + result.error().message));
    }
    if (result && result->applied != core::RepairKind::kNone)
      trace_.back().note = KindText(KindOf(result->applied));
    if (!result && result.error().discrepancy) trace_.back().note = "discrepancy";
    const double tol = 1e-9 * PositionScale();
    const double tol_v = 1e-9 * TwistScale();
    const auto same_discrepancy = [&](const core::Discrepancy& d) {
      return std::abs(d.position - expected.position) <= std::max(tol, tol_v) &&
             std::abs(d.angle - expected.angle) <= std::max(1e-9, tol_v);
    };
    if (result) {
      if (KindOf(result->applied) != expected.applied && !either) {
        Fail(std::string("repairing add: kernel applied ") + KindText(KindOf(result->applied)) +
             ", model " + KindText(expected.applied));
      }
      if (result->reversed_edges != expected.reversed_edges) {
        Fail("repairing add: kernel reversed " + std::to_string(result->reversed_edges) +
             " edges, model " + std::to_string(expected.reversed_edges));
      }
      if (result->applied == core::RepairKind::kConsistent &&
          !same_discrepancy(result->discrepancy)) {
        Fail("repairing add: the consistent check's discrepancy differs: kernel " +
             YamlNumber(result->discrepancy.position) + " / " +
             YamlNumber(result->discrepancy.angle) + ", model " + YamlNumber(expected.position) +
             " / " + YamlNumber(expected.angle));
      }
      if (result->applied != core::RepairKind::kNone && result->change.empty())
        Fail("a repair without a change text");
    } else {
      const bool refused_check =
          expected.has_discrepancy && expected.applied != reference::RepairKind::kConsistent;
      if (result.error().discrepancy.has_value() !=
          (refused_check || (either && expected.has_discrepancy))) {
        Fail("repairing add refused: discrepancy reported " +
             std::to_string(result.error().discrepancy.has_value()) +
             ", model's consistency check refused it " + std::to_string(refused_check));
      }
      if (result.error().discrepancy && !same_discrepancy(*result.error().discrepancy)) {
        Fail("repairing add refused: the discrepancy differs: kernel " +
             YamlNumber(result.error().discrepancy->position) + " / " +
             YamlNumber(result.error().discrepancy->angle) + ", model " +
             YamlNumber(expected.position) + " / " + YamlNumber(expected.angle));
      }
    }
    core::BuildResult plain = result ? core::BuildResult(base::Ok{})
                                     : core::BuildResult(base::Unexpected{result.error()});
    return Finish(plain, code);
  }

  // The kernel's nodes, edges and stored values against the model's.
  void CompareState() {
    const auto& frames = model_.frames();
    if (graph_.num_frames() != frames.size() || graph_.num_bodies() != model_.bodies().size() ||
        graph_.num_pose_edges() != model_.poses().size() ||
        graph_.num_twist_edges() != model_.twists().size()) {
      Fail("node or edge counts differ: kernel frames/bodies/poses/twists " +
           std::to_string(graph_.num_frames()) + "/" + std::to_string(graph_.num_bodies()) + "/" +
           std::to_string(graph_.num_pose_edges()) + "/" +
           std::to_string(graph_.num_twist_edges()) + ", model " + std::to_string(frames.size()) +
           "/" + std::to_string(model_.bodies().size()) + "/" +
           std::to_string(model_.poses().size()) + "/" + std::to_string(model_.twists().size()));
    }
    for (const auto& [name, body] : frames) {
      const core::FrameIndex f = graph_.FindFrame(name);
      if (!f.is_valid() || graph_.body_name(graph_.body_of(f)) != body) {
        Fail("frame " + YamlName(name) + " is not on body " + YamlName(body) + " in the kernel");
      }
    }
    const double tol = 1e-9 * PositionScale();
    for (const reference::PoseEdge& e : model_.poses()) {
      const core::FrameIndex h = graph_.FindFrame(e.head);
      if (graph_.pose_parent(h) != graph_.FindFrame(e.tail))
        Fail("pose parent of " + e.head + " differs");
      const auto X = graph_.pose_value(h);
      if (!Near(B::ToMatrix(B::RotationOf(X)), e.X_TH.R, 1e-9) ||
          !Near(B::TranslationOf(X), e.X_TH.p, tol)) {
        Fail("stored value of the pose edge " + e.tail + " -> " + e.head + " differs");
      }
      CompareCovariance("pose edge " + e.tail + " -> " + e.head, graph_.pose_covariance(h), e.S);
      if (!e.S.isZero(0.0)) {  // asked back in its own form: the edge's covariance itself
        const auto r = graph_.GetPoseWithCovariance(core::PoseSpec::Of(e.head).RelativeTo(e.tail));
        if (!r) Fail("GetPoseWithCovariance of the edge " + e.tail + " -> " + e.head + " failed");
        CompareCovariance("queried pose " + e.head + " wrt " + e.tail, r->covariance, e.S, 1e-9);
      }
    }
    if (graph_.num_joints() != model_.joints().size()) {
      Fail("joint counts differ: kernel " + std::to_string(graph_.num_joints()) + ", model " +
           std::to_string(model_.joints().size()));
    }
    for (const reference::Joint& j : model_.joints()) {
      const auto h = graph_.FindJoint(j.name);
      if (!h) Fail("joint " + j.name + " is missing in the kernel");
      const double q = graph_.joint_position(*h), qdot = graph_.joint_velocity(*h);
      if (!(std::abs(q - j.q) <= 1e-12 * (1 + std::abs(j.q))) ||
          !(std::abs(qdot - j.qdot) <= 1e-12 * (1 + std::abs(j.qdot)))) {
        Fail("state of joint " + j.name + " differs: kernel q " + YamlNumber(q) + " qdot " +
             YamlNumber(qdot) + ", model q " + YamlNumber(j.q) + " qdot " + YamlNumber(j.qdot));
      }
    }
    const double tol_v = 1e-9 * TwistScale();
    for (const reference::TwistEdge& t : model_.twists()) {
      const core::FrameIndex h = graph_.FindFrame(t.head);
      const core::BodyIndex D = graph_.twist_parent(h);
      const auto value = graph_.twist_value(h);
      if (!D.is_valid() || graph_.body_name(D) != t.tail_body || !value) {
        Fail("twist parent of " + t.head + " differs");
      }
      if (!Near(value->linear, t.v, tol_v) || !Near(value->angular, t.w, tol_v)) {
        Fail("stored value of the twist edge " + t.tail_body + " -> " + t.head + " differs");
      }
      const std::string key = "twist edge " + t.tail_body + " -> " + t.head;
      CompareCovariance(key, graph_.twist_covariance(h), t.S);
      if (!t.S.isZero(0.0)) {  // the twist of h wrt D at h in [h]: the edge alone (W3: a tree)
        const auto r = graph_.GetTwistWithCovariance(
            core::TwistSpec::Of(t.head).RelativeTo(t.tail_body).ExpressedIn(t.head));
        if (!r) Fail("GetTwistWithCovariance of the " + key + " failed");
        CompareCovariance("queried twist of the " + key, r->covariance, t.S, 1e-9);
      }
    }
    CompareWrenches();
    CompareAccelerations();
  }

  struct KeptWrench {
    std::string on, point, coord;
    std::vector<std::uint64_t> serials;  // the model's wrenches it sums (fixed when compiled)
    std::set<std::string> used;          // pose edge keys on its terms' paths
    bool invalidated = false;
    core::CompiledWrench<B> compiled;
  };
  std::deque<KeptWrench> kept_wrenches_;
  void CheckKeptWrenches() {
    for (std::size_t i = 0; i < kept_wrenches_.size(); ++i) {
      KeptWrench& k = kept_wrenches_[i];
      Eigen::Vector3d f = Eigen::Vector3d::Zero(), m = Eigen::Vector3d::Zero();
      const ErrorCode code = k.compiled.Evaluate(f, m);
      const std::string which = "kept compiled wrench query #" + std::to_string(i) + " on " + k.on +
                                " at {" + k.point + "} in [" + k.coord + "]";
      if (k.invalidated) {
        if (code != ErrorCode::kQueryInvalidated) {
          Fail(which + ": a wrench or pose edge it used was removed, but Evaluate() returned " +
               std::string(base::ToString(code)) + " instead of query_invalidated");
        }
        continue;
      }
      CompareWrench(which + " (re-evaluated)",
                    model_.AskWrenchTerms(k.serials, k.on, k.point, k.coord), code, f, m);
    }
  }

  struct KeptWrenchHandle {
    std::string on, by;
    std::uint64_t serial = 0;
    core::WrenchHandle handle;
  };
  std::vector<KeptWrenchHandle> wrench_handles_;

  // Tolerance of wrench numbers of size `scale` moved along the graph's poses.
  double WrenchTolerance(double scale) const {
    double forces = 1.0;
    for (const reference::WrenchEntry& w : model_.wrenches()) forces += w.f.norm() + w.m.norm();
    return 1e-9 * (PositionScale() * forces + scale);
  }

  void CompareWrench(const std::string& what, const reference::WrenchAnswer& expected,
                     ErrorCode code, const Eigen::Vector3d& f, const Eigen::Vector3d& m) {
    if (code != expected.code) {
      Fail(what + ": kernel says " + std::string(base::ToString(code)) + ", model says " +
           std::string(base::ToString(expected.code)));
    }
    if (code != ErrorCode::kOk) return;
    const double tol = WrenchTolerance(expected.scale);
    if (!Near(f, expected.f, tol) || !Near(m, expected.m, tol)) {
      const Eigen::IOFormat fmt(17, Eigen::DontAlignCols, ", ", "; ", "", "", "[", "]");
      std::ostringstream out;
      out << what << ": values differ\n  kernel f " << f.transpose().format(fmt) << " m "
          << m.transpose().format(fmt) << "\n  model  f " << expected.f.transpose().format(fmt)
          << " m " << expected.m.transpose().format(fmt);
      Fail(out.str());
    }
  }

  // The stored wrenches: the same pairs, storage frames and values (stored form).
  void CompareWrenches() {
    const auto& wrenches = model_.wrenches();
    if (graph_.num_wrenches() != wrenches.size()) {
      Fail("wrench counts differ: kernel " + std::to_string(graph_.num_wrenches()) + ", model " +
           std::to_string(wrenches.size()));
    }
    const auto& store = graph_.wrench_store();
    for (const reference::WrenchEntry& w : wrenches) {
      const auto h = graph_.FindWrench(w.on, w.by);
      if (!h) Fail("the wrench on " + w.on + " by " + w.by + " is missing in the kernel");
      if (h->frame != graph_.FindFrame(w.frame)) {
        Fail("the wrench on " + w.on + " by " + w.by + " is stored in {" +
             std::string(graph_.frame_name(h->frame)) + "} in the kernel, {" + w.frame +
             "} in the model");
      }
      const core::WrenchNumbers W = store.values[h->slot].Load();
      const double tol = WrenchTolerance(w.scale);
      if (!Near(W.f_S, w.f, tol) || !Near(W.m_So_S, w.m, tol)) {
        Fail("stored value of the wrench on " + w.on + " by " + w.by + " differs");
      }
    }
  }

  // A kernel covariance against the model's (edge form): within `rel` of max(1, max|S|), and
  // symmetric (stored symmetrized) within 1e-12 of that scale.
  void CompareCovariance(const std::string& what, const coord::Covariance6& kernel,
                         const reference::Matrix6& model, double rel = 1e-12) const {
    const double scale = std::max(1.0, model.cwiseAbs().maxCoeff());
    const double diff = (kernel - model).cwiseAbs().maxCoeff();
    const double asym = (kernel - kernel.transpose()).cwiseAbs().maxCoeff();
    if (!(diff <= rel * scale) || !(asym <= 1e-12 * scale)) {
      std::ostringstream m;
      m.precision(17);
      m << "covariance of the " << what << " differs (max difference " << diff << ", asymmetry "
        << asym << "):\nkernel\n"
        << kernel << "\nmodel\n"
        << model;
      Fail(m.str());
    }
  }

  void Removed(const std::string& key) {
    for (Kept& k : kept_) {
      if (k.used.count(key)) k.invalidated = true;
    }
    for (KeptWrench& k : kept_wrenches_) {
      if (k.used.count(key)) k.invalidated = true;
    }
    for (KeptConvertingHandle& k : converting_handles_) {
      if (k.used.count(key)) k.invalidated = true;
    }
  }

  void CheckKept() {
    CheckKeptWrenches();
    for (std::size_t i = 0; i < kept_.size(); ++i) {
      Kept& k = kept_[i];
      const Outcome got = Evaluate(k.compiled, k.query.kind);
      const std::string which =
          "kept compiled query #" + std::to_string(i) + " " +
          (k.acceleration ? AccelerationQueryText(k.query) : QueryText(k.query));
      if (k.invalidated) {
        if (got.code != ErrorCode::kQueryInvalidated) {
          Fail(which + ": an edge it used was removed, but Evaluate() returned " +
               std::string(base::ToString(got.code)) + " instead of query_invalidated");
        }
        continue;
      }
      if (k.acceleration) {
        CompareAcceleration(
            "kept compiled acceleration query #" + std::to_string(i) + " " +
                AccelerationQueryText(k.query) + " (re-evaluated)",
            k.zero_twist ? reference::AccelerationAnswer{} : model_.AskAcceleration(k.query), got);
        continue;
      }
      if (got.code != ErrorCode::kOk) {
        Fail(which + ": Evaluate() returned " + std::string(base::ToString(got.code)) +
             " though no edge it uses was removed");
      }
      CompareAnswer(which + " (re-evaluated)", k.zero_twist ? Answer{} : model_.Ask(k.query), got);
    }
  }

  // Whether the compiled form is expected to fail like the one-shot query. CompileTwist needs
  // its point, as GetTwist does; an angular velocity is compiled as the twist at the coordinate
  // frame's origin (what GetAngularVelocity asks), which without a body takes that frame's body
  // (GetAngularVelocity: invalid_name).
  static bool CompileComparable(const Query& q) {
    switch (q.kind) {
      case QueryKind::kAngularVelocity:
        return !q.body.empty();
      default:
        return true;
    }
  }

  static core::PoseSpec PoseSpecOf(const Query& q) {
    core::PoseSpec s;
    s.point = q.point;
    s.orientation = q.orientation;
    s.body = q.body;
    s.ref_point = q.ref_point;
    s.ref_orientation = q.ref_orientation;
    s.ref_body = q.ref_body;
    s.coordinate_frame = q.coord;
    return s;
  }
  static core::TwistSpec TwistSpecOf(const Query& q) {
    core::TwistSpec s;
    s.point =
        q.kind == QueryKind::kAngularVelocity ? std::string_view() : std::string_view(q.point);
    s.body = q.body;
    s.ref_body = q.ref_body;
    s.coordinate_frame = q.coord;
    return s;
  }

  template <class R>
  static Outcome Code(const R& r) {
    Outcome o;
    o.code = r ? ErrorCode::kOk : r.error().code;
    return o;
  }

  Outcome OneShot(const Query& q) const {
    Outcome o;
    switch (q.kind) {
      case QueryKind::kPose: {
        const auto r = graph_.GetPose(PoseSpecOf(q));
        if (!r) return Code(r);
        o.M = B::ToMatrix(B::RotationOf(r->value));
        o.p = B::TranslationOf(r->value);
        return o;
      }
      case QueryKind::kPosition: {
        const auto r = graph_.GetPosition(PoseSpecOf(q));
        if (!r) return Code(r);
        o.p = r->value;
        return o;
      }
      case QueryKind::kOrientation: {
        const auto r = graph_.GetOrientation(PoseSpecOf(q));
        if (!r) return Code(r);
        o.M = B::ToMatrix(r->value);
        return o;
      }
      case QueryKind::kTwist: {
        const auto r = graph_.GetTwist(TwistSpecOf(q));
        if (!r) return Code(r);
        o.v = r->linear;
        o.w = r->angular;
        return o;
      }
      case QueryKind::kLinearVelocity: {
        const auto r = graph_.GetLinearVelocity(TwistSpecOf(q));
        if (!r) return Code(r);
        o.v = r->value;
        return o;
      }
      case QueryKind::kAngularVelocity: {
        const auto r = graph_.GetAngularVelocity(TwistSpecOf(q));
        if (!r) return Code(r);
        o.w = r->value;
        return o;
      }
    }
    return o;
  }

  // Compiles q (kept in *keep when given) and evaluates it once.
  Outcome Compiled(const Query& q, CompiledAny* keep) const {
    CompiledAny c;
    switch (q.kind) {
      case QueryKind::kPose: {
        auto r = graph_.CompilePose(PoseSpecOf(q));
        if (!r) return Code(r);
        c = std::move(*r);
        break;
      }
      case QueryKind::kPosition: {
        auto r = graph_.CompilePosition(PoseSpecOf(q));
        if (!r) return Code(r);
        c = std::move(*r);
        break;
      }
      case QueryKind::kOrientation: {
        auto r = graph_.CompileOrientation(PoseSpecOf(q));
        if (!r) return Code(r);
        c = std::move(*r);
        break;
      }
      default: {
        core::TwistSpec spec = TwistSpecOf(q);
        if (q.kind == QueryKind::kAngularVelocity) spec.point = spec.coordinate_frame;
        auto r = graph_.CompileTwist(spec);
        if (!r) return Code(r);
        c = std::move(*r);
        break;
      }
    }
    Outcome o = Evaluate(c, q.kind);
    if (keep) *keep = std::move(c);
    return o;
  }

  static Outcome Evaluate(CompiledAny& c, QueryKind kind) {
    Outcome o;
    if (const auto* pose = std::get_if<core::CompiledPose<B>>(&c)) {
      typename B::PoseCoords X;
      o.code = pose->Evaluate(X);
      if (o.code == ErrorCode::kOk) o.M = B::ToMatrix(B::RotationOf(X)), o.p = B::TranslationOf(X);
    } else if (const auto* position = std::get_if<core::CompiledPosition<B>>(&c)) {
      o.code = position->Evaluate(o.p);
    } else if (const auto* orientation = std::get_if<core::CompiledOrientation<B>>(&c)) {
      typename B::Rotation M;
      o.code = orientation->Evaluate(M);
      if (o.code == ErrorCode::kOk) o.M = B::ToMatrix(M);
    } else if (const auto* twist = std::get_if<core::CompiledTwist<B>>(&c)) {
      o.code = twist->Evaluate(o.v, o.w);
      if (kind == QueryKind::kLinearVelocity) o.w.setZero();
      if (kind == QueryKind::kAngularVelocity) o.v.setZero();
    } else if (auto* acc = std::get_if<core::CompiledAcceleration<B>>(&c)) {
      o.code = acc->Evaluate(o.v, o.w);  // a, alpha
      if (o.code != ErrorCode::kOk) o.v.setZero(), o.w.setZero();
      if (kind == QueryKind::kLinearVelocity) o.w.setZero();
      if (kind == QueryKind::kAngularVelocity) o.v.setZero();
    }
    return o;
  }

  template <class DA, class DB>
  static bool Near(const Eigen::MatrixBase<DA>& a, const Eigen::MatrixBase<DB>& b, double tol) {
    return (a - b).cwiseAbs().maxCoeff() <= tol;  // false for NaN
  }

  // Magnitudes of the scene: rounding errors of a composed position grow with the positions
  // summed along its path, those of a twist with |v| + |w| times the lever arms.
  double PositionScale() const {
    double s = 1.0;
    for (const reference::PoseEdge& e : model_.poses()) s += e.X_TH.p.norm();
    return s;
  }
  double TwistScale() const {
    double s = 1.0;
    const double lever = PositionScale();
    for (const reference::TwistEdge& t : model_.twists()) s += t.v.norm() + t.w.norm() * lever;
    return s;
  }

  void CompareAnswer(const std::string& what, const Answer& expected, const Outcome& got) {
    if (got.code != expected.code) {
      Fail(what + ": kernel says " + std::string(base::ToString(got.code)) + ", model says " +
           std::string(base::ToString(expected.code)));
    }
    if (got.code != ErrorCode::kOk) return;
    const double tol_p = 1e-9 * std::max(PositionScale(), expected.p.norm());
    const double tol_v = 1e-9 * std::max(TwistScale(), expected.v.norm());
    const bool ok = Near(got.M, expected.M, 1e-9) && Near(got.p, expected.p, tol_p) &&
                    Near(got.v, expected.v, tol_v) && Near(got.w, expected.w, tol_v);
    if (!ok) {
      const Eigen::IOFormat fmt(17, Eigen::DontAlignCols, ", ", "; ", "", "", "[", "]");
      std::ostringstream out;
      out << what << ": values differ\n  kernel M " << got.M.format(fmt) << " p "
          << got.p.transpose().format(fmt) << " v " << got.v.transpose().format(fmt) << " w "
          << got.w.transpose().format(fmt) << "\n  model  M " << expected.M.format(fmt) << " p "
          << expected.p.transpose().format(fmt) << " v " << expected.v.transpose().format(fmt)
          << " w " << expected.w.transpose().format(fmt);
      Fail(out.str());
    }
  }

  // A sweep acceleration query: like AskAcceleration but not traced unless it fails.
  void CheckAcceleration(const Query& q) {
    const reference::AccelerationAnswer expected = model_.AskAcceleration(q);
    const Outcome got = OneShotAcceleration(q);
    if (got.code != expected.code || got.code == ErrorCode::kOk) {
      trace_.push_back(TraceLine{
          [=] { return "# final sweep: " + AccelerationQueryText(q); }, std::nullopt, {}});
      CompareAcceleration("final sweep acceleration query", expected, got);
      CompareAcceleration("final sweep acceleration query, compiled", expected,
                          CompiledAccelerationOutcome(q, nullptr));
      trace_.pop_back();
    }
  }

  // A sweep query: like Ask but not traced unless it fails.
  void Check(const Query& q) {
    const Answer expected = model_.Ask(q);
    const Outcome got = OneShot(q);
    if (got.code != expected.code || got.code == ErrorCode::kOk) {
      trace_.push_back(
          TraceLine{[=] { return "# final sweep: " + QueryText(q); }, std::nullopt, {}});
      CompareAnswer("final sweep query", expected, got);
      CompareAnswer("final sweep query, compiled", expected, Compiled(q, nullptr));
      trace_.pop_back();
    }
  }

  Graph graph_;
  ReferenceModel model_;
  std::vector<TraceLine> trace_;
  std::string before_;                                            // Dump() before the current op
  std::map<std::string, coord::Covariance6> covariances_before_;  // Covariances() likewise
  std::string dump_;  // cache of Dump() while dump_valid_
  bool dump_valid_ = false;
  bool checks_ = true;
  std::deque<Kept> kept_;
  reference::TimeOptions time_;
  std::optional<core::JointGroup> group_;   // the last group made (SetGroup)
  std::vector<std::uint64_t> model_group_;  // the model's serials of the same joints
};

}  // namespace semgraph::fuzz
