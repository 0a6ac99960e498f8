// Script runner: one scene-graph call per op, one JSON line per outcome. Contract:
// script_runner.h; output format: docs/scene-script.md.
#include "semgraph/script_runner.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "semgraph/base/error_code.h"
#include "semgraph/base/utf8.h"
#if SEMGRAPH_SCRIPT_HAS_MODELS
#include "semgraph/models/urdf.h"
#if SEMGRAPH_SCRIPT_HAS_ROS
#include "semgraph/bag_op.h"
#endif
#endif

namespace semgraph::script {

namespace {

// C1 controls (U+0080..U+009F) and the separators U+2028 / U+2029 are valid UTF-8 but break
// lines for many readers (U+0085 is "next line"; Python's splitlines splits at all three): JSON
// lines carry them escaped. `sequence` is one valid UTF-8 character; empty if it can stay.
std::string_view LineBreakingEscape(std::string_view sequence) {
  static constexpr std::string_view kC1[32] = {
      "\\u0080", "\\u0081", "\\u0082", "\\u0083", "\\u0084", "\\u0085", "\\u0086", "\\u0087",
      "\\u0088", "\\u0089", "\\u008a", "\\u008b", "\\u008c", "\\u008d", "\\u008e", "\\u008f",
      "\\u0090", "\\u0091", "\\u0092", "\\u0093", "\\u0094", "\\u0095", "\\u0096", "\\u0097",
      "\\u0098", "\\u0099", "\\u009a", "\\u009b", "\\u009c", "\\u009d", "\\u009e", "\\u009f"};
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(sequence[k]); };
  if (sequence.size() == 2 && byte(0) == 0xC2 && byte(1) < 0xA0) return kC1[byte(1) - 0x80];
  if (sequence == "\xE2\x80\xA8") return "\\u2028";
  if (sequence == "\xE2\x80\xA9") return "\\u2029";
  return {};
}

// One named result array of a successful query.
struct ResultField {
  std::string_view key;
  std::vector<double> values;
};

OpOutcome Success(std::size_t index, std::initializer_list<ResultField> fields = {}) {
  for (const ResultField& f : fields) {
    for (const double v : f.values) {
      if (!std::isfinite(v)) {
        // Defensive: JSON has no Inf/NaN, and the graph's input bounds should prevent this.
        return OpOutcome{false, "invalid_number",
                         "{\"op\": " + std::to_string(index) +
                             ", \"ok\": false, \"error\": \"invalid_number\", "
                             "\"message\": " +
                             JsonString("the " + std::string(f.key) +
                                        " of the result is not finite (overflow)") +
                             "}"};
      }
    }
  }
  std::string json = "{\"op\": " + std::to_string(index) + ", \"ok\": true";
  for (const ResultField& f : fields) {
    json += ", \"" + std::string(f.key) + "\": [";
    for (std::size_t i = 0; i < f.values.size(); ++i) {
      if (i > 0) json += ',';
      json += JsonNumber(f.values[i]);
    }
    json += ']';
  }
  return OpOutcome{true, "", json + "}"};
}

// The graph's messages quote the names of the op whole. A name longer than any valid name
// (kMaxEchoedNameBytes) is shown as its first bytes and its length instead, so that a hostile
// megabyte name gives a short line.
std::string CapNames(std::string message, const ScriptOp& op) {
  const SemanticNames& n = op.names;
  for (const std::string* name : {&op.name, &n.point, &n.orientation, &n.body, &n.ref_point,
                                  &n.ref_orientation, &n.ref_body, &n.coord, &op.mimic_joint}) {
    if (name->size() <= kMaxEchoedNameBytes) continue;
    std::size_t shown = kEchoedPrefixBytes;
    while (shown > 0 && (static_cast<unsigned char>((*name)[shown]) & 0xC0u) == 0x80u) --shown;
    const std::string capped =
        name->substr(0, shown) + "... (" + std::to_string(name->size()) + " bytes)";
    const std::boyer_moore_horspool_searcher searcher(name->begin(), name->end());
    std::string out;
    auto from = message.cbegin();
    for (;;) {
      const auto found = std::search(from, message.cend(), searcher);
      out.append(from, found);
      if (found == message.cend()) break;
      out += capped;
      from = found + static_cast<std::ptrdiff_t>(name->size());
    }
    message = std::move(out);
  }
  return message;
}

OpOutcome Failure(const ScriptOp& op, std::size_t index, base::ErrorCode code,
                  std::string_view message) {
  return OpOutcome{false, std::string(base::ToString(code)),
                   "{\"op\": " + std::to_string(index) +
                       ", \"ok\": false, \"error\": " + JsonString(base::ToString(code)) +
                       ", \"message\": " + JsonString(CapNames(std::string(message), op)) + "}"};
}

OpOutcome FromBuild(const ScriptOp& op, std::size_t index, const core::BuildResult& result) {
  if (result) return Success(index);
  return Failure(op, index, result.error().code, result.error().message);
}

std::vector<double> Values(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// [w, x, y, z] with w >= 0; for w == 0 the first nonzero of x, y, z is made positive, so that
// the printed text does not depend on which of q and -q a computation produced.
std::vector<double> Values(const Eigen::Quaterniond& q) {
  std::vector<double> c = {q.w(), q.x(), q.y(), q.z()};
  for (const double component : c) {
    if (component == 0.0) continue;
    if (component < 0.0) {
      for (double& x : c) x = -x;
    }
    break;
  }
  return c;
}

Eigen::Vector3d ToVector(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

core::PoseSpec PoseSpecOf(const SemanticNames& n) {
  core::PoseSpec s;
  s.point = n.point;
  s.orientation = n.orientation;
  s.body = n.body;
  s.ref_point = n.ref_point;
  s.ref_orientation = n.ref_orientation;
  s.ref_body = n.ref_body;
  s.coordinate_frame = n.coord;
  return s;
}

core::TwistSpec TwistSpecOf(const SemanticNames& n) {
  core::TwistSpec s;
  s.point = n.point;
  s.body = n.body;
  s.ref_body = n.ref_body;
  s.coordinate_frame = n.coord;
  return s;
}

// A repairing add: the plain result, plus "repair" (the strategy applied) on success, or the
// "discrepancy" of a refused consistency check.
OpOutcome FromRepair(const ScriptOp& op, std::size_t index,
                     const base::Expected<core::RepairReport, core::BuildError>& result) {
  if (!result) {
    OpOutcome out = Failure(op, index, result.error().code, result.error().message);
    if (const auto& d = result.error().discrepancy) {
      out.json.pop_back();  // '}'
      const bool twist = op.kind == OpKind::kTwist;
      out.json += std::string(", \"discrepancy\": {\"") + (twist ? "linear" : "position") +
                  "\": " + JsonNumber(d->position) + ", \"" + (twist ? "angular" : "angle") +
                  "\": " + JsonNumber(d->angle) + "}}";
    }
    return out;
  }
  OpOutcome out = Success(index);
  out.json.pop_back();  // '}'
  out.json += ", \"repair\": " + JsonString(core::ToString(result->applied)) + "}";
  return out;
}

// ---------------------------------------------------------------- time (docs/scene-script.md)

// "'at' nan s": a time field and its value for a message (any double, NaN included).
std::string TimeText(std::string_view field, double seconds) {
  char buffer[48];  // the shortest of 15 or 17 digits that reads back as the value
  std::snprintf(buffer, sizeof(buffer), "%.15g", seconds);
  if (std::isfinite(seconds) && std::strtod(buffer, nullptr) != seconds) {
    std::snprintf(buffer, sizeof(buffer), "%.17g", seconds);
  }
  return "'" + std::string(field) + "' " + buffer + " s";
}

std::string NotATime(std::string_view field, double seconds) {
  return TimeText(field, seconds) + " is not a finite time within +-9.2e9 s";
}

// A graph's invalid_number message with the reason replaced ("X rejected (invalid_number): ...").
std::string WithReason(const std::string& message, std::string_view reason) {
  static constexpr std::string_view kTag = "(invalid_number): ";
  const std::size_t at = message.find(kTag);
  if (at == std::string::npos) return std::string(reason);
  return message.substr(0, at + kTag.size()) + std::string(reason);
}

// The op's stamp in nanoseconds; false (with the reason) when it is not a valid time.
bool StampOf(const ScriptOp& op, std::optional<core::Stamp>* stamp, std::string* reason) {
  if (!op.stamp) return true;
  *stamp = core::StampFromSeconds(*op.stamp);
  if (!*stamp) *reason = NotATime("stamp", *op.stamp);
  return stamp->has_value();
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The covariance of a pose or twist op as written (the reader checked its shape only).
coord::Covariance6 CovarianceOf(const ScriptOp& op) {
  coord::Covariance6 S;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) S(i, j) = op.covariance[i][j];
  }
  return S;
}
core::CovarianceInput CovarianceInputOf(const ScriptOp& op, const coord::Covariance6& S) {
  core::CovarianceInput in;
  in.matrix = op.has_covariance ? &S : nullptr;
  in.order = op.covariance_angular_first ? coord::CovarianceOrder::kAngularLinear
                                         : coord::CovarianceOrder::kLinearAngular;
  in.convention = op.covariance_body ? coord::PoseCovarianceConvention::kBody
                                     : coord::PoseCovarianceConvention::kCoordinates;
  return in;
}

core::WrenchSpec WrenchSpecOf(const SemanticNames& n) {
  core::WrenchSpec s;
  s.on = n.body;
  s.by = n.ref_body;
  s.point = n.point;
  s.coordinate_frame = n.coord;
  return s;
}

// A wrench op, stamped or not (the stamp's invalid_number after the names', as AddPose).
template <coord::Backend B>
OpOutcome AddWrench(core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index) {
  const core::WrenchSpec spec = WrenchSpecOf(op.names);
  const Eigen::Vector3d f = Eigen::Vector3d::Map(op.force.data()),
                        m = Eigen::Vector3d::Map(op.moment.data());
  std::optional<core::Stamp> stamp;
  if (std::string reason; !StampOf(op, &stamp, &reason)) {
    const auto probe = graph.AddWrench(spec, Eigen::Vector3d(kNaN, 0, 0), m);
    if (probe.error().code != base::ErrorCode::kInvalidNumber) return FromBuild(op, index, probe);
    return Failure(op, index, base::ErrorCode::kInvalidNumber,
                   WithReason(probe.error().message, reason));
  }
  return FromBuild(op, index, graph.AddWrench(spec, f, m, stamp));
}

template <coord::Backend B>
OpOutcome AddPose(core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index) {
  const core::PoseSpec spec = PoseSpecOf(op.names);
  const Eigen::Vector3d p = ToVector(op.position);
  const RotationValue& r = op.rotation;
  std::optional<core::Stamp> stamp;
  if (std::string reason; !StampOf(op, &stamp, &reason)) {
    // The add's own order: invalid_name comes before invalid_number. A position of NaN makes
    // the graph check the names and stop at invalid_number, changing nothing.
    const auto probe =
        graph.AddPose(spec, Eigen::Quaterniond::Identity(), Eigen::Vector3d(kNaN, 0, 0));
    if (probe.error().code != base::ErrorCode::kInvalidNumber) return FromBuild(op, index, probe);
    return Failure(op, index, base::ErrorCode::kInvalidNumber,
                   WithReason(probe.error().message, reason));
  }
  const coord::Covariance6 S = CovarianceOf(op);
  const core::CovarianceInput covariance = CovarianceInputOf(op, S);
  const auto add = [&](const auto& rotation) {
    if (op.has_covariance) {
      return stamp ? graph.AddPose(spec, rotation, p, *stamp, covariance)
                   : graph.AddPose(spec, rotation, p, covariance);
    }
    return stamp ? graph.AddPose(spec, rotation, p, *stamp) : graph.AddPose(spec, rotation, p);
  };
  if (op.repair) {
    // The repairing add takes a quaternion; a rotation that is not one is validated as given
    // first, so that an invalid one is refused exactly as without repair.
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    if (r.form == RotationForm::kQuaternion) {
      q = Eigen::Quaterniond(r.quaternion[0], r.quaternion[1], r.quaternion[2], r.quaternion[3]);
    } else if (r.form == RotationForm::kRpy) {
      q = Eigen::AngleAxisd(r.rpy[2], Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(r.rpy[1], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r.rpy[0], Eigen::Vector3d::UnitX());
    } else if (r.form == RotationForm::kMatrix) {
      Eigen::Matrix3d R;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) R(i, j) = r.matrix[i][j];
      }
      auto valid = coord::ValidateRotationMatrix(R);
      if (!valid) return FromBuild(op, index, graph.AddPose(spec, R, p));
      q = Eigen::Quaterniond(*valid);
    }
    return FromRepair(op, index, graph.AddPose(spec, q, p, core::RepairPolicy{}));
  }
  switch (r.form) {
    case RotationForm::kIdentity:
      return FromBuild(op, index, add(Eigen::Quaterniond::Identity()));
    case RotationForm::kQuaternion:
      // Passed as written: normalizing here would hide invalid_rotation.
      return FromBuild(op, index,
                       add(Eigen::Quaterniond(r.quaternion[0], r.quaternion[1], r.quaternion[2],
                                              r.quaternion[3])));
    case RotationForm::kRpy: {
      // R = Rz(yaw) Ry(pitch) Rx(roll); a non-finite angle gives a non-finite quaternion, which
      // the graph reports as invalid_number.
      const Eigen::Quaterniond q = Eigen::AngleAxisd(r.rpy[2], Eigen::Vector3d::UnitZ()) *
                                   Eigen::AngleAxisd(r.rpy[1], Eigen::Vector3d::UnitY()) *
                                   Eigen::AngleAxisd(r.rpy[0], Eigen::Vector3d::UnitX());
      return FromBuild(op, index, add(q));
    }
    case RotationForm::kMatrix: {
      Eigen::Matrix3d R;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) R(i, j) = r.matrix[i][j];
      }
      return FromBuild(op, index, add(R));
    }
  }
  base::DemandFailed("valid RotationForm", __FILE__, __LINE__);
}

