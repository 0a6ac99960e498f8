// tf transforms and joint states into a scene graph (tf_lift.h).
#include "semgraph/ros/tf_lift.h"

#include <cmath>
#include <limits>
#include <vector>

#include "semgraph/coord/covariance.h"
#include "semgraph/models/urdf.h"

namespace semgraph::ros {

using core::ErrorCode;
using core::PoseSpec;
using core::Stamp;

namespace {

std::string Vec(double x, double y, double z) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.17g, %.17g, %.17g)", x, y, z);
  return buf;
}

std::string Quat(const Quaternion& q) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%.17g, %.17g, %.17g, %.17g)", q.w, q.x, q.y, q.z);
  return buf;
}

bool Finite(const Transform& t) {
  const auto& v = t.translation;
  const auto& r = t.rotation;
  for (const double x : {v.x, v.y, v.z, r.x, r.y, r.z, r.w}) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

/// a == b; frame names are short: a byte loop beats a call of memcmp.
bool SameName(const std::string& a, std::string_view b) noexcept {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (a[i] != b[i]) return false;
  }
  return true;
}

/// A ROS covariance (row-major float64[36]) as a 6x6 matrix, entry for entry.
coord::Covariance6 ToMatrix(const Covariance36& c) {
  coord::Covariance6 S;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) S(i, j) = c[static_cast<std::size_t>(6 * i + j)];
  }
  return S;
}

/// Why a covariance message cannot be applied (checked before the graph is touched).
struct MessageProblem {
  ErrorCode code = ErrorCode::kOk;
  std::string message;
};

/// The pose's numbers and quaternion (as a transform's), normalizing q_PC.
MessageProblem CheckPose(const Pose& pose, Eigen::Quaterniond& q_PC) {
  const auto& p = pose.position;
  const auto& r = pose.orientation;
  for (const double x : {p.x, p.y, p.z, r.x, r.y, r.z, r.w}) {
    if (!std::isfinite(x)) {
      return {ErrorCode::kInvalidNumber, "pose position " + Vec(p.x, p.y, p.z) +
                                             " or orientation (w, x, y, z) = " + Quat(r) +
                                             " has a NaN or infinite component"};
    }
  }
  q_PC = Eigen::Quaterniond(r.w, r.x, r.y, r.z);
  const double norm2 = q_PC.squaredNorm();
  if (!(std::abs(norm2 - 1.0) <= kRosQuaternionTolerance)) {
    return {ErrorCode::kInvalidRotation, "pose orientation with |q|^2 = " + std::to_string(norm2) +
                                             ", more than 0.01 from 1 (tf2's tolerance)"};
  }
  q_PC.coeffs() /= std::sqrt(norm2);
  return {};
}

/// The core's covariance check (finite, not above 1e12, symmetric, PSD) on `what`.
MessageProblem CheckMatrix(const coord::Covariance6& S, std::string_view what) {
  const coord::CovarianceCheck check = coord::CheckCovariance(S);
  if (check.code() == ErrorCode::kOk) return {};
  return {check.code(), std::string(what) + ": " + coord::Describe(check)};
}

}  // namespace

template <coord::Backend B>
void TfLift<B>::CoverModel(const models::Robot& robot) {
  edges_.clear();  // a covered pair must not be updated by handle
  edge_index_.clear();
  next_edge_ = 0;
  const std::set<std::string, std::less<>> floating(robot.floating_joints.begin(),
                                                    robot.floating_joints.end());
  for (const std::string& link : robot.links) {
    const core::FrameIndex c = graph_.FindFrame(link);
    if (!c.is_valid()) continue;
    const core::FrameIndex p = graph_.pose_parent(c);
    if (!p.is_valid()) continue;  // the root link
    const std::string parent(graph_.frame_name(p));
    if (floating.count(link + " wrt " + parent) != 0) continue;  // an ordinary edge
    covered_.emplace(parent, link);
  }
}

