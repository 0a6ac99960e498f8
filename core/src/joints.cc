// Joints: adds (a pose edge and its twist edge, through the one add pipeline of add_plan.h,
// atomically), removal through the joint's pose edge, joint states (by name at build time, by
// group on the real-time path: the edge values are computed here, on the write side).
// Jacobians: jacobian.cc. Contract: joints.h, scene_graph.h.
#include "semgraph/core/joints.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "add_plan.h"
#include "joint_scan.h"
#include "name_rollback.h"
#include "semgraph/base/demand.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/semantics/describe.h"
#include "text.h"

namespace semgraph::core {

using internal::NameRollback;

using base::Unexpected;
using text::Reject;

std::string_view ToString(JointType type) noexcept {
  switch (type) {
    case JointType::kRevolute:
      return "revolute";
    case JointType::kContinuous:
      return "continuous";
    case JointType::kPrismatic:
      return "prismatic";
    case JointType::kFixed:
      return "fixed";
  }
  return "unknown";
}

namespace internal {

// sin and cos of x, for the joint setters (one call per revolute joint and update). |x| <= 1e5:
// a Cody-Waite reduction by pi/2 (fdlibm's 33-bit split of pi/2; the reduction is exact to
// ~1e-21 there) and fdlibm's minimax kernels on [-pi/4, pi/4] (within ~1 ulp), about a third
// of libm's sincos; beyond 1e5 (a wheel after days of turning), std::sin and std::cos.
void SinCos(double x, double& s, double& c) noexcept {
  if (!(std::abs(x) <= 1e5)) {
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  constexpr double kTwoOverPi = 6.36619772367581382433e-01;
  constexpr double kPio2Hi = 1.57079632673412561417e+00;  // the first 33 bits of pi/2
  constexpr double kPio2Lo = 6.07710050650619224932e-11;  // pi/2 - kPio2Hi
  constexpr double kRound = 6755399441055744.0;           // 1.5 * 2^52: adds round to nearest
  const double k = (x * kTwoOverPi + kRound) - kRound;
  const double r = (x - k * kPio2Hi) - k * kPio2Lo;
  const double z = r * r;
  const double sr =
      r + r * z *
              (-1.66666666666666324348e-01 +
               z * (8.33333333332248946124e-03 +
                    z * (-1.98412698298579493134e-04 +
                         z * (2.75573137070700676789e-06 + z * (-2.50507602534068634195e-08 +
                                                                z * 1.58969099521155010221e-10)))));
  const double cr =
      1.0 - 0.5 * z +
      z * z *
          (4.16666666666666019037e-02 +
           z * (-1.38888888888741095749e-03 +
                z * (2.48015872894767294178e-05 +
                     z * (-2.75573143513906633035e-07 +
                          z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11)))));
  switch (static_cast<long long>(k) & 3) {
    case 0:
      s = sr;
      c = cr;
      return;
    case 1:
      s = cr;
      c = -sr;
      return;
    case 2:
      s = -sr;
      c = -cr;
      return;
    default:
      s = -cr;
      c = sr;
      return;
  }
}

void JointRecord::PoseAt(double position, Eigen::Quaterniond& q_PC,
                         Eigen::Vector3d& p_PoCo_P) const noexcept {
  switch (type) {
    case JointType::kRevolute:
    case JointType::kContinuous: {
      double s, c;
      SinCos(0.5 * position, s, c);
      q_PC = q_origin * Eigen::Quaterniond(c, s * axis.x(), s * axis.y(), s * axis.z());
      p_PoCo_P = p_origin;
      return;
    }
    case JointType::kPrismatic:
      q_PC = q_origin;
      p_PoCo_P = p_origin + q_origin * (position * axis);
      return;
    case JointType::kFixed:
      q_PC = q_origin;
      p_PoCo_P = p_origin;
      return;
  }
}

void JointRecord::TwistAt(double velocity, Eigen::Vector3d& v, Eigen::Vector3d& w) const noexcept {
  v.setZero();
  w.setZero();
  if (type == JointType::kPrismatic) {
    v = velocity * axis;
  } else if (type != JointType::kFixed) {
    w = velocity * axis;
  }
}

void JointRecord::AccelerationAt(double acceleration, Eigen::Vector3d& a,
                                 Eigen::Vector3d& alpha) const noexcept {
  TwistAt(acceleration, a, alpha);  // the same form: axis times the derivative
}

}  // namespace internal

namespace {

using internal::kLimitSlack;

// A joint set without a stamp (and its mimics, which follow it): its edges are timeless.
void MarkTimeless(internal::JointTable& joints, JointIndex index) noexcept {
  internal::JointRecord& j = joints[index];
  j.timeless = true;
  for (JointIndex m : j.mimics) joints[m].timeless = true;
}

std::string JointWhat(std::string_view name) {
  return "joint " + (name.empty() ? std::string("\"\"") : std::string(name));
}

std::string Num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

// invalid_name, in the order of the spec's fields.
template <class What>
BuildResult CheckJointNames(const JointSpec& spec, const What& what) {
  const struct {
    std::string_view value;
    const char* role;
    bool required;
  } checked[] = {{spec.name, "name", true},
                 {spec.parent, "parent", true},
                 {spec.parent_body, "parent_body", false},
                 {spec.child, "child", true},
                 {spec.child_body, "child_body", false},
                 {spec.mimic, "mimic", false}};
  for (const auto& n : checked) {
    if (n.value.empty() && !n.required) continue;
    if (auto ok = semantics::ValidateName(n.value); !ok) {
      return Reject(ErrorCode::kInvalidName, what(),
                    std::string(n.role) + ": " + semantics::Describe(ok.error(), n.value));
    }
  }
  return Ok{};
}

// The joint's record from its spec, checked: invalid_number / invalid_rotation -> invalid_model
// (axis, limits, mimic) -> duplicate_joint. Its nodes and edges are set when it is applied.
template <class What>
BuildResult MakeJointRecord(const internal::JointTable& joints, const semantics::NameTable& names,
                            const JointSpec& spec, const What& what, internal::JointRecord& j) {
  auto p_ok = coord::ValidateVector(spec.p_origin, coord::ValueRole::kPosition);
  if (!p_ok)
    return Reject(p_ok.error().code, what(), "origin: " + coord::Describe(p_ok.error(), names));
  if (spec.R_origin) {
    auto R_ok = coord::ValidateRotationMatrix(*spec.R_origin);
    if (!R_ok)
      return Reject(R_ok.error().code, what(), "origin: " + coord::Describe(R_ok.error(), names));
    j.q_origin = Eigen::Quaterniond(*R_ok).normalized();
  } else {
    auto q_ok = coord::ValidateQuaternion(spec.q_origin);
    if (!q_ok)
      return Reject(q_ok.error().code, what(), "origin: " + coord::Describe(q_ok.error(), names));
    j.q_origin = *q_ok;
  }
  const struct {
    double value;
    const char* role;
  } scalars[] = {{spec.axis.x(), "axis"}, {spec.axis.y(), "axis"}, {spec.axis.z(), "axis"},
                 {spec.lower, "lower"},   {spec.upper, "upper"},   {spec.multiplier, "multiplier"},
                 {spec.offset, "offset"}};
  for (const auto& s : scalars) {
    if (!std::isfinite(s.value)) {
      return Reject(ErrorCode::kInvalidNumber, what(),
                    std::string(s.role) + " is not a finite number");
    }
  }
  // invalid_model: axis, limits, mimic.
  j.type = spec.type;
  const double axis_norm = spec.axis.norm();
  if (j.movable() && axis_norm < 1e-12) {
    return Reject(ErrorCode::kInvalidModel, what(),
                  "the axis " + text::Vector(spec.axis) + " has no direction");
  }
  if (j.limited() && !(spec.lower <= spec.upper)) {
    return Reject(
        ErrorCode::kInvalidModel, what(),
        "the lower limit " + Num(spec.lower) + " is above the upper limit " + Num(spec.upper));
  }
  if (!spec.mimic.empty()) {
    if (!j.movable())
      return Reject(ErrorCode::kInvalidModel, what(), "a fixed joint cannot mimic another joint");
    const internal::JointRecord* m = joints.Find(spec.mimic);
    if (!m) {
      return Reject(ErrorCode::kInvalidModel, what(),
                    "it mimics joint " + std::string(spec.mimic) + ", which does not exist");
    }
    const std::string m_name(joints.name(*m));
    if (!m->movable())
      return Reject(ErrorCode::kInvalidModel, what(),
                    "it mimics joint " + m_name + ", which is fixed");
    if (m->is_mimic()) {
      return Reject(ErrorCode::kInvalidModel, what(),
                    "it mimics joint " + m_name + ", which itself mimics joint " +
                        std::string(joints.name(joints[m->master])) +
                        " (mimic the master directly)");
    }
    j.master = joints.IndexOf(*m);
  }
  if (joints.Find(spec.name)) {
    return Reject(ErrorCode::kDuplicateJoint, what(),
                  "a joint named " + std::string(spec.name) + " already exists");
  }
  j.p_origin = *p_ok;
  // A unit axis (to rounding) is kept as given, as rotations are (coord/validate.h), so that
  // adding a joint again with the stored axis stores the same axis (scene export).
  const bool unit_axis = std::abs(axis_norm - 1.0) <= coord::kUnitRounding;
  j.axis = !j.movable() ? Eigen::Vector3d::UnitX()
           : unit_axis  ? spec.axis
                        : Eigen::Vector3d(spec.axis / axis_norm);
  j.lower = spec.lower;
  j.upper = spec.upper;
  j.multiplier = j.is_mimic() ? spec.multiplier : 1.0;
  j.offset = j.is_mimic() ? spec.offset : 0.0;
  if (j.is_mimic()) {
    j.q = j.multiplier * joints[j.master].q + j.offset;
    j.qdot = j.multiplier * joints[j.master].qdot;
    j.qddot = j.multiplier * joints[j.master].qddot;
    j.has_qddot = joints[j.master].has_qddot;
  } else if (j.limited()) {
    j.q = std::clamp(0.0, j.lower, j.upper);
  }
  return Ok{};
}

}  // namespace

// ====================================================================== add

template <coord::Backend B>
BuildResult SceneGraph<B>::AddJoint(const JointSpec& spec) {
  const topology::SceneTopology::ChangeScope change(topology_);  // readers validate
  semantics::NameTable& names = topology_.mutable_names();
  const auto what = [&] {
    return JointWhat(spec.name) + " (" + std::string(ToString(spec.type)) + ")";
  };
  // 1. invalid_name, in field order; the frames' and bodies' names are interned below in the
  // order parent, child, parent_body, child_body, as they always were.
  if (auto ok = CheckJointNames(spec, what); !ok) return ok;
  const internal::NamedField named[] = {
      {spec.parent}, {spec.child}, {spec.parent_body, false}, {spec.child_body, false}};
  internal::AddNames<4> ids;
  semantics::NameError unused;
  (void)ids.LookUp(names, named, unused);  // every name is valid (above)
  // 2-4. invalid_number, invalid_rotation -> invalid_model -> duplicate_joint.
  internal::JointRecord j;
  if (auto ok = MakeJointRecord(joints_, names, spec, what, j); !ok) return ok;

  // 5. Node resolution, as a pose of {child}|C wrt {parent}|P.
  NameRollback rollback(names);
  ids.Intern(names, named);
  const NameId p_id = ids.id[0], c_id = ids.id[1];
  const topology::SceneTopology& t = topology_;
  internal::AddPlan plan;
  plan.pose_edge = plan.twist_edge = plan.tail_body_first = true;
  if (auto p = internal::ResolveEnd(t, c_id, ids.id[3], plan.head);
      p != internal::EndProblem::kNone) {
    return text::RejectEnd(t, p, plan.head, what(), spec.child, spec.child_body);
  }
  if (auto p = internal::ResolveEnd(t, p_id, ids.id[2], plan.tail);
      p != internal::EndProblem::kNone) {
    return text::RejectEnd(t, p, plan.tail, what(), spec.parent, spec.parent_body);
  }
  const FrameIndex p = plan.tail.frame, c = plan.head.frame;
  // 6. self_edge, twist_same_body.
  if (p_id == c_id) {
    return Reject(ErrorCode::kSelfEdge, what(),
                  "a joint from {" + std::string(spec.parent) + "} to itself");
  }
  if (plan.tail.body_name == plan.head.body_name) {
    return Reject(ErrorCode::kTwistSameBody, what(),
                  "parent and child are both on body " +
                      std::string(names.name(plan.tail.body_name)) +
                      ": a joint moves one body relative to another");
  }
  // 7. joint_edge: the edge is already a joint's.
  if (topology::PoseEdgeExists(t, p, c)) {
    if (const internal::JointRecord* other = joints_.OfChild(c)) {
      return Reject(ErrorCode::kJointEdge, what(),
                    "the pose edge " + text::Frame(t, p) + " -> " + text::Frame(t, c) +
                        " belongs to joint " + std::string(joints_.name(*other)));
    }
  }
  // 8. P1 -> P2 -> P3 -> W4 for the pose edge, then W1 -> W3 for the twist edge P -> {c}|C in
  // the merged tree.
  if (auto v = topology::CheckNewJointEdges(t, plan.pose_ends())) {
    const PoseSpec as_pose =
        PoseSpec::Of(spec.child, spec.child_body).RelativeTo(spec.parent, spec.parent_body);
    return Reject(v->code, what(), text::JointRule(t, *v, plan.pose_ends(), as_pose));
  }

  // 9. Apply. Every allocation before the first change (all or nothing under std::bad_alloc;
  // the names interned here are rolled back until Commit): the nodes and links (ReserveAdd),
  // the joint's slot, its name, its mimic entry, and its child map entry, whose node is made
  // now in a local map and moved into the table after the changes (moving a node handle does
  // not allocate; reserve() rules out a rehash).
  JointIndex index(static_cast<std::uint32_t>(joints_.joints.size()));
  for (const internal::JointRecord& slot : joints_.joints) {
    if (!slot.alive) {
      index = joints_.IndexOf(slot);
      break;
    }
  }
  const bool new_slot = index.value() == joints_.joints.size();
  j.generation = new_slot ? 0 : joints_[index].generation;
  ReserveAdd(plan);
  if (new_slot) joints_.joints.reserve(std::max<std::size_t>(8, 2 * joints_.joints.size()));
  if (j.is_mimic()) joints_[j.master].mimics.reserve(joints_[j.master].mimics.size() + 1);
  NameRollback joint_rollback(joints_.names);
  j.name = *joints_.names.Intern(spec.name);
  joints_.of_name.reserve(joints_.names.size());
  joints_.joint_of_child.reserve(joints_.joint_of_child.size() + 1);
  decltype(joints_.joint_of_child) child_node;
  child_node.emplace(0, index);  // keyed by the child frame once it exists

  // Apply: nothing below allocates.
  rollback.Commit();
  joint_rollback.Commit();
  if (new_slot) joints_.joints.emplace_back();
  const internal::AddedEdges made = CommitAdd(plan);
  j.parent = made.tail;
  j.child = made.head;
  j.parent_body = made.tail_body;
  j.child_body = made.head_body;
  j.alive = true;
  if (joints_.of_name.size() < joints_.names.size())
    joints_.of_name.resize(joints_.names.size());  // reserved
  joints_.of_name[j.name.value()] = index;
  joints_[index] = std::move(j);
  auto child_entry = child_node.extract(child_node.begin());
  child_entry.key() = made.head.value();
  joints_.joint_of_child.insert(std::move(child_entry));
  const internal::JointRecord& rec = joints_[index];
  if (rec.is_mimic()) joints_[rec.master].mimics.push_back(index);
  ++joints_.num_alive;
  const double q0 = rec.q, qdot0 = rec.qdot, qddot0 = rec.qddot;
  ApplyJoint(index, &q0, &qdot0, rec.has_qddot ? &qddot0 : nullptr);
  return Ok{};
}

// ====================================================================== removal

template <coord::Backend B>
BuildResult SceneGraph<B>::RemoveJoint(const internal::JointRecord& joint) {
  const topology::SceneTopology::ChangeScope change(topology_);  // readers validate
  const topology::SceneTopology& t = topology_;
  for (JointIndex m : joint.mimics) {
    if (joints_[m].alive) {
      return Reject(ErrorCode::kJointEdge,
                    "removal of the pose of " + text::Frame(t, joint.child) + " wrt " +
                        text::Frame(t, joint.parent),
                    "it is the pose edge of joint " + std::string(joints_.name(joint)) +
                        ", which joint " + std::string(joints_.name(joints_[m])) +
                        " mimics; remove the mimic joints first");
    }
  }
  const JointIndex index = joints_.IndexOf(joint);
  internal::JointRecord& j = joints_[index];
  const TwistEdgeIndex edge = t.twist_edge_of(j.child);
  SEMGRAPH_DEMAND(edge.is_valid());
  // All or nothing under std::bad_alloc: CutPose makes all its allocations before its first
  // change, and UnlinkTwist's are reserved before it; so cut first, then unlink.
  topology_.ReserveUnlinkAfterCut();
  RemovePoseEdge(j.child);
  RemoveTwistEdge(edge);
  if (j.is_mimic()) {
    auto& mimics = joints_[j.master].mimics;
    mimics.erase(std::remove(mimics.begin(), mimics.end(), index), mimics.end());
  }
  joints_.of_name[j.name.value()] = JointIndex();
  joints_.joint_of_child.erase(j.child.value());
  const std::uint32_t generation = j.generation + 1;
  j = internal::JointRecord{};
  j.generation = generation;
  --joints_.num_alive;
  return Ok{};
}

// ====================================================================== state

template <coord::Backend B>
void SceneGraph<B>::ApplyJoint(JointIndex index, const double* q, const double* qdot,
                               const double* qddot) noexcept {
  internal::JointRecord& j = joints_[index];
  if (q) {
    j.q = *q;
    Eigen::Quaterniond q_PC;
    Eigen::Vector3d p_PC;
    j.PoseAt(j.q, q_PC, p_PC);
    values_.X_PF[j.child.value()].Store(B::MakePose(B::FromQuaternion(q_PC), p_PC));
  }
  if (qdot) j.qdot = *qdot;
  if (qddot) {
    j.qddot = *qddot;
    j.has_qddot = true;
  }
  if (qdot || qddot) {
    // The acceleration record first, with the twist it goes with (edge_values.h): a new qdot
    // keeps the joint's qddot, whose edge form does not depend on qdot.
    const std::uint32_t slot = topology_.twist_edge_of(j.child).value();
    TwistNumbers V;
    j.TwistAt(j.qdot, V.v_DHo_H, V.w_DH_H);
    if (j.has_qddot) {
      AccelerationNumbers A;
      j.AccelerationAt(j.qddot, A.a_DHo_H, A.alpha_DH_H);
      values_.StoreAcceleration(slot, V, &A);
    }
    if (qdot) values_.V_DH[slot].Store(V);
  }
  for (JointIndex m : j.mimics) {
    const internal::JointRecord& mj = joints_[m];
    const double qm = mj.multiplier * j.q + mj.offset, qdotm = mj.multiplier * j.qdot,
                 qddotm = mj.multiplier * j.qddot;
    ApplyJoint(m, q ? &qm : nullptr, qdot ? &qdotm : nullptr,
               qddot ? &qddotm : nullptr);  // a mimic has no mimics: depth 1
  }
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetGroup(const JointGroup& group, const double* q, const double* qdot,
                                  const double* qddot, UpdateError* why) noexcept {
  // One pass collects every failure; the first in the rules' order is reported, so a rejected
  // set changes nothing (all or nothing) and costs one pass too.
  const std::size_t n = group.joints.size();
  bool stamped = false;
  const ErrorCode code = internal::ScanJointGroup(
      joints_, group, q, qdot, qddot, [&](std::size_t, const internal::JointRecord& j) {
        stamped |= values_.history.pose_of(j.child.value()) != nullptr;  // needs a stamp
      });
  if (code != ErrorCode::kOk) return RefuseJoints(code, group, q, qdot, qddot, why);
  if (stamped) return RefuseJoints(ErrorCode::kStampMismatch, group, q, qdot, qddot, why);
  for (std::size_t i = 0; i < n; ++i) {
    ApplyJoint(group.joints[i].index, q ? q + i : nullptr, qdot ? qdot + i : nullptr,
               qddot ? qddot + i : nullptr);
    MarkTimeless(joints_, group.joints[i].index);
  }
  return internal::Report(why, ErrorCode::kOk);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointPositions(const JointGroup& group, std::span<const double> q,
                                           UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(q.size() == group.size());
  return SetGroup(group, q.data(), nullptr, nullptr, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointVelocities(const JointGroup& group, std::span<const double> qdot,
                                            UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(qdot.size() == group.size());
  return SetGroup(group, nullptr, qdot.data(), nullptr, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointState(const JointGroup& group, std::span<const double> q,
                                       std::span<const double> qdot, UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(q.size() == group.size() && qdot.size() == group.size());
  return SetGroup(group, q.data(), qdot.data(), nullptr, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointAccelerations(const JointGroup& group,
                                               std::span<const double> qddot,
                                               UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(qddot.size() == group.size());
  return SetGroup(group, nullptr, nullptr, qddot.data(), why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointState(const JointGroup& group, std::span<const double> q,
                                       std::span<const double> qdot, std::span<const double> qddot,
                                       UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(q.size() == group.size() && qdot.size() == group.size() &&
                  qddot.size() == group.size());
  return SetGroup(group, q.data(), qdot.data(), qddot.data(), why);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::CheckJointValues(std::span<const JointValue> positions,
                                            std::span<const JointValue> velocities,
                                            std::span<const JointValue> accelerations) const {
  const auto what = [] { return std::string("joint state"); };
  const std::span<const JointValue>* lists[] = {&positions, &velocities, &accelerations};
  const char* fields[] = {"position", "velocity", "acceleration"};
  // invalid_number -> unknown_joint -> mimic_joint -> joint_limit, over all values given.
  for (int k = 0; k < 3; ++k) {
    for (const JointValue& v : *lists[k]) {
      if (!std::isfinite(v.value)) {
        return Reject(ErrorCode::kInvalidNumber, what(),
                      std::string(fields[k]) + " of joint " + std::string(v.joint) +
                          " is not a finite number");
      }
    }
  }
  for (const auto* list : lists) {
    for (const JointValue& v : *list) {
      const internal::JointRecord* j = joints_.Find(v.joint);
      if (!j)
        return Reject(ErrorCode::kUnknownJoint, what(),
                      "there is no joint named " + std::string(v.joint));
      if (!j->movable()) {
        return Reject(ErrorCode::kUnknownJoint, what(),
                      "joint " + std::string(joints_.name(*j)) + " is fixed: it has no state");
      }
    }
  }
  for (const auto* list : lists) {
    for (const JointValue& v : *list) {
      const internal::JointRecord* j = joints_.Find(v.joint);
      if (j->is_mimic()) {
        return Reject(ErrorCode::kMimicJoint, what(),
                      "joint " + std::string(joints_.name(*j)) + " mimics joint " +
                          std::string(joints_.name(joints_[j->master])) +
                          "; set the master instead");
      }
    }
  }
  for (const JointValue& v : positions) {
    const internal::JointRecord* j = joints_.Find(v.joint);
    if (j->limited() && (v.value < j->lower - kLimitSlack || v.value > j->upper + kLimitSlack)) {
      return Reject(ErrorCode::kJointLimit, what(),
                    "position " + Num(v.value) + " of joint " + std::string(joints_.name(*j)) +
                        " is outside its limits [" + Num(j->lower) + ", " + Num(j->upper) + "]");
    }
  }
  return Ok{};
}

template <coord::Backend B>
BuildResult SceneGraph<B>::SetJoints(std::span<const JointValue> positions,
                                     std::span<const JointValue> velocities) {
  return SetJoints(positions, velocities, std::span<const JointValue>());
}

template <coord::Backend B>
BuildResult SceneGraph<B>::SetJoints(std::span<const JointValue> positions,
                                     std::span<const JointValue> velocities,
                                     std::span<const JointValue> accelerations) {
  const auto what = [] { return std::string("joint state"); };
  if (auto ok = CheckJointValues(positions, velocities, accelerations); !ok) return ok;
  const std::span<const JointValue>* lists[] = {&positions, &velocities, &accelerations};
  for (const auto* list : lists) {
    for (const JointValue& v : *list) {
      const internal::JointRecord* j = joints_.Find(v.joint);
      if (values_.history.pose_of(j->child.value()) != nullptr) {
        return Reject(ErrorCode::kStampMismatch, what(),
                      "joint " + std::string(joints_.name(*j)) + ": " +
                          DescribeSampleRejection(ErrorCode::kStampMismatch, false,
                                                  j->child.value(), std::nullopt));
      }
    }
  }
  const auto index = [&](const JointValue& v) {
    return joints_.HandleOf(*joints_.Find(v.joint)).index;
  };
  for (const JointValue& v : positions) ApplyJoint(index(v), &v.value, nullptr, nullptr);
  for (const JointValue& v : velocities) ApplyJoint(index(v), nullptr, &v.value, nullptr);
  for (const JointValue& v : accelerations) ApplyJoint(index(v), nullptr, nullptr, &v.value);
  for (const auto* list : lists) {
    for (const JointValue& v : *list) MarkTimeless(joints_, index(v));
  }
  return Ok{};
}

template <coord::Backend B>
Expected<JointHandle, BuildError> SceneGraph<B>::FindJoint(std::string_view name) const {
  const internal::JointRecord* j = joints_.Find(name);
  if (!j) {
    return Unexpected{Reject(ErrorCode::kUnknownJoint, JointWhat(name),
                             "there is no joint named " + std::string(name))
                          .error()};
  }
  return joints_.HandleOf(*j);
}

template <coord::Backend B>
Expected<JointGroup, BuildError> SceneGraph<B>::MakeJointGroup(
    std::span<const std::string_view> names) const {
  JointGroup g;
  for (std::string_view n : names) {
    const internal::JointRecord* j = joints_.Find(n);
    const std::string what = "joint group";
    if (!j)
      return Unexpected{
          Reject(ErrorCode::kUnknownJoint, what, "there is no joint named " + std::string(n))
              .error()};
    if (!j->movable()) {
      return Unexpected{
          Reject(ErrorCode::kUnknownJoint, what,
                 "joint " + std::string(joints_.name(*j)) + " is fixed: it has no state")
              .error()};
    }
    if (j->is_mimic()) {
      return Unexpected{Reject(ErrorCode::kMimicJoint, what,
                               "joint " + std::string(joints_.name(*j)) + " mimics joint " +
                                   std::string(joints_.name(joints_[j->master])))
                            .error()};
    }
    const JointHandle h = joints_.HandleOf(*j);
    if (std::find(g.joints.begin(), g.joints.end(), h) != g.joints.end()) {
      return Unexpected{Reject(ErrorCode::kDuplicateJoint, what,
                               "joint " + std::string(joints_.name(*j)) + " is named twice")
                            .error()};
    }
    g.joints.push_back(h);
  }
  return g;
}

template <coord::Backend B>
JointGroup SceneGraph<B>::AllJoints() const {
  // Creation order: slots are reused, so order by the child frame (frames are never reused).
  std::vector<JointIndex> order;
  for (const internal::JointRecord& j : joints_.joints) {
    if (j.alive && j.movable() && !j.is_mimic()) order.push_back(joints_.IndexOf(j));
  }
  std::sort(order.begin(), order.end(), [&](JointIndex a, JointIndex b) {
    return joints_[a].child.value() < joints_[b].child.value();
  });
  JointGroup g;
  for (JointIndex i : order) g.joints.push_back(joints_.HandleOf(joints_[i]));
  return g;
}

template <coord::Backend B>
double SceneGraph<B>::joint_position(JointHandle h) const noexcept {
  const internal::JointRecord* j = joints_.Get(h);
  return j ? j->q : std::numeric_limits<double>::quiet_NaN();
}
template <coord::Backend B>
double SceneGraph<B>::joint_velocity(JointHandle h) const noexcept {
  const internal::JointRecord* j = joints_.Get(h);
  return j ? j->qdot : std::numeric_limits<double>::quiet_NaN();
}
template <coord::Backend B>
double SceneGraph<B>::joint_acceleration(JointHandle h) const noexcept {
  const internal::JointRecord* j = joints_.Get(h);
  return j && j->has_qddot ? j->qddot : std::numeric_limits<double>::quiet_NaN();
}
template <coord::Backend B>
std::string_view SceneGraph<B>::joint_name(JointHandle h) const noexcept {
  const internal::JointRecord* j = joints_.Get(h);
  return j ? joints_.name(*j) : std::string_view();
}

#define SEMGRAPH_INSTANTIATE_JOINTS(B)                                                             \
  template BuildResult SceneGraph<B>::AddJoint(const JointSpec&);                                  \
  template BuildResult SceneGraph<B>::RemoveJoint(const internal::JointRecord&);                   \
  template void SceneGraph<B>::ApplyJoint(JointIndex, const double*, const double*,                \
                                          const double*) noexcept;                                 \
  template ErrorCode SceneGraph<B>::SetGroup(const JointGroup&, const double*, const double*,      \
                                             const double*, UpdateError*) noexcept;                \
  template ErrorCode SceneGraph<B>::SetJointPositions(const JointGroup&, std::span<const double>,  \
                                                      UpdateError*) noexcept;                      \
  template ErrorCode SceneGraph<B>::SetJointVelocities(const JointGroup&, std::span<const double>, \
                                                       UpdateError*) noexcept;                     \
  template ErrorCode SceneGraph<B>::SetJointAccelerations(                                         \
      const JointGroup&, std::span<const double>, UpdateError*) noexcept;                          \
  template ErrorCode SceneGraph<B>::SetJointState(const JointGroup&, std::span<const double>,      \
                                                  std::span<const double>, UpdateError*) noexcept; \
  template ErrorCode SceneGraph<B>::SetJointState(const JointGroup&, std::span<const double>,      \
                                                  std::span<const double>,                         \
                                                  std::span<const double>, UpdateError*) noexcept; \
  template BuildResult SceneGraph<B>::SetJoints(std::span<const JointValue>,                       \
                                                std::span<const JointValue>);                      \
  template BuildResult SceneGraph<B>::SetJoints(                                                   \
      std::span<const JointValue>, std::span<const JointValue>, std::span<const JointValue>);      \
  template BuildResult SceneGraph<B>::CheckJointValues(                                            \
      std::span<const JointValue>, std::span<const JointValue>, std::span<const JointValue>)       \
      const;                                                                                       \
  template Expected<JointHandle, BuildError> SceneGraph<B>::FindJoint(std::string_view) const;     \
  template Expected<JointGroup, BuildError> SceneGraph<B>::MakeJointGroup(                         \
      std::span<const std::string_view>) const;                                                    \
  template JointGroup SceneGraph<B>::AllJoints() const;                                            \
  template double SceneGraph<B>::joint_position(JointHandle) const noexcept;                       \
  template double SceneGraph<B>::joint_velocity(JointHandle) const noexcept;                       \
  template double SceneGraph<B>::joint_acceleration(JointHandle) const noexcept;                   \
  template std::string_view SceneGraph<B>::joint_name(JointHandle) const noexcept;

SEMGRAPH_INSTANTIATE_JOINTS(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_JOINTS(coord::HomogeneousBackend)

}  // namespace semgraph::core
