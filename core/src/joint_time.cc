// Stamped joint states (docs/kinematics.md "Time", docs/time.md): a state given with a stamp is
// a sample of (q, qdot) of each joint given and of its mimics, written into the histories of the
// joint's pose edge (X_origin M(q)) and twist edge (the twist of qdot), so the one evaluator reads
// joint edges exactly as any stamped edge. Contract: scene_graph.h (SetJoints with a stamp, the
// stamped SetJointPositions / Velocities / Accelerations / State).
//
// Interpolation: a joint's edges are interpolated as edges (the graph's mode). For revolute,
// continuous and prismatic joints both modes give the joint-space interpolation (q and qdot
// linear) as long as q moves by less than half a turn between two samples of one joint: the
// relative motion of two samples is a rotation about the fixed axis u (or a translation along
// it), which screw and slerp both follow at a constant rate. The pose edge's derivative (source
// poses) is then the twist of (q1 - q0) / (s1 - s0), and its extrapolation with the twist edge
// integrates q + qdot (t - s).
//
// A sample at an existing stamp is identical when q and qdot are each within
// 1e-9 max(1, |stored|): the stored q and qdot are recovered from the edge samples (revolute:
// the angle of X_origin^-1 X about u, modulo a full turn; prismatic: the offset along u).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "joint_scan.h"
#include "semgraph/base/demand.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/core/timed_read.h"
#include "text.h"