template <coord::Backend B>
std::size_t TfLift<B>::FindCachedEdge(std::string_view parent, std::string_view child) {
  // A publisher sends its transforms in the same order message after message: the entry after
  // the last one used is nearly always the one (two short compares, no hashing).
  if (next_edge_ < edges_.size() && SameName(edges_[next_edge_].parent, parent) &&
      SameName(edges_[next_edge_].child, child)) {
    return next_edge_;
  }
  key_.assign(parent).append(1, '\n').append(child);  // '\n' is in no valid frame name
  const auto it = edge_index_.find(key_);
  return it == edge_index_.end() ? kNotCached : it->second;
}

template <coord::Backend B>
std::string TfLift<B>::BodyOf(std::string_view frame) const {
  return plan_.BodyOf(frame, [this](std::string_view f) -> std::optional<std::string> {
    const core::FrameIndex i = graph_.FindFrame(f);
    if (!i.is_valid()) return std::nullopt;
    return std::string(graph_.body_name(graph_.body_of(i)));
  });
}

template <coord::Backend B>
LiftOutcome TfLift<B>::Refuse(ErrorCode code, std::string message, std::string_view parent,
                              std::string_view child, const TransformOrigin& origin) {
  ++counts_.refused;
  findings_.Add(FindingCode{code, false}, parent, child, origin,
                [&] { return std::move(message); });
  return LiftOutcome::kRefused;
}

template <coord::Backend B>
LiftOutcome TfLift<B>::Apply(const TransformStamped& t, bool is_static, std::string_view topic,
                             std::int64_t log_time_ns) {
  // The steady state of a stream, kept lean: a new sample of a stamped edge this lift added
  // before, by handle (no name lookups, no body plan). Anything else, including any refusal,
  // takes the full path, which names it (the same checks: SetPose's codes are AddPose's for an
  // existing edge).
  if (!is_static && !edges_.empty() && Finite(t.transform)) {
    const auto& r = t.transform.rotation;
    Eigen::Quaterniond q_PC(r.w, r.x, r.y, r.z);
    const double norm2 = q_PC.squaredNorm();
    const std::size_t i =
        std::abs(norm2 - 1.0) <= kRosQuaternionTolerance
            ? FindCachedEdge(LiftFrameName(t.header.frame_id), LiftFrameName(t.child_frame_id))
            : kNotCached;
    if (i != kNotCached) {
      const double norm = std::sqrt(norm2);
      q_PC.coeffs() /= norm;
      const auto& v = t.transform.translation;
      if (graph_.SetPose(edges_[i].edge, q_PC, Eigen::Vector3d(v.x, v.y, v.z),
                         Stamp::Nanoseconds(ToNanoseconds(t.header.stamp))) == ErrorCode::kOk) {
        next_edge_ = i + 1 == edges_.size() ? 0 : i + 1;
        ++counts_.transforms;
        ++counts_.applied;
        if (std::abs(norm - 1.0) > 1e-6) ++counts_.normalized;
        return LiftOutcome::kApplied;
      }
    }
  }
  return ApplyByNames(t, is_static, topic, log_time_ns);
}