core::JointType JointTypeOf(JointKind k) {
  switch (k) {
    case JointKind::kRevolute:
      return core::JointType::kRevolute;
    case JointKind::kContinuous:
      return core::JointType::kContinuous;
    case JointKind::kPrismatic:
      return core::JointType::kPrismatic;
    case JointKind::kFixed:
      return core::JointType::kFixed;
  }
  return core::JointType::kFixed;
}

template <coord::Backend B>
OpOutcome AddJoint(core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index) {
  const SemanticNames& n = op.names;
  core::JointSpec s;
  s.name = op.name;
  s.type = JointTypeOf(op.joint_type);
  s.parent = n.ref_orientation;
  s.parent_body = n.ref_body;
  s.child = n.orientation;
  s.child_body = n.body;
  s.p_origin = ToVector(op.position);
  const RotationValue& r = op.rotation;
  switch (r.form) {
    case RotationForm::kIdentity:
      break;
    case RotationForm::kQuaternion:
      s.q_origin =
          Eigen::Quaterniond(r.quaternion[0], r.quaternion[1], r.quaternion[2], r.quaternion[3]);
      break;
    case RotationForm::kRpy:
      s.q_origin = Eigen::AngleAxisd(r.rpy[2], Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(r.rpy[1], Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(r.rpy[0], Eigen::Vector3d::UnitX());
      break;
    case RotationForm::kMatrix: {
      Eigen::Matrix3d R;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) R(i, j) = r.matrix[i][j];
      }
      s.R_origin = R;
      break;
    }
  }
  s.axis = ToVector(op.axis);
  s.lower = op.lower;
  s.upper = op.upper;
  if (op.has_mimic) {
    s.mimic = op.mimic_joint;
    s.multiplier = op.mimic_multiplier;
    s.offset = op.mimic_offset;
  }
  return FromBuild(op, index, graph.AddJoint(s));
}