namespace semgraph::core {

using text::Reject;

namespace {

using internal::kLimitSlack;
constexpr double kSameJointValue = 1e-9;  // kinematics.md: identical samples

bool Near(double a, double b) {
  return std::abs(a - b) <= kSameJointValue * std::max(1.0, std::abs(b));
}

// The (q, qdot) a joint's edge samples hold.
void StoredJointState(const internal::JointRecord& j, const double (&pose)[7],
                      const double (&twist)[6], double& q, double& qdot) noexcept {
  const auto X = internal::PoseFromWords(pose);
  const TwistNumbers V = internal::TwistFromWords(twist);
  if (j.type == JointType::kPrismatic) {
    q = j.axis.dot(j.q_origin.conjugate() * (X.p - j.p_origin));
    qdot = j.axis.dot(V.v_DHo_H);
  } else {
    const Eigen::Quaterniond r = j.q_origin.conjugate() * X.q;
    q = 2.0 * std::atan2(r.vec().dot(j.axis), r.w());
    qdot = j.axis.dot(V.w_DH_H);
  }
}

// A revolute angle equals another modulo a full turn (both give the same edge value).
bool SameAngle(double q, double stored) {
  const double d = std::remainder(q - stored, 2.0 * std::numbers::pi);
  return std::abs(d) <= kSameJointValue * std::max(1.0, std::abs(q));
}

// The acceleration words of a joint's edge for qddot (null: none; a: room for them).
const double* JointAccelerationWords(const internal::JointRecord& j, const double* qddot,
                                     double (&a)[7]) noexcept {
  if (qddot == nullptr) return nullptr;
  AccelerationNumbers A;
  j.AccelerationAt(*qddot, A.a_DHo_H, A.alpha_DH_H);
  internal::WordsFromAcceleration(A, a);
  return a;
}

}  // namespace

template <coord::Backend B>
ErrorCode SceneGraph<B>::CheckJointSample(const internal::JointRecord& j, double q, double qdot,
                                          const double* qddot, std::int64_t s) const noexcept {
  const PoseHistory* hp = values_.history.pose_of(j.child.value());
  const TwistHistory* ht = values_.history.twist_of(topology_.twist_edge_of(j.child).value());
  if (j.timeless || !hp || !ht) return ErrorCode::kStampMismatch;
  const TimeOptions& o = values_.history.options;
  if (s < SaturatingSub(hp->newest_stamp(), o.window.nanoseconds())) return ErrorCode::kStampTooOld;
  if (o.duplicate_stamp == DuplicatePolicy::kReject && s <= hp->newest_stamp()) {
    double pw[7], tw[6];
    if (hp->ValueAt(s, pw) && ht->ValueAt(s, tw)) {
      double q0 = 0, qdot0 = 0;
      StoredJointState(j, pw, tw, q0, qdot0);
      const bool same_q = j.type == JointType::kPrismatic ? Near(q, q0) : SameAngle(q, q0);
      double a[7];
      if (!same_q || !Near(qdot, qdot0) ||
          !SameSampleAcceleration(*ht, s, JointAccelerationWords(j, qddot, a))) {
        return ErrorCode::kDuplicateStamp;
      }
    }
  }
  return ErrorCode::kOk;
}

// A sample's qddot: the given one, else the joint's state (the newest sample's), if it has one;
// its edge's twist history then has its acceleration words (SetJoints reserved them).
template <coord::Backend B>
void SceneGraph<B>::StoreJointSample(JointIndex index, const double* q_given,
                                     const double* qdot_given, const double* qddot_given,
                                     std::int64_t s) noexcept {
  internal::JointRecord& j = joints_[index];
  const double q = q_given ? *q_given : j.q, qdot = qdot_given ? *qdot_given : j.qdot;
  const double* qddot = qddot_given ? qddot_given : (j.has_qddot ? &j.qddot : nullptr);
  const double qddot_value = qddot ? *qddot : 0.0;  // j.qddot may change below
  const TwistEdgeIndex edge = topology_.twist_edge_of(j.child);
  PoseHistory& hp = values_.history.pose.writable(j.child.value());
  TwistHistory& ht = values_.history.twist.writable(edge.value());
  double pw[7], tw[6], aw[7];
  const double* a = JointAccelerationWords(j, qddot, aw);
  // The words were reserved with the joint's first stamped state (SetJoints with a stamp), so the
  // real-time setters never allocate and never drop a sample's acceleration.
  SEMGRAPH_DEMAND(a == nullptr || ht.has_accelerations());
  bool identical = false;
  if (s <= hp.newest_stamp() && hp.ValueAt(s, pw) && ht.ValueAt(s, tw)) {
    double q0 = 0, qdot0 = 0;
    StoredJointState(j, pw, tw, q0, qdot0);
    identical = (j.type == JointType::kPrismatic ? Near(q, q0) : SameAngle(q, q0)) &&
                Near(qdot, qdot0) && SameSampleAcceleration(ht, s, a);
  }
  if (!identical) {  // the same sample again is a no-op that keeps the stored one
    Eigen::Quaterniond q_PC;
    Eigen::Vector3d p_PC;
    j.PoseAt(q, q_PC, p_PC);
    TwistNumbers V;
    j.TwistAt(qdot, V.v_DHo_H, V.w_DH_H);
    internal::WordsFromPose(q_PC, p_PC, pw);
    internal::WordsFromTwist(V, tw);
    const bool becomes_newest = s >= hp.newest_stamp();
    const std::int64_t window = values_.history.options.window.nanoseconds();
    hp.Insert(s, pw, window);
    ht.Insert(s, tw, window, nullptr, a);
    if (becomes_newest) {  // the untimed readers' values and the state: the newest sample's
      j.q = q;
      j.qdot = qdot;
      if (qddot) {
        j.qddot = qddot_value;
        j.has_qddot = true;
      }
      values_.X_PF[j.child.value()].Store(B::MakePose(B::FromQuaternion(q_PC), p_PC));
      AccelerationNumbers A;
      if (qddot) j.AccelerationAt(qddot_value, A.a_DHo_H, A.alpha_DH_H);
      values_.StoreAcceleration(edge.value(), V, qddot ? &A : nullptr);  // before the twist
      values_.V_DH[edge.value()].Store(V);
    }
  }
  for (JointIndex m : j.mimics) {
    const internal::JointRecord& mj = joints_[m];
    const double qm = mj.multiplier * q + mj.offset, qdotm = mj.multiplier * qdot,
                 qddotm = mj.multiplier * qddot_value;
    StoreJointSample(m, &qm, &qdotm, qddot ? &qddotm : nullptr, s);  // mimics have no mimics
  }
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetGroupStamped(const JointGroup& group, const double* q,
                                         const double* qdot, const double* qddot, Stamp stamp,
                                         UpdateError* why) noexcept {
  // As SetGroup: one pass collects every failure and the first in the rules' order is reported.
  // A field not given is the joint's newest sample's (its state; qddot only if it has one), as
  // in SetJoints with a stamp, whose CheckJointSample / StoreJointSample this shares.
  const std::size_t n = group.joints.size();
  const std::int64_t s = stamp.nanoseconds();
  ErrorCode time = ErrorCode::kOk;  // the first stamp failure in the order of the codes
  const auto note = [&time](ErrorCode c) {
    if (c != ErrorCode::kOk && (time == ErrorCode::kOk || c < time)) time = c;
  };
  const ErrorCode code = internal::ScanJointGroup(
      joints_, group, q, qdot, qddot, [&](std::size_t i, const internal::JointRecord& j) {
        const double qi = q ? q[i] : j.q, qdoti = qdot ? qdot[i] : j.qdot;
        const double* qddoti = qddot ? qddot + i : (j.has_qddot ? &j.qddot : nullptr);
        note(CheckJointSample(j, qi, qdoti, qddoti, s));
        for (JointIndex m : j.mimics) {
          const internal::JointRecord& mj = joints_[m];
          const double qddotm = qddoti ? mj.multiplier * *qddoti : 0.0;
          note(CheckJointSample(mj, mj.multiplier * qi + mj.offset, mj.multiplier * qdoti,
                                qddoti ? &qddotm : nullptr, s));
        }
      });
  if (code != ErrorCode::kOk) return RefuseJoints(code, group, q, qdot, qddot, why);
  if (time != ErrorCode::kOk) return RefuseJoints(time, group, q, qdot, qddot, why);
  for (std::size_t i = 0; i < n; ++i) {
    StoreJointSample(group.joints[i].index, q ? q + i : nullptr, qdot ? qdot + i : nullptr,
                     qddot ? qddot + i : nullptr, s);
  }
  return internal::Report(why, ErrorCode::kOk);
}

// Only on refusal: a second pass finds the first joint that breaks the rule of `code` (the
// collecting pass above keeps only flags, so that the accepted case stays one cheap pass).
template <coord::Backend B>
ErrorCode SceneGraph<B>::RefuseJoints(ErrorCode code, const JointGroup& group, const double* q,
                                      const double* qdot, const double* qddot,
                                      UpdateError* why) const noexcept {
  internal::Report(why, code);
  if (why == nullptr) return code;
  if (code != ErrorCode::kInvalidNumber && code != ErrorCode::kJointLimit) return code;
  for (std::size_t i = 0; i < group.joints.size(); ++i) {
    why->joint = static_cast<std::uint32_t>(i);
    why->value.role = coord::ValueRole::kJointPosition;
    if (code == ErrorCode::kInvalidNumber) {
      why->value.problem = coord::ValueProblem::kNotFinite;
      // The first non-finite field of the joint: position, velocity, acceleration.
      const struct {
        const double* values;
        coord::ValueRole role;
      } fields[] = {{q, coord::ValueRole::kJointPosition},
                    {qdot, coord::ValueRole::kJointVelocity},
                    {qddot, coord::ValueRole::kJointAcceleration}};
      for (const auto& f : fields) {
        if (f.values && !std::isfinite(f.values[i])) {
          why->value.role = f.role;
          why->value.magnitude = f.values[i];
          return code;
        }
      }
      continue;
    }
    const internal::JointRecord* j = joints_.Get(group.joints[i]);
    if (!j || !j->limited()) continue;
    why->value.problem = coord::ValueProblem::kOutsideLimits;
    why->value.magnitude = q[i];
    if (q[i] < j->lower - kLimitSlack) {
      why->limit = j->lower;
      return code;
    }
    if (q[i] > j->upper + kLimitSlack) {
      why->limit = j->upper;
      return code;
    }
  }
  return code;
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointPositions(const JointGroup& group, std::span<const double> q,
                                           Stamp stamp, UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(q.size() == group.size());
  return SetGroupStamped(group, q.data(), nullptr, nullptr, stamp, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointVelocities(const JointGroup& group, std::span<const double> qdot,
                                            Stamp stamp, UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(qdot.size() == group.size());
  return SetGroupStamped(group, nullptr, qdot.data(), nullptr, stamp, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointState(const JointGroup& group, std::span<const double> q,
                                       std::span<const double> qdot, Stamp stamp,
                                       UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(q.size() == group.size() && qdot.size() == group.size());
  return SetGroupStamped(group, q.data(), qdot.data(), nullptr, stamp, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointAccelerations(const JointGroup& group,
                                               std::span<const double> qddot, Stamp stamp,
                                               UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(qddot.size() == group.size());
  return SetGroupStamped(group, nullptr, nullptr, qddot.data(), stamp, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointState(const JointGroup& group, std::span<const double> q,
                                       std::span<const double> qdot, std::span<const double> qddot,
                                       Stamp stamp, UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(q.size() == group.size() && qdot.size() == group.size() &&
                  qddot.size() == group.size());
  return SetGroupStamped(group, q.data(), qdot.data(), qddot.data(), stamp, why);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::SetJoints(std::span<const JointValue> positions,
                                     std::span<const JointValue> velocities, Stamp stamp) {
  return SetJoints(positions, velocities, std::span<const JointValue>(), stamp);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::SetJoints(std::span<const JointValue> positions,
                                     std::span<const JointValue> velocities,
                                     std::span<const JointValue> accelerations, Stamp stamp) {
  const auto what = [] { return std::string("joint state"); };
  // The rules before time, shared with the unstamped set (joints.cc).
  if (auto ok = CheckJointValues(positions, velocities, accelerations); !ok) return ok;
  // The sample of each joint given: its given fields, the others of its newest sample (its
  // state; an acceleration only if the joint has one). A joint named in several maps gives one
  // sample.
  struct Sample {
    JointIndex index;
    const double* q;
    const double* qdot;
    const double* qddot;
  };
  std::vector<Sample> samples;
  samples.reserve(positions.size() + velocities.size() + accelerations.size());
  const auto sample_of = [&](const JointValue& v) -> Sample& {
    const JointIndex index = joints_.HandleOf(*joints_.Find(v.joint)).index;
    for (Sample& x : samples) {
      if (x.index == index) return x;
    }
    return samples.emplace_back(Sample{index, nullptr, nullptr, nullptr});
  };
  for (const JointValue& v : positions) sample_of(v).q = &v.value;
  for (const JointValue& v : velocities) sample_of(v).qdot = &v.value;
  for (const JointValue& v : accelerations) sample_of(v).qddot = &v.value;
  const std::int64_t s = stamp.nanoseconds();
  // A joint never set yet becomes stamped: its (and its mimics') histories are made first, so a
  // refusal below or running out of memory changes nothing.
  std::vector<JointIndex> fresh;  // joints (and mimics) that get histories
  for (const Sample& x : samples) {
    const internal::JointRecord& j = joints_[x.index];
    for (std::size_t k = 0; k <= j.mimics.size(); ++k) {
      const JointIndex idx = k == 0 ? x.index : j.mimics[k - 1];
      const internal::JointRecord& jk = joints_[idx];
      if (!jk.timeless && values_.history.pose_of(jk.child.value()) == nullptr)
        fresh.push_back(idx);
    }
  }
  // The stamp rules, on the joints that are stamped already (and the timeless ones); the first
  // failure in the order of the codes is reported.
  ErrorCode worst = ErrorCode::kOk;
  std::string worst_reason;
  for (const Sample& x : samples) {
    const internal::JointRecord& j = joints_[x.index];
    const double q = x.q ? *x.q : j.q, qdot = x.qdot ? *x.qdot : j.qdot;
    const double* qddot = x.qddot ? x.qddot : (j.has_qddot ? &j.qddot : nullptr);
    for (std::size_t k = 0; k <= j.mimics.size(); ++k) {
      const JointIndex idx = k == 0 ? x.index : j.mimics[k - 1];
      if (std::find(fresh.begin(), fresh.end(), idx) != fresh.end()) continue;
      const internal::JointRecord& jk = joints_[idx];
      const double qk = k == 0 ? q : jk.multiplier * q + jk.offset,
                   qdotk = k == 0 ? qdot : jk.multiplier * qdot,
                   qddotk = qddot ? (k == 0 ? *qddot : jk.multiplier * *qddot) : 0.0;
      const ErrorCode code = CheckJointSample(jk, qk, qdotk, qddot ? &qddotk : nullptr, s);
      if (code == ErrorCode::kOk || (worst != ErrorCode::kOk && code >= worst)) continue;
      worst = code;
      std::string reason = "joint " + std::string(joints_.name(jk)) + ": ";
      if (code == ErrorCode::kStampMismatch && jk.timeless) {
        reason += "it was set without a stamp, so its edges are timeless and take no stamped state";
      } else {
        reason += DescribeSampleRejection(code, false, jk.child.value(), stamp);
      }
      worst_reason = std::move(reason);
    }
  }
  if (worst != ErrorCode::kOk) return Reject(worst, what(), worst_reason);
  std::vector<PoseHistoryLease> new_pose;
  std::vector<TwistHistoryLease> new_twist;
  new_pose.reserve(fresh.size());
  new_twist.reserve(fresh.size());
  for (std::size_t i = 0; i < fresh.size(); ++i) {
    new_pose.push_back(NewPoseHistory());
    new_twist.push_back(NewTwistHistory());
    new_twist.back()->EnsureAccelerations();  // whether or not this call gives one: a later may
  }
  // The acceleration words of the stamped joints given a qddot (and their mimics).
  for (const Sample& x : samples) {
    if (x.qddot == nullptr) continue;
    const internal::JointRecord& j = joints_[x.index];
    for (std::size_t k = 0; k <= j.mimics.size(); ++k) {
      const JointIndex idx = k == 0 ? x.index : j.mimics[k - 1];
      values_.ReserveTwistSampleAccelerations(
          topology_.twist_edge_of(joints_[idx].child).value());  // nothing for a fresh one yet
    }
  }
  // No failure from here on. A fresh joint's first sample is its current state (the newest
  // "sample" of a joint without one), replaced at once by StoreJointSample at the same stamp.
  for (std::size_t i = 0; i < fresh.size(); ++i) {
    const internal::JointRecord& j = joints_[fresh[i]];
    Eigen::Quaterniond q_PC;
    Eigen::Vector3d p_PC;
    j.PoseAt(j.q, q_PC, p_PC);
    TwistNumbers V;
    j.TwistAt(j.qdot, V.v_DHo_H, V.w_DH_H);
    InstallPoseHistory(j.child, std::move(new_pose[i]), B::MakePose(B::FromQuaternion(q_PC), p_PC),
                       stamp);
    InstallTwistHistory(topology_.twist_edge_of(j.child), std::move(new_twist[i]), V, stamp);
  }
  for (const Sample& x : samples) StoreJointSample(x.index, x.q, x.qdot, x.qddot, s);
  return Ok{};
}

#define SEMGRAPH_INSTANTIATE_JOINT_TIME(B)                                                         \
  template ErrorCode SceneGraph<B>::CheckJointSample(const internal::JointRecord&, double, double, \
                                                     const double*, std::int64_t) const noexcept;  \
  template void SceneGraph<B>::StoreJointSample(JointIndex, const double*, const double*,          \
                                                const double*, std::int64_t) noexcept;             \
  template ErrorCode SceneGraph<B>::SetGroupStamped(const JointGroup&, const double*,              \
                                                    const double*, const double*, Stamp,           \
                                                    UpdateError*) noexcept;                        \
  template ErrorCode SceneGraph<B>::RefuseJoints(ErrorCode, const JointGroup&, const double*,      \
                                                 const double*, const double*, UpdateError*)       \
      const noexcept;                                                                              \
  template ErrorCode SceneGraph<B>::SetJointPositions(const JointGroup&, std::span<const double>,  \
                                                      Stamp, UpdateError*) noexcept;               \
  template ErrorCode SceneGraph<B>::SetJointVelocities(const JointGroup&, std::span<const double>, \
                                                       Stamp, UpdateError*) noexcept;              \
  template ErrorCode SceneGraph<B>::SetJointState(const JointGroup&, std::span<const double>,      \
                                                  std::span<const double>, Stamp,                  \
                                                  UpdateError*) noexcept;                          \
  template ErrorCode SceneGraph<B>::SetJointAccelerations(                                         \
      const JointGroup&, std::span<const double>, Stamp, UpdateError*) noexcept;                   \
  template ErrorCode SceneGraph<B>::SetJointState(                                                 \
      const JointGroup&, std::span<const double>, std::span<const double>,                         \
      std::span<const double>, Stamp, UpdateError*) noexcept;                                      \
  template BuildResult SceneGraph<B>::SetJoints(std::span<const JointValue>,                       \
                                                std::span<const JointValue>, Stamp);               \
  template BuildResult SceneGraph<B>::SetJoints(std::span<const JointValue>,                       \
                                                std::span<const JointValue>,                       \
                                                std::span<const JointValue>, Stamp);
SEMGRAPH_INSTANTIATE_JOINT_TIME(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_JOINT_TIME(coord::HomogeneousBackend)

}  // namespace semgraph::core