template <coord::Backend B>
LiftOutcome TfLift<B>::ApplyByNames(const TransformStamped& t, bool is_static,
                                    std::string_view topic, std::int64_t log_time_ns) {
  ++counts_.transforms;
  const std::string_view parent = LiftFrameName(t.header.frame_id);
  const std::string_view child = LiftFrameName(t.child_frame_id);
  const TransformOrigin origin{topic, log_time_ns, ToNanoseconds(t.header.stamp)};
  const auto& v = t.transform.translation;
  const auto& r = t.transform.rotation;
  if (!Finite(t.transform)) {
    return Refuse(ErrorCode::kInvalidNumber,
                  "translation " + Vec(v.x, v.y, v.z) + " or rotation (w, x, y, z) = " + Quat(r) +
                      " has a NaN or infinite component",
                  parent, child, origin);
  }
  Eigen::Quaterniond q_PC(r.w, r.x, r.y, r.z);
  const double norm2 = q_PC.squaredNorm();
  if (!(std::abs(norm2 - 1.0) <= kRosQuaternionTolerance)) {
    return Refuse(ErrorCode::kInvalidRotation,
                  "quaternion with |q|^2 = " + std::to_string(norm2) +
                      ", more than 0.01 from 1 (tf2's tolerance)",
                  parent, child, origin);
  }
  const double norm = std::sqrt(norm2);  // > 0.99 here
  const bool normalized = std::abs(norm - 1.0) > 1e-6;
  q_PC.coeffs() /= norm;
  const Eigen::Vector3d p_PoCo_P(v.x, v.y, v.z);

  LiftOutcome outcome;
  if (covered_.count(std::make_pair(std::string(parent), std::string(child))) != 0) {
    ++counts_.covered;
    if (!is_static && (!latest_joint_stamp_ns_ || *latest_joint_stamp_ns_ < origin.stamp_ns)) {
      outcome = Defer(parent, child, q_PC, p_PoCo_P, origin);
    } else {
      outcome = CompareWithModel(parent, child, q_PC, p_PoCo_P, is_static, origin);
    }
  } else {
    // A static transform that joins bodies puts the child on its parent's body, explicitly: a
    // child already on another body is then frame_body_mismatch, as the spec asks live.
    const std::string parent_body = BodyOf(parent);
    const std::string child_body =
        is_static && plan_.JoinsBodies(child) ? parent_body : BodyOf(child);
    const PoseSpec spec = PoseSpec::Of(child, child_body).RelativeTo(parent, parent_body);
    const core::BuildResult added =
        is_static ? graph_.AddPose(spec, q_PC, p_PoCo_P)
                  : graph_.AddPose(spec, q_PC, p_PoCo_P, Stamp::Nanoseconds(origin.stamp_ns));
    if (!added) return Refuse(added.error().code, added.error().message, parent, child, origin);
    if (!is_static && edges_.size() < kMaxCachedEdges) {
      if (auto edge = graph_.FindPoseEdge(child, parent)) {
        key_.assign(parent).append(1, '\n').append(child);
        edge_index_.emplace(key_, edges_.size());
        edges_.push_back({std::string(parent), std::string(child), *edge});
      }
    }
    ++counts_.applied;
    outcome = LiftOutcome::kApplied;
  }
  if (normalized) ++counts_.normalized;
  return outcome;
}

template <coord::Backend B>
LiftOutcome TfLift<B>::CompareWithModel(std::string_view parent, std::string_view child,
                                        const Eigen::Quaterniond& q_PC,
                                        const Eigen::Vector3d& p_PoCo_P, bool is_static,
                                        const TransformOrigin& origin) {
  const PoseSpec spec = PoseSpec::Of(child).RelativeTo(parent);
  const auto model = is_static
                         ? graph_.GetPose(spec, core::Latest())
                         : graph_.GetPose(spec, core::At(Stamp::Nanoseconds(origin.stamp_ns)));
  const auto mismatch = [&](FindingCode code, std::string message) {
    ++counts_.mismatched;
    findings_.Add(code, parent, child, origin, [&] { return std::move(message); });
    return LiftOutcome::kMismatch;
  };
  if (!model) {  // the model has no pose there (e.g. no joint state at that stamp)
    return mismatch(FindingCode{model.error().code, false},
                    "covered by the robot model, which has no pose of {" + std::string(child) +
                        "} wrt {" + std::string(parent) +
                        "} at this stamp: " + graph_.Describe(model.error(), spec));
  }
  const Eigen::Isometry3d X_PC = model->value.ToIsometry();
  const Eigen::Quaterniond q_model(X_PC.linear());
  const double angle = q_model.angularDistance(q_PC);
  const double distance = (X_PC.translation() - p_PoCo_P).norm();
  if (angle <= kModelTolerance && distance <= kModelTolerance) return LiftOutcome::kCovered;
  const Eigen::Vector3d& p = X_PC.translation();
  return mismatch(FindingCode::ModelMismatch(),
                  "the transform differs from the robot model's pose by " +
                      std::to_string(distance) + " m and " + std::to_string(angle) +
                      " rad (model position " + Vec(p.x(), p.y(), p.z()) + ", tf position " +
                      Vec(p_PoCo_P.x(), p_PoCo_P.y(), p_PoCo_P.z()) + ")");
}