template <coord::Backend B>
OpOutcome AddTwist(core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index) {
  const core::TwistSpec spec = TwistSpecOf(op.names);
  if (op.repair) {
    return FromRepair(
        op, index,
        graph.AddTwist(spec, ToVector(op.linear), ToVector(op.angular), core::RepairPolicy{}));
  }
  std::optional<core::Stamp> stamp;
  if (std::string reason; !StampOf(op, &stamp, &reason)) {
    const auto probe =
        graph.AddTwist(spec, Eigen::Vector3d(kNaN, 0, 0), Eigen::Vector3d::Zero());  // as AddPose
    if (probe.error().code != base::ErrorCode::kInvalidNumber) return FromBuild(op, index, probe);
    return Failure(op, index, base::ErrorCode::kInvalidNumber,
                   WithReason(probe.error().message, reason));
  }
  if (op.has_acceleration) {  // without covariance (the reader checked)
    const core::AccelerationInput A{ToVector(op.acceleration_linear),
                                    ToVector(op.acceleration_angular)};
    return FromBuild(
        op, index,
        stamp ? graph.AddTwist(spec, ToVector(op.linear), ToVector(op.angular), *stamp, A)
              : graph.AddTwist(spec, ToVector(op.linear), ToVector(op.angular), A));
  }
  if (op.has_covariance) {
    const coord::Covariance6 S = CovarianceOf(op);
    const core::CovarianceInput covariance = CovarianceInputOf(op, S);
    return FromBuild(
        op, index,
        stamp ? graph.AddTwist(spec, ToVector(op.linear), ToVector(op.angular), *stamp, covariance)
              : graph.AddTwist(spec, ToVector(op.linear), ToVector(op.angular), covariance));
  }
  if (stamp)
    return FromBuild(op, index,
                     graph.AddTwist(spec, ToVector(op.linear), ToVector(op.angular), *stamp));
  return FromBuild(op, index, graph.AddTwist(spec, ToVector(op.linear), ToVector(op.angular)));
}

// An acceleration on its own, at the op's stamp if it has one (a stamp that is no time: the
// graph's name checks first, as AddTwist).
template <coord::Backend B>
OpOutcome AddAcceleration(core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index) {
  const core::TwistSpec spec = TwistSpecOf(op.names);
  const Eigen::Vector3d a = ToVector(op.acceleration_linear),
                        alpha = ToVector(op.acceleration_angular);
  std::optional<core::Stamp> stamp;
  if (std::string reason; !StampOf(op, &stamp, &reason)) {
    const auto probe = graph.AddAcceleration(spec, Eigen::Vector3d(kNaN, 0, 0), alpha);
    if (probe.error().code != base::ErrorCode::kInvalidNumber) return FromBuild(op, index, probe);
    return Failure(op, index, base::ErrorCode::kInvalidNumber,
                   WithReason(probe.error().message, reason));
  }
  return FromBuild(op, index,
                   stamp ? graph.AddAcceleration(spec, a, alpha, *stamp)
                         : graph.AddAcceleration(spec, a, alpha));
}

template <coord::Backend B>
OpOutcome SetJoints(core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index) {
  std::vector<core::JointValue> q, qdot, qddot;
  for (const auto& [name, value] : op.positions) q.push_back({name, value});
  for (const auto& [name, value] : op.velocities) qdot.push_back({name, value});
  for (const auto& [name, value] : op.accelerations) qddot.push_back({name, value});
  std::optional<core::Stamp> stamp;
  if (std::string reason;
      !StampOf(op, &stamp, &reason)) {  // invalid_number comes first for joint states
    return Failure(op, index, base::ErrorCode::kInvalidNumber,
                   "joint state rejected (invalid_number): " + reason);
  }
  return FromBuild(
      op, index, stamp ? graph.SetJoints(q, qdot, qddot, *stamp) : graph.SetJoints(q, qdot, qddot));
}

template <coord::Backend B>
OpOutcome LoadUrdf(core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index,
                   std::string_view base_dir) {
#if SEMGRAPH_SCRIPT_HAS_MODELS
  std::string path = op.file;
  const bool uri = path.rfind("file://", 0) == 0 || path.rfind("package://", 0) == 0;
  if (!uri && !path.empty() && path.front() != '/' && !base_dir.empty())
    path = std::string(base_dir) + "/" + path;
  auto robot = models::LoadUrdfFile(graph, path, op.prefix);
  if (!robot) {
    // Name the file as the script wrote it, not as resolved against the script's folder.
    std::string message = robot.error().message;
    if (const std::size_t at = message.find(path); at != std::string::npos && path != op.file) {
      message.replace(at, path.size(), op.file);
    }
    return Failure(op, index, robot.error().code, message);
  }
  return Success(index);
#else
  (void)graph;
  (void)base_dir;
  return Failure(op, index, base::ErrorCode::kInvalidModel,
                 "robot model " + op.file +
                     " rejected (invalid_model): this tool was built without semgraph::models");
#endif
}

// A query's time policy from the op's fields. False, with the reason, when a time is not valid
// (not finite, out of range, or a negative horizon).
struct QueryTime {
  core::TimePolicy policy = core::Latest{};
  std::optional<core::TimeTravel> travel;
};

bool TimeOf(const ScriptOp& op, QueryTime* out, std::string* reason) {
  const auto time = [&](std::string_view field, double seconds, std::optional<std::int64_t>* ns) {
    *ns = core::NanosecondsFromSeconds(seconds);
    if (!*ns) *reason = NotATime(field, seconds);
    return ns->has_value();
  };
  std::optional<std::int64_t> at, not_before_ns, horizon_ns, ref_at;
  if (op.at == AtKind::kTime && !time("at", op.at_seconds, &at)) return false;
  if (op.ref_at && !time("ref_at", *op.ref_at, &ref_at)) return false;
  if (op.not_before && !time("not_before", *op.not_before, &not_before_ns)) return false;
  if (op.max_extrapolation) {
    if (*op.max_extrapolation < 0) {  // negative before rounding (-1e-10 s too)
      *reason = TimeText("max_extrapolation", *op.max_extrapolation) + " is negative";
      return false;
    }
    if (!time("max_extrapolation", *op.max_extrapolation, &horizon_ns)) return false;
  }
  std::optional<core::Stamp> not_before;
  if (not_before_ns) not_before = core::Stamp::Nanoseconds(*not_before_ns);
  const core::Duration horizon = core::Duration::Nanoseconds(horizon_ns.value_or(0));
  if (ref_at) {
    out->travel.emplace(core::Stamp::Nanoseconds(*at), core::Stamp::Nanoseconds(*ref_at), op.fixed,
                        horizon, not_before);
  } else if (op.at == AtKind::kTime) {
    out->policy = core::At{core::Stamp::Nanoseconds(*at), horizon, not_before};
  } else if (op.at == AtKind::kLatestCommon) {
    out->policy = core::LatestCommon{horizon, not_before};
  } else {
    out->policy = core::Latest{not_before};
  }
  return true;
}