template <coord::Backend B>
void TfLift<B>::Apply(const TFMessage& message, bool is_static, std::string_view topic,
                      std::int64_t log_time_ns) {
  for (const TransformStamped& t : message.transforms) {
    (void)Apply(t, is_static, topic, log_time_ns);
  }
}

template <coord::Backend B>
void TfLift<B>::Apply(const JointState& state, std::string_view topic, std::int64_t log_time_ns) {
  if (graph_.num_joints() == 0) {
    ++counts_.joint_states_skipped;
    return;
  }
  const TransformOrigin origin{topic, log_time_ns, ToNanoseconds(state.header.stamp)};
  const auto refuse = [&](ErrorCode code, std::string message) {
    ++counts_.joint_states_refused;
    findings_.Add(FindingCode{code, false}, "", "", origin, [&] { return std::move(message); });
  };
  const std::size_t n = state.name.size();
  if (!state.position.empty() && state.position.size() != n) {
    return refuse(ErrorCode::kInvalidNumber,
                  "joint state with " + std::to_string(n) + " names and " +
                      std::to_string(state.position.size()) + " positions");
  }
  std::vector<core::JointValue> positions, velocities;
  for (std::size_t i = 0; i < n; ++i) {
    if (!state.position.empty()) positions.push_back({state.name[i], state.position[i]});
    if (state.velocity.size() == n) velocities.push_back({state.name[i], state.velocity[i]});
  }
  const core::BuildResult set =
      graph_.SetJoints(positions, velocities, Stamp::Nanoseconds(origin.stamp_ns));
  if (!set) return refuse(set.error().code, set.error().message);
  ++counts_.joint_states;
  if (!latest_joint_stamp_ns_ || *latest_joint_stamp_ns_ < origin.stamp_ns) {
    latest_joint_stamp_ns_ = origin.stamp_ns;
  }
  CompareDeferredUpTo(*latest_joint_stamp_ns_);
}

template <coord::Backend B>
LiftOutcome TfLift<B>::Defer(std::string_view parent, std::string_view child,
                             const Eigen::Quaterniond& q_PC, const Eigen::Vector3d& p_PoCo_P,
                             const TransformOrigin& origin) {
  if (deferred_.size() == kMaxDeferredCovers) {
    CompareDeferred(deferred_.front());
    deferred_.pop_front();
  }
  deferred_.push_back({std::string(origin.topic), std::string(parent), std::string(child),
                       origin.log_time_ns, origin.stamp_ns, q_PC, p_PoCo_P});
  return LiftOutcome::kDeferred;
}

template <coord::Backend B>
void TfLift<B>::CompareDeferred(const DeferredCover& d) {
  (void)CompareWithModel(d.parent, d.child, d.q_PC, d.p_PoCo_P, false,
                         TransformOrigin{d.topic, d.log_time_ns, d.stamp_ns});
}

template <coord::Backend B>
void TfLift<B>::CompareDeferredUpTo(std::int64_t up_to_ns) {
  // Stamps mostly grow with arrival; a cover stamped later than one behind it just waits longer.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < deferred_.size(); ++i) {
    if (deferred_[i].stamp_ns <= up_to_ns) {
      CompareDeferred(deferred_[i]);
    } else {
      if (kept != i) deferred_[kept] = std::move(deferred_[i]);
      ++kept;
    }
  }
  deferred_.resize(kept);
}

template <coord::Backend B>
void TfLift<B>::Flush() {
  CompareDeferredUpTo(std::numeric_limits<std::int64_t>::max());
}

template <coord::Backend B>
LiftOutcome TfLift<B>::Apply(const PoseWithCovarianceStamped& message, std::string_view child_frame,
                             std::string_view topic, std::int64_t log_time_ns) {
  return ApplyWithCovariance(message.header, child_frame, message.pose, nullptr, topic,
                             log_time_ns);
}