// A stamp in seconds, as printed: the nearest double of ns / 1e9 (round-trips through %.17g).
double Seconds(core::Stamp s) { return static_cast<double>(s.nanoseconds()) / 1e9; }

// Appends the time keys of a successful query: those that apply, in the documented order.
OpOutcome WithTime(OpOutcome out, const core::TimeReport& t) {
  if (!out.ok) return out;
  std::string keys;
  const std::pair<std::string_view, const std::optional<core::Stamp>*> stamps[] = {
      {"time", &t.time}, {"ref_time", &t.ref_time}, {"oldest", &t.oldest}, {"newest", &t.newest}};
  for (const auto& [key, stamp] : stamps) {
    if (*stamp) keys += ", \"" + std::string(key) + "\": " + JsonNumber(Seconds(**stamp));
  }
  if (t.extrapolated) keys += ", \"extrapolated\": true";
  out.json.insert(out.json.size() - 1, keys);
  return out;
}

template <coord::Backend B>
OpOutcome Jacobian(const core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index,
                   const core::TimePolicy& policy) {
  const core::TwistSpec spec = TwistSpecOf(op.names);
  const auto timed = graph.GetJacobian(spec, policy);
  if (!timed) return Failure(op, index, timed.error().code, graph.Describe(timed.error(), spec));
  const core::Jacobian* J = &timed->value;
  if (!J->J.allFinite())
    return Failure(op, index, base::ErrorCode::kInvalidNumber, "the Jacobian is not finite");
  std::string json = "{\"op\": " + std::to_string(index) + ", \"ok\": true, \"joints\": [";
  for (std::size_t c = 0; c < J->joints.size(); ++c) {
    if (c > 0) json += ", ";
    json += JsonString(graph.joint_name(J->joints[c]));
  }
  json += "]";
  for (int part = 0; part < 2; ++part) {
    json += part == 0 ? ", \"linear\": [" : ", \"angular\": [";
    for (int row = 0; row < 3; ++row) {
      if (row > 0) json += ", ";
      json += "[";
      for (Eigen::Index c = 0; c < J->J.cols(); ++c) {
        if (c > 0) json += ",";
        json += JsonNumber(J->J(3 * part + row, c));
      }
      json += "]";
    }
    json += "]";
  }
  return WithTime(OpOutcome{true, "", json + "}"}, timed->time);
}

// A wrench, force or moment query (docs/dynamics.md) under the query's time policy (the time
// fields of a twist query but 'source'); the time keys of the answer as a twist query's.
template <coord::Backend B>
OpOutcome WrenchQuery(const core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index) {
  const core::WrenchSpec spec = WrenchSpecOf(op.names);
  QueryTime time;
  if (std::string reason; !TimeOf(op, &time, &reason)) {
    // invalid_name before invalid_number: a negative horizon makes the graph check the names.
    const auto probe =
        graph.GetWrench(spec, core::At{core::Stamp{}, core::Duration::Nanoseconds(-1)});
    if (probe.error().code != base::ErrorCode::kInvalidNumber) {
      return Failure(op, index, probe.error().code, graph.Describe(probe.error(), spec));
    }
    return Failure(op, index, base::ErrorCode::kInvalidNumber,
                   "query failed (invalid_number): " + reason);
  }
  const auto W = graph.GetWrench(spec, time.policy);
  if (!W) return Failure(op, index, W.error().code, graph.Describe(W.error(), spec));
  const coord::Wrench& w = W->value;
  if (op.query_kind == QueryKind::kForce) {
    return WithTime(Success(index, {{"force", Values(w.force)}}), W->time);
  }
  if (op.query_kind == QueryKind::kMoment) {
    return WithTime(Success(index, {{"moment", Values(w.moment)}}), W->time);
  }
  return WithTime(Success(index, {{"force", Values(w.force)}, {"moment", Values(w.moment)}}),
                  W->time);
}

// An acceleration, linear_acceleration or angular_acceleration query (docs/dynamics.md §7),
// under the query's time policy (docs/dynamics.md "Stamped accelerations"; no time travel, no
// source: the reader refuses them).
template <coord::Backend B>
OpOutcome AccelerationQuery(const core::SceneGraph<B>& graph, const ScriptOp& op,
                            std::size_t index) {
  const core::TwistSpec spec = TwistSpecOf(op.names);
  const bool angular = op.query_kind == QueryKind::kAngularAcceleration;
  QueryTime time;
  if (std::string reason; !TimeOf(op, &time, &reason)) {
    // invalid_name before invalid_number, as the other queries (a negative horizon probes).
    const core::At probe{core::Stamp{}, core::Duration::Nanoseconds(-1)};
    const core::QueryError error = angular ? graph.GetAngularAcceleration(spec, probe).error()
                                           : graph.GetAcceleration(spec, probe).error();
    if (error.code != base::ErrorCode::kInvalidNumber) {
      return Failure(op, index, error.code, graph.Describe(error, spec));
    }
    return Failure(op, index, base::ErrorCode::kInvalidNumber,
                   "query failed (invalid_number): " + reason);
  }
  if (angular) {
    const auto alpha = graph.GetAngularAcceleration(spec, time.policy);
    if (!alpha) return Failure(op, index, alpha.error().code, graph.Describe(alpha.error(), spec));
    return WithTime(Success(index, {{"angular", Values(alpha->value.value)}}), alpha->time);
  }
  const auto A = graph.GetAcceleration(spec, time.policy);
  if (!A) return Failure(op, index, A.error().code, graph.Describe(A.error(), spec));
  if (op.query_kind == QueryKind::kLinearAcceleration) {
    return WithTime(Success(index, {{"linear", Values(A->value.linear)}}), A->time);
  }
  return WithTime(
      Success(index, {{"linear", Values(A->value.linear)}, {"angular", Values(A->value.angular)}}),
      A->time);
}

template <coord::Backend B>
OpOutcome QueryValue(const core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index) {
  if (op.query_kind == QueryKind::kWrench || op.query_kind == QueryKind::kForce ||
      op.query_kind == QueryKind::kMoment) {
    return WrenchQuery(graph, op, index);
  }
  if (op.query_kind == QueryKind::kAcceleration ||
      op.query_kind == QueryKind::kLinearAcceleration ||
      op.query_kind == QueryKind::kAngularAcceleration) {
    return AccelerationQuery(graph, op, index);
  }
  const SemanticNames& n = op.names;
  const bool pose_kind = op.query_kind == QueryKind::kPose ||
                         op.query_kind == QueryKind::kPosition ||
                         op.query_kind == QueryKind::kOrientation;
  const core::PoseSpec pose_spec = PoseSpecOf(n);
  const core::TwistSpec twist_spec = TwistSpecOf(n);
  QueryTime time;
  if (std::string reason; !TimeOf(op, &time, &reason)) {
    // The query's order: invalid_name before invalid_number. A negative horizon makes the graph
    // check the names the kind uses (a time travel's fixed frame too) and stop at invalid_number.
    const core::At probe{core::Stamp{}, core::Duration::Nanoseconds(-1)};
    const core::TimeTravel travel_probe{core::Stamp{}, core::Stamp{}, op.fixed,
                                        core::Duration::Nanoseconds(-1)};
    const auto pose_probe = [&](auto&& get) { return op.ref_at ? get(travel_probe) : get(probe); };
    core::QueryError error;
    if (op.query_kind == QueryKind::kPose) {
      error = pose_probe([&](const auto& p) { return graph.GetPose(pose_spec, p).error(); });
    } else if (op.query_kind == QueryKind::kPosition) {
      error = pose_probe([&](const auto& p) { return graph.GetPosition(pose_spec, p).error(); });
    } else if (op.query_kind == QueryKind::kOrientation) {
      error = pose_probe([&](const auto& p) { return graph.GetOrientation(pose_spec, p).error(); });
    } else if (op.query_kind == QueryKind::kAngularVelocity) {
      error = graph.GetAngularVelocity(twist_spec, probe).error();
    } else {
      error = graph.GetTwist(twist_spec, probe).error();
    }
    if (error.code != base::ErrorCode::kInvalidNumber) {
      return Failure(
          op, index, error.code,
          pose_kind ? graph.Describe(error, pose_spec) : graph.Describe(error, twist_spec));
    }
    return Failure(op, index, base::ErrorCode::kInvalidNumber,
                   "query failed (invalid_number): " + reason);
  }
  if (op.query_kind == QueryKind::kJacobian) return Jacobian(graph, op, index, time.policy);
  const core::TwistSource source =
      op.source_poses ? core::TwistSource::kPoses : core::TwistSource::kTwists;
  // One call per kind, with the policy or the time travel.
  const auto pose_query = [&](auto&& get) {
    return time.travel ? get(*time.travel) : get(time.policy);
  };
  switch (op.query_kind) {
    case QueryKind::kPose: {
      const auto X = pose_query([&](const auto& t) { return graph.GetPose(pose_spec, t); });
      if (!X) return Failure(op, index, X.error().code, graph.Describe(X.error(), pose_spec));
      return WithTime(
          Success(index, {{"position", Values(B::TranslationOf(X->value.value))},
                          {"quaternion", Values(B::ToQuaternion(B::RotationOf(X->value.value)))}}),
          X->time);
    }
    case QueryKind::kPosition: {
      const auto p = pose_query([&](const auto& t) { return graph.GetPosition(pose_spec, t); });
      if (!p) return Failure(op, index, p.error().code, graph.Describe(p.error(), pose_spec));
      return WithTime(Success(index, {{"position", Values(p->value.value)}}), p->time);
    }
    case QueryKind::kOrientation: {
      const auto R = pose_query([&](const auto& t) { return graph.GetOrientation(pose_spec, t); });
      if (!R) return Failure(op, index, R.error().code, graph.Describe(R.error(), pose_spec));
      return WithTime(Success(index, {{"quaternion", Values(B::ToQuaternion(R->value.value))}}),
                      R->time);
    }
    case QueryKind::kTwist: {
      const auto V = graph.GetTwist(twist_spec, time.policy, source);
      if (!V) return Failure(op, index, V.error().code, graph.Describe(V.error(), twist_spec));
      return WithTime(Success(index, {{"linear", Values(V->value.linear)},
                                      {"angular", Values(V->value.angular)}}),
                      V->time);
    }
    case QueryKind::kLinearVelocity: {
      const auto v = graph.GetLinearVelocity(twist_spec, time.policy, source);
      if (!v) return Failure(op, index, v.error().code, graph.Describe(v.error(), twist_spec));
      return WithTime(Success(index, {{"linear", Values(v->value.value)}}), v->time);
    }
    case QueryKind::kAngularVelocity: {
      const auto w = graph.GetAngularVelocity(twist_spec, time.policy, source);
      if (!w) return Failure(op, index, w.error().code, graph.Describe(w.error(), twist_spec));
      return WithTime(Success(index, {{"angular", Values(w->value.value)}}), w->time);
    }
    case QueryKind::kJacobian:
    case QueryKind::kWrench:
    case QueryKind::kForce:
    case QueryKind::kMoment:
    case QueryKind::kAcceleration:
    case QueryKind::kLinearAcceleration:
    case QueryKind::kAngularAcceleration:
      break;
  }
  base::DemandFailed("valid QueryKind", __FILE__, __LINE__);
}