template <coord::Backend B>
LiftOutcome TfLift<B>::Apply(const Odometry& message, std::string_view topic,
                             std::int64_t log_time_ns) {
  return ApplyWithCovariance(message.header, message.child_frame_id, message.pose, &message.twist,
                             topic, log_time_ns);
}

template <coord::Backend B>
LiftOutcome TfLift<B>::ApplyWithCovariance(const Header& header, std::string_view child_frame,
                                           const PoseWithCovariance& pose,
                                           const TwistWithCovariance* twist, std::string_view topic,
                                           std::int64_t log_time_ns) {
  const std::string_view parent = LiftFrameName(header.frame_id);
  const std::string_view child = LiftFrameName(child_frame);
  const TransformOrigin origin{topic, log_time_ns, ToNanoseconds(header.stamp)};
  const auto refuse = [&](ErrorCode code, std::string message) {
    ++counts_.covariance_refused;
    findings_.Add(FindingCode{code, false}, parent, child, origin,
                  [&] { return std::move(message); });
    return LiftOutcome::kRefused;
  };
  // Every number first: a bad message leaves the graph as it was.
  Eigen::Quaterniond q_PC;
  MessageProblem problem = CheckPose(pose.pose, q_PC);
  const coord::Covariance6 S_pose = ToMatrix(pose.covariance);
  if (problem.code == ErrorCode::kOk) problem = CheckMatrix(S_pose, "pose covariance");
  coord::Covariance6 S_twist = coord::Covariance6::Zero();
  Eigen::Vector3d v_PCo_C = Eigen::Vector3d::Zero(), w_PC_C = Eigen::Vector3d::Zero();
  if (twist != nullptr && problem.code == ErrorCode::kOk) {
    const Vector3& v = twist->twist.linear;
    const Vector3& w = twist->twist.angular;
    for (const double x : {v.x, v.y, v.z, w.x, w.y, w.z}) {
      if (!std::isfinite(x)) {
        problem = {ErrorCode::kInvalidNumber, "twist linear " + Vec(v.x, v.y, v.z) +
                                                  " or angular " + Vec(w.x, w.y, w.z) +
                                                  " has a NaN or infinite component"};
      }
    }
    v_PCo_C = Eigen::Vector3d(v.x, v.y, v.z);
    w_PC_C = Eigen::Vector3d(w.x, w.y, w.z);
    S_twist = ToMatrix(twist->covariance);
    if (problem.code == ErrorCode::kOk) problem = CheckMatrix(S_twist, "twist covariance");
  }
  if (problem.code != ErrorCode::kOk) return refuse(problem.code, std::move(problem.message));

  const std::string parent_body = BodyOf(parent);
  const std::string child_body = BodyOf(child);
  const Stamp stamp = Stamp::Nanoseconds(origin.stamp_ns);
  const PoseSpec spec = PoseSpec::Of(child, child_body).RelativeTo(parent, parent_body);
  const Eigen::Vector3d p_PoCo_P(pose.pose.position.x, pose.pose.position.y, pose.pose.position.z);
  const core::BuildResult added =
      graph_.AddPose(spec, q_PC, p_PoCo_P, stamp, core::CovarianceInput{&S_pose});
  if (!added) return refuse(added.error().code, "pose: " + added.error().message);
  if (twist != nullptr) {
    const core::TwistSpec twist_spec =
        core::TwistSpec::Of(child, child_body).RelativeTo(parent_body).ExpressedIn(child);
    const core::BuildResult twisted =
        graph_.AddTwist(twist_spec, v_PCo_C, w_PC_C, stamp, core::CovarianceInput{&S_twist});
    if (!twisted) {
      return refuse(twisted.error().code, "twist (its pose was added): " + twisted.error().message);
    }
    ++counts_.odometry;
  } else {
    ++counts_.poses_with_covariance;
  }
  return LiftOutcome::kApplied;
}

template class TfLift<coord::QuaternionBackend>;
template class TfLift<coord::HomogeneousBackend>;

}  // namespace semgraph::ros