// Appends the answer's covariance, row-major, to a successful query's object.
template <int N>
OpOutcome WithCovarianceKey(OpOutcome out, const ScriptOp& op, std::size_t index,
                            const Eigen::Matrix<double, N, N>& S) {
  if (!S.allFinite()) {
    return Failure(op, index, base::ErrorCode::kInvalidNumber,
                   "the covariance of the result is not finite (overflow)");
  }
  std::string key = ", \"covariance\": [";
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j) {
      if (i + j > 0) key += ',';
      key += JsonNumber(S(i, j));
    }
  }
  out.json.insert(out.json.size() - 1, key + "]");
  return out;
}

// The covariance of a query at its time (docs/uncertainty.md, "Time"): `untimed` without time
// fields (and without source poses, which the timed queries read: latest by default), else the
// timed query's (time policy, or time travel unless at_travel is nullptr), as `untimed` gives
// them back.
template <class Untimed, class AtPolicy, class AtTravel>
auto CovarianceAt(const ScriptOp& op, const QueryTime& time, Untimed&& untimed,
                  AtPolicy&& at_policy, AtTravel&& at_travel) {
  using Result = decltype(untimed());
  const bool timed =
      time.travel || op.at != AtKind::kLatest || op.not_before.has_value() || op.source_poses;
  if (!timed) return untimed();
  const auto unwrap = [](auto&& answer) -> Result {
    if (!answer) return base::Unexpected{answer.error()};
    return answer->value;
  };
  if constexpr (!std::is_same_v<std::decay_t<AtTravel>, std::nullptr_t>) {
    if (time.travel) return unwrap(at_travel(*time.travel));
  }
  return unwrap(at_policy(time.policy));
}

// The twist query with covariance, untimed or at a policy with a source (the order before it).
template <coord::Backend B>
auto TwistCovariance(const core::SceneGraph<B>& graph, const core::TwistSpec& spec,
                     coord::CovarianceOrder order) {
  return graph.GetTwistWithCovariance(spec, order);
}
template <coord::Backend B>
auto TwistCovariance(const core::SceneGraph<B>& graph, const core::TwistSpec& spec,
                     coord::CovarianceOrder order, const core::TimePolicy& policy,
                     core::TwistSource source) {
  return graph.GetTwistWithCovariance(spec, policy, order, source);
}

// A query: its value (and time keys), then, when asked (`covariance: true`), the covariance of
// the answer (docs/uncertainty.md §3) at the query's time, twists from `source`.
template <coord::Backend B>
OpOutcome Query(const core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index) {
  OpOutcome out = QueryValue(graph, op, index);
  if (!out.ok || !op.query_covariance) return out;
  QueryTime time;
  if (std::string reason; !TimeOf(op, &time, &reason)) return out;  // QueryValue refused it
  const core::PoseSpec pose_spec = PoseSpecOf(op.names);
  const core::TwistSpec twist_spec = TwistSpecOf(op.names);
  const coord::CovarianceOrder order = op.covariance_angular_first
                                           ? coord::CovarianceOrder::kAngularLinear
                                           : coord::CovarianceOrder::kLinearAngular;
  const core::TwistSource source =
      op.source_poses ? core::TwistSource::kPoses : core::TwistSource::kTwists;
  const auto emit = [&](const auto& answer, const auto& spec) {
    if (!answer) {
      return Failure(op, index, answer.error().code, graph.Describe(answer.error(), spec));
    }
    return WithCovarianceKey(std::move(out), op, index, answer->covariance);
  };
  const auto pose = [&](auto&& get) {
    return CovarianceAt(
        op, time, [&] { return get(); }, [&](const core::TimePolicy& p) { return get(p); },
        [&](const core::TimeTravel& t) { return get(t); });
  };
  const auto twist = [&](auto&& get) {
    return CovarianceAt(
        op, time, [&] { return get(); }, [&](const core::TimePolicy& p) { return get(p, source); },
        nullptr);  // the reader refuses ref_at on twists
  };
  switch (op.query_kind) {
    case QueryKind::kPose:
      return emit(pose([&](const auto&... t) {
                    return graph.GetPoseWithCovariance(pose_spec, t..., order);
                  }),
                  pose_spec);
    case QueryKind::kPosition:
      return emit(
          pose([&](const auto&... t) { return graph.GetPositionWithCovariance(pose_spec, t...); }),
          pose_spec);
    case QueryKind::kOrientation:
      return emit(pose([&](const auto&... t) {
                    return graph.GetOrientationWithCovariance(pose_spec, t...);
                  }),
                  pose_spec);
    case QueryKind::kTwist:
      return emit(
          twist([&](const auto&... t) { return TwistCovariance(graph, twist_spec, order, t...); }),
          twist_spec);
    case QueryKind::kLinearVelocity:
      return emit(twist([&](const auto&... t) {
                    return graph.GetLinearVelocityWithCovariance(twist_spec, t...);
                  }),
                  twist_spec);
    case QueryKind::kAngularVelocity:
      return emit(twist([&](const auto&... t) {
                    return graph.GetAngularVelocityWithCovariance(twist_spec, t...);
                  }),
                  twist_spec);
    case QueryKind::kJacobian:
    case QueryKind::kWrench:
    case QueryKind::kForce:
    case QueryKind::kMoment:
    case QueryKind::kAcceleration:
    case QueryKind::kLinearAcceleration:
    case QueryKind::kAngularAcceleration:
      break;  // the reader takes no covariance on Jacobian, wrench and acceleration queries
  }
  return out;
}

}  // namespace

std::string JsonString(std::string_view text) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string s;
  s.reserve(text.size() + 2);
  s += '"';
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x80) {
      const std::size_t length = base::Utf8Length(text, i);
      if (length == 0) {
        s += "\\ufffd";  // JSON text must be UTF-8; keep the position of the bad byte visible
        ++i;
      } else if (const std::string_view escaped = LineBreakingEscape(text.substr(i, length));
                 !escaped.empty()) {
        s += escaped;
        i += length;
      } else {
        s.append(text.substr(i, length));
        i += length;
      }
      continue;
    }
    switch (c) {
      case '"':
        s += "\\\"";
        break;
      case '\\':
        s += "\\\\";
        break;
      case '\b':
        s += "\\b";
        break;
      case '\f':
        s += "\\f";
        break;
      case '\n':
        s += "\\n";
        break;
      case '\r':
        s += "\\r";
        break;
      case '\t':
        s += "\\t";
        break;
      default:
        if (c < 0x20 || c == 0x7F) {
          s += "\\u00";
          s += kHex[c >> 4];
          s += kHex[c & 0xF];
        } else {
          s += static_cast<char>(c);
        }
    }
    ++i;
  }
  s += '"';
  return s;
}

std::string JsonNumber(double value) {
  if (value == 0.0) value = 0.0;  // -0 and 0 are one value; print both as 0
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

namespace {

template <coord::Backend B>
OpOutcome ApplyOpUnlabelled(core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index,
                            std::string_view base_dir) {
  const SemanticNames& n = op.names;
  switch (op.kind) {
    case OpKind::kBody:
      return FromBuild(op, index, graph.AddBody(op.name));
    case OpKind::kFrame:
      return FromBuild(op, index, graph.AddFrame(op.name, n.body));
    case OpKind::kPose:
      return AddPose(graph, op, index);
    case OpKind::kTwist:
      return AddTwist(graph, op, index);
    case OpKind::kRemovePose:
      return FromBuild(op, index, graph.RemovePose(n.orientation, n.ref_orientation));
    case OpKind::kRemoveTwist:
      return FromBuild(op, index, graph.RemoveTwist(n.point, n.ref_body));
    case OpKind::kWrench:
      return AddWrench(graph, op, index);
    case OpKind::kRemoveWrench:
      return FromBuild(op, index, graph.RemoveWrench(n.body, n.ref_body));
    case OpKind::kAcceleration:
      return AddAcceleration(graph, op, index);
    case OpKind::kQuery:
      return Query(std::as_const(graph), op, index);
    case OpKind::kUrdf:
      return LoadUrdf(graph, op, index, base_dir);
    case OpKind::kJoint:
      return AddJoint(graph, op, index);
    case OpKind::kJoints:
      return SetJoints(graph, op, index);
    case OpKind::kBag:
#if SEMGRAPH_SCRIPT_HAS_ROS
      return ApplyBagOp(graph, op, index, base_dir);
#else
      return OpOutcome{false, "invalid_bag",
                       "{\"op\": " + std::to_string(index) +
                           ", \"ok\": false, \"error\": \"invalid_bag\", \"message\": " +
                           JsonString("bag " + op.file +
                                      " rejected: this tool was built without semgraph::ros") +
                           "}"};
#endif
  }
  base::DemandFailed("valid OpKind", __FILE__, __LINE__);
}

}  // namespace

core::TimeOptions TimeOptionsOf(const TimeSettings& time) {
  core::TimeOptions options;
  options.window = core::Duration::Nanoseconds(time.window_ns);
  options.interpolation = time.linear ? core::Interpolation::kLinear : core::Interpolation::kScrew;
  options.duplicate_stamp =
      time.reject_duplicates ? core::DuplicatePolicy::kReject : core::DuplicatePolicy::kReplace;
  return options;
}

std::string OpLabel(const ScriptOp& op) {
  switch (op.kind) {
    case OpKind::kRemovePose:
      return "remove pose";
    case OpKind::kRemoveTwist:
      return "remove twist";
    case OpKind::kRemoveWrench:
      return "remove wrench";
    case OpKind::kQuery:
      return "query " + std::string(ToString(op.query_kind));
    default:
      return std::string(ToString(op.kind));
  }
}

template <coord::Backend B>
OpOutcome ApplyOp(core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index,
                  std::string_view base_dir) {
  OpOutcome outcome = ApplyOpUnlabelled(graph, op, index, base_dir);
  // The op's kind and script line close the object, after the keys of the original format.
  outcome.json.pop_back();  // '}'
  outcome.json += ", \"kind\": " + JsonString(OpLabel(op)) +
                  ", \"line\": " + std::to_string(op.location.line) + "}";
  return outcome;
}

template OpOutcome ApplyOp<coord::QuaternionBackend>(core::SceneGraph<coord::QuaternionBackend>&,
                                                     const ScriptOp&, std::size_t,
                                                     std::string_view);
template OpOutcome ApplyOp<coord::HomogeneousBackend>(core::SceneGraph<coord::HomogeneousBackend>&,
                                                      const ScriptOp&, std::size_t,
                                                      std::string_view);

}  // namespace semgraph::script
