// Joints: adds (checked as a pose add plus its twist edge, atomically), removal through the
// joint's pose edge, joint states (by name at build time, by group on the real-time path: the
// edge values are computed here, on the write side) and Jacobians (planned on the twist plan,
// evaluated by the one evaluator). Contract: joints.h, jacobian.h, scene_graph.h.
#include "semgraph/core/joints.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include "semgraph/base/demand.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/semantics/describe.h"
#include "name_rollback.h"
#include "text.h"

namespace semgraph::core {

using internal::NameRollback;

using base::Unexpected;
using text::Reject;

std::string_view ToString(JointType type) noexcept {
  switch (type) {
    case JointType::kRevolute: return "revolute";
    case JointType::kContinuous: return "continuous";
    case JointType::kPrismatic: return "prismatic";
    case JointType::kFixed: return "fixed";
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
  constexpr double kPio2Hi = 1.57079632673412561417e+00;   // the first 33 bits of pi/2
  constexpr double kPio2Lo = 6.07710050650619224932e-11;   // pi/2 - kPio2Hi
  constexpr double kRound = 6755399441055744.0;            // 1.5 * 2^52: adds round to nearest
  const double k = (x * kTwoOverPi + kRound) - kRound;
  const double r = (x - k * kPio2Hi) - k * kPio2Lo;
  const double z = r * r;
  const double sr = r + r * z * (-1.66666666666666324348e-01 +
                                 z * (8.33333333332248946124e-03 +
                                      z * (-1.98412698298579493134e-04 +
                                           z * (2.75573137070700676789e-06 +
                                                z * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10)))));
  const double cr = 1.0 - 0.5 * z +
                    z * z * (4.16666666666666019037e-02 +
                             z * (-1.38888888888741095749e-03 +
                                  z * (2.48015872894767294178e-05 +
                                       z * (-2.75573143513906633035e-07 +
                                            z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11)))));
  switch (static_cast<long long>(k) & 3) {
    case 0: s = sr; c = cr; return;
    case 1: s = cr; c = -sr; return;
    case 2: s = -sr; c = -cr; return;
    default: s = -cr; c = sr; return;
  }
}

void JointRecord::PoseAt(double position, Eigen::Quaterniond& q_PC, Eigen::Vector3d& p_PoCo_P) const noexcept {
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

}  // namespace internal

namespace {

constexpr double kLimitSlack = 1e-9;
constexpr std::uint32_t kNoJoint = 0xFFFFFFFFu;

// A joint set without a stamp (and its mimics, which follow it): its edges are timeless.
void MarkTimeless(internal::JointTable& joints, std::uint32_t index) noexcept {
  internal::JointRecord& j = joints.joints[index];
  j.timeless = true;
  for (std::uint32_t m : j.mimics) joints.joints[m].timeless = true;
}

std::string JointWhat(std::string_view name) {
  return "joint " + (name.empty() ? std::string("\"\"") : std::string(name));
}

std::string Num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

// True when bodies u and v are joined in TG(P1) U TG(P2) (either may be null): a temporary
// union-find over the edges of both. Build time only.
bool ConnectedInUnion(const topology::TwistForest* a, const topology::TwistForest* b, BodyIndex u, BodyIndex v) {
  std::map<BodyIndex, BodyIndex> parent;
  const auto find = [&](BodyIndex x) {
    auto it = parent.find(x);
    if (it == parent.end()) return x;
    while (it->second != x) {
      x = it->second;
      it = parent.find(x);
    }
    return x;
  };
  const auto unite = [&](BodyIndex x, BodyIndex y) {
    parent.try_emplace(x, x);
    parent.try_emplace(y, y);
    x = find(x);
    y = find(y);
    if (x != y) parent[x] = y;
  };
  for (const topology::TwistForest* f : {a, b}) {
    if (f) f->ForEachEdge([&](TwistEdgeIndex, BodyIndex tail, BodyIndex head) { unite(tail, head); });
  }
  return u == v || (parent.count(u) && parent.count(v) && find(u) == find(v));
}

}  // namespace

// ====================================================================== add

template <coord::Backend B>
BuildResult SceneGraph<B>::AddJoint(const JointSpec& spec) {
  semantics::NameTable& names = topology_.mutable_names();
  const auto what = [&] { return JointWhat(spec.name) + " (" + std::string(ToString(spec.type)) + ")"; };
  // 1. invalid_name.
  struct NamedField {
    std::string_view value;
    const char* role;
    bool required;
  };
  const NamedField named[] = {{spec.name, "name", true},          {spec.parent, "parent", true},
                              {spec.parent_body, "parent_body", false}, {spec.child, "child", true},
                              {spec.child_body, "child_body", false},   {spec.mimic, "mimic", false}};
  for (const NamedField& n : named) {
    if (n.value.empty() && !n.required) continue;
    if (auto ok = semantics::ValidateName(n.value); !ok) {
      return Reject(ErrorCode::kInvalidName, what(), std::string(n.role) + ": " + semantics::Describe(ok.error(), n.value));
    }
  }
  // 2. invalid_number, invalid_rotation.
  auto p_ok = coord::ValidateVector(spec.p_origin, coord::ValueRole::kPosition);
  if (!p_ok) return Reject(p_ok.error().code, what(), "origin: " + coord::Describe(p_ok.error(), names));
  Eigen::Quaterniond q_origin;
  if (spec.R_origin) {
    auto R_ok = coord::ValidateRotationMatrix(*spec.R_origin);
    if (!R_ok) return Reject(R_ok.error().code, what(), "origin: " + coord::Describe(R_ok.error(), names));
    q_origin = Eigen::Quaterniond(*R_ok).normalized();
  } else {
    auto q_ok = coord::ValidateQuaternion(spec.q_origin);
    if (!q_ok) return Reject(q_ok.error().code, what(), "origin: " + coord::Describe(q_ok.error(), names));
    q_origin = *q_ok;
  }
  const struct {
    double value;
    const char* role;
  } scalars[] = {{spec.axis.x(), "axis"}, {spec.axis.y(), "axis"},      {spec.axis.z(), "axis"},
                 {spec.lower, "lower"},   {spec.upper, "upper"},        {spec.multiplier, "multiplier"},
                 {spec.offset, "offset"}};
  for (const auto& s : scalars) {
    if (!std::isfinite(s.value)) {
      return Reject(ErrorCode::kInvalidNumber, what(), std::string(s.role) + " is not a finite number");
    }
  }
  // 3. invalid_model: axis, limits, mimic.
  const bool movable = spec.type != JointType::kFixed;
  const double axis_norm = spec.axis.norm();
  if (movable && axis_norm < 1e-12) {
    return Reject(ErrorCode::kInvalidModel, what(), "the axis " + text::Vector(spec.axis) + " has no direction");
  }
  const bool limited = spec.type == JointType::kRevolute || spec.type == JointType::kPrismatic;
  if (limited && !(spec.lower <= spec.upper)) {
    return Reject(ErrorCode::kInvalidModel, what(),
                  "the lower limit " + Num(spec.lower) + " is above the upper limit " + Num(spec.upper));
  }
  std::uint32_t master = kNoJoint;
  if (!spec.mimic.empty()) {
    if (!movable) return Reject(ErrorCode::kInvalidModel, what(), "a fixed joint cannot mimic another joint");
    const internal::JointRecord* m = joints_.Find(spec.mimic);
    if (!m) {
      return Reject(ErrorCode::kInvalidModel, what(),
                    "it mimics joint " + std::string(spec.mimic) + ", which does not exist");
    }
    if (!m->movable()) {
      return Reject(ErrorCode::kInvalidModel, what(), "it mimics joint " + m->name + ", which is fixed");
    }
    if (m->is_mimic()) {
      return Reject(ErrorCode::kInvalidModel, what(),
                    "it mimics joint " + m->name + ", which itself mimics joint " + joints_.joints[m->master].name +
                        " (mimic the master directly)");
    }
    master = joints_.HandleOf(*m).index;
  }
  // 4. duplicate_joint.
  if (joints_.Find(spec.name)) {
    return Reject(ErrorCode::kDuplicateJoint, what(), "a joint named " + std::string(spec.name) + " already exists");
  }
  // 5. Node resolution, as a pose of {child}|C wrt {parent}|P.
  NameRollback rollback(names);
  const topology::SceneTopology& t = topology_;
  const NameId p_id = *names.Intern(spec.parent), c_id = *names.Intern(spec.child);
  const NameId P_given = spec.parent_body.empty() ? NameId() : *names.Intern(spec.parent_body);
  const NameId C_given = spec.child_body.empty() ? NameId() : *names.Intern(spec.child_body);
  const FrameIndex p = t.FrameOfName(p_id), c = t.FrameOfName(c_id);
  NameId P_name = P_given, C_name = C_given;
  const auto resolve = [&](FrameIndex x, std::string_view frame, std::string_view body_text, NameId given,
                           NameId& body_name_id) -> BuildResult {
    if (x.is_valid()) {
      if (given.is_valid() && t.BodyOfName(given) != t.body_of(x)) {
        return Reject(ErrorCode::kFrameBodyMismatch, what(),
                      "frame {" + std::string(frame) + "} is attached to body " +
                          std::string(t.body_name(t.body_of(x))) + ", not " + std::string(body_text));
      }
      body_name_id = t.body_name_id(t.body_of(x));
      return Ok{};
    }
    if (!given.is_valid()) {
      return Reject(ErrorCode::kFrameWithoutBody, what(),
                    "frame {" + std::string(frame) + "} does not exist and no body is given to attach it to");
    }
    return Ok{};
  };
  if (auto ok = resolve(c, spec.child, spec.child_body, C_given, C_name); !ok) return ok;
  if (auto ok = resolve(p, spec.parent, spec.parent_body, P_given, P_name); !ok) return ok;
  // 6. self_edge, twist_same_body.
  if (p_id == c_id) {
    return Reject(ErrorCode::kSelfEdge, what(), "a joint from {" + std::string(spec.parent) + "} to itself");
  }
  if (P_name == C_name) {
    return Reject(ErrorCode::kTwistSameBody, what(),
                  "parent and child are both on body " + std::string(names.name(P_name)) +
                      ": a joint moves one body relative to another");
  }
  // 7. joint_edge: the edge is already a joint's.
  if (c.is_valid() && p.is_valid() && topology::PoseEdgeExists(t, p, c)) {
    if (const internal::JointRecord* other = joints_.OfChild(c)) {
      return Reject(ErrorCode::kJointEdge, what(),
                    "the pose edge " + text::Frame(t, p) + " -> " + text::Frame(t, c) + " belongs to joint " +
                        other->name);
    }
  }
  // 8. P1 -> P2 -> P3 -> W4 for the pose edge.
  const BodyIndex P = t.BodyOfName(P_name), C = t.BodyOfName(C_name);
  const topology::NewPoseEdge ends{p, c, P, C, false};
  if (auto v = topology::CheckNewPoseEdge(t, ends)) {
    return Reject(v->code, what(), text::PoseRule(t, *v, ends, PoseSpec::Of(spec.child, spec.child_body)
                                                                      .RelativeTo(spec.parent, spec.parent_body)));
  }
  // 9. W1, W3 for the twist edge P -> {c}|C in the merged tree.
  if (c.is_valid() && t.twist_edge_of(c).is_valid()) {
    return Reject(ErrorCode::kMultipleTwistParents, what(),
                  text::Frame(t, c) + " already has a twist parent: body " +
                      std::string(t.body_name(t.twist_edge(t.twist_edge_of(c)).tail)));
  }
  if (P.is_valid() && C.is_valid()) {
    const topology::TreeRecord* rec_p = p.is_valid() ? t.RecordOf(p) : nullptr;
    const topology::TreeRecord* rec_c = c.is_valid() ? t.RecordOf(c) : nullptr;
    if (ConnectedInUnion(rec_p ? &rec_p->twists : nullptr, rec_c ? &rec_c->twists : nullptr, P, C)) {
      return Reject(ErrorCode::kDuplicateTwistPath, what(),
                    "the twist of " + std::string(t.body_name(C)) + " relative to " + std::string(t.body_name(P)) +
                        " already follows from the twist edges of the pose trees it joins");
    }
  }

  // 10. Apply.
  internal::JointRecord j;
  j.name = std::string(spec.name);
  j.type = spec.type;
  j.alive = true;
  j.q_origin = q_origin;
  j.p_origin = *p_ok;
  // A unit axis (to rounding) is kept as given, as rotations are (coord/validate.h), so that
  // adding a joint again with the stored axis stores the same axis (scene export).
  const bool unit_axis = std::abs(axis_norm - 1.0) <= coord::kUnitRounding;
  j.axis = !movable ? Eigen::Vector3d::UnitX() : unit_axis ? spec.axis : Eigen::Vector3d(spec.axis / axis_norm);
  j.lower = spec.lower;
  j.upper = spec.upper;
  j.master = master;
  j.multiplier = master == kNoJoint ? 1.0 : spec.multiplier;
  j.offset = master == kNoJoint ? 0.0 : spec.offset;
  if (master != kNoJoint) {
    j.q = j.multiplier * joints_.joints[master].q + j.offset;
    j.qdot = j.multiplier * joints_.joints[master].qdot;
  } else if (limited) {
    j.q = std::clamp(0.0, j.lower, j.upper);
  }
  std::uint32_t index = static_cast<std::uint32_t>(joints_.joints.size());
  for (std::uint32_t i = 0; i < joints_.joints.size(); ++i) {
    if (!joints_.joints[i].alive) {
      index = i;
      break;
    }
  }
  j.generation = index < joints_.joints.size() ? joints_.joints[index].generation : 0;

  // Every allocation before the first change (all or nothing under std::bad_alloc; the names
  // interned above are rolled back by `rollback` until Commit): room for the new nodes, the
  // pose and the twist link in the merged tree, the twist slot, the joint's slot, its mimic
  // entry, and the two map entries, whose nodes are made now in local maps and moved into the
  // tables after the changes (moving a node handle does not allocate; reserve() rules out a
  // rehash).
  const std::size_t new_bodies = (P.is_valid() ? 0 : 1) + (C.is_valid() ? 0 : 1);
  const std::size_t new_frames = (c.is_valid() ? 0 : 1) + (p.is_valid() ? 0 : 1);
  topology_.ReserveNodes(new_bodies, new_frames);
  values_.ReserveFrames(values_.X_PF.size() + new_frames);
  topology_.ReserveLinkJoint(p, c);
  values_.ReserveTwistSlots(t.num_twist_edge_slots() + 1);
  if (index == joints_.joints.size()) joints_.joints.reserve(std::max<std::size_t>(8, 2 * joints_.joints.size()));
  if (master != kNoJoint) joints_.joints[master].mimics.reserve(joints_.joints[master].mimics.size() + 1);
  joints_.by_name.reserve(joints_.by_name.size() + 1);
  joints_.joint_of_child.reserve(joints_.joint_of_child.size() + 1);
  decltype(joints_.by_name) name_node;
  name_node.emplace(j.name, index);
  decltype(joints_.joint_of_child) child_node;
  child_node.emplace(0, index);  // keyed by the child frame once it exists

  // Apply: nothing below allocates.
  rollback.Commit();
  if (index == joints_.joints.size()) joints_.joints.emplace_back();
  const BodyIndex P_body = P.is_valid() ? P : topology_.CreateBody(P_name);
  const BodyIndex C_body = C.is_valid() ? C : topology_.CreateBody(C_name);
  const FrameIndex head = c.is_valid() ? c : CreateFrame(c_id, C_body);
  const FrameIndex tail = p.is_valid() ? p : CreateFrame(p_id, P_body);
  topology_.LinkPoseReserved(tail, head);  // reserved above (ReserveLinkJoint)
  const TwistEdgeIndex edge = topology_.LinkTwist(
      P_body, head,
      semantics::TwistSemantics{semantics::Point(c_id), t.BodySem(C_body), t.BodySem(P_body),
                                semantics::OrientationFrame(c_id)});
  values_.AddTwistSlot(edge);
  j.parent = tail;
  j.child = head;
  j.parent_body = P_body;
  j.child_body = C_body;
  joints_.joints[index] = std::move(j);
  joints_.by_name.insert(name_node.extract(name_node.begin()));
  auto child_entry = child_node.extract(child_node.begin());
  child_entry.key() = head.value();
  joints_.joint_of_child.insert(std::move(child_entry));
  if (master != kNoJoint) joints_.joints[master].mimics.push_back(index);
  ++joints_.num_alive;
  const internal::JointRecord& rec = joints_.joints[index];
  const double q0 = rec.q, qdot0 = rec.qdot;
  ApplyJoint(index, &q0, &qdot0);
  return Ok{};
}

// ====================================================================== removal

template <coord::Backend B>
BuildResult SceneGraph<B>::RemoveJoint(const internal::JointRecord& joint) {
  const topology::SceneTopology& t = topology_;
  for (std::uint32_t m : joint.mimics) {
    if (joints_.joints[m].alive) {
      return Reject(ErrorCode::kJointEdge,
                    "removal of the pose of " + text::Frame(t, joint.child) + " wrt " + text::Frame(t, joint.parent),
                    "it is the pose edge of joint " + joint.name + ", which joint " + joints_.joints[m].name +
                        " mimics; remove the mimic joints first");
    }
  }
  const std::uint32_t index = joints_.HandleOf(joint).index;
  internal::JointRecord& j = joints_.joints[index];
  const TwistEdgeIndex edge = t.twist_edge_of(j.child);
  SEMGRAPH_DEMAND(edge.is_valid());
  // All or nothing under std::bad_alloc: CutPose makes all its allocations before its first
  // change, and UnlinkTwist's are reserved before it; so cut first, then unlink.
  topology_.ReserveUnlinkAfterCut();
  topology_.CutPose(j.child);
  topology_.UnlinkTwist(edge);
  values_.V_DH[edge.value()].BumpEpoch();
  DropTwistHistory(edge);
  values_.X_PF[j.child.value()].BumpEpoch();
  DropPoseHistory(j.child);
  if (j.is_mimic()) {
    auto& mimics = joints_.joints[j.master].mimics;
    mimics.erase(std::remove(mimics.begin(), mimics.end(), index), mimics.end());
  }
  joints_.by_name.erase(j.name);
  joints_.joint_of_child.erase(j.child.value());
  const std::uint32_t generation = j.generation + 1;
  j = internal::JointRecord{};
  j.generation = generation;
  --joints_.num_alive;
  return Ok{};
}

// ====================================================================== state

template <coord::Backend B>
void SceneGraph<B>::ApplyJoint(std::uint32_t index, const double* q, const double* qdot) noexcept {
  internal::JointRecord& j = joints_.joints[index];
  if (q) {
    j.q = *q;
    Eigen::Quaterniond q_PC;
    Eigen::Vector3d p_PC;
    j.PoseAt(j.q, q_PC, p_PC);
    values_.X_PF[j.child.value()].Store(B::MakePose(B::FromQuaternion(q_PC), p_PC));
  }
  if (qdot) {
    j.qdot = *qdot;
    TwistNumbers V;
    j.TwistAt(j.qdot, V.v_DHo_H, V.w_DH_H);
    values_.V_DH[topology_.twist_edge_of(j.child).value()].Store(V);
  }
  for (std::uint32_t m : j.mimics) {
    const internal::JointRecord& mj = joints_.joints[m];
    const double qm = mj.multiplier * j.q + mj.offset, qdotm = mj.multiplier * j.qdot;
    ApplyJoint(m, q ? &qm : nullptr, qdot ? &qdotm : nullptr);  // a mimic has no mimics: depth 1
  }
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetGroup(const JointGroup& group, const double* q, const double* qdot,
                                  UpdateError* why) noexcept {
  // One pass collects every failure; the first in the rules' order is reported, so a rejected
  // set changes nothing (all or nothing) and costs one pass too.
  const std::size_t n = group.joints.size();
  bool bad_number = false, unknown = false, mimic = false, limit = false, stamped = false;
  for (std::size_t i = 0; i < n; ++i) {
    bad_number |= (q && !std::isfinite(q[i])) || (qdot && !std::isfinite(qdot[i]));
    const internal::JointRecord* j = joints_.Get(group.joints[i]);
    if (!j || !j->movable()) {
      unknown = true;
      continue;
    }
    mimic |= j->is_mimic();
    limit |= q && j->limited() && !(q[i] >= j->lower - kLimitSlack && q[i] <= j->upper + kLimitSlack);
    stamped |= values_.history.pose_of(j->child.value()) != nullptr;  // its states need a stamp
  }
  if (bad_number) return RefuseJoints(ErrorCode::kInvalidNumber, group, q, qdot, why);
  if (unknown) return RefuseJoints(ErrorCode::kUnknownJoint, group, q, qdot, why);
  if (mimic) return RefuseJoints(ErrorCode::kMimicJoint, group, q, qdot, why);
  if (limit) return RefuseJoints(ErrorCode::kJointLimit, group, q, qdot, why);
  if (stamped) return RefuseJoints(ErrorCode::kStampMismatch, group, q, qdot, why);
  for (std::size_t i = 0; i < n; ++i) {
    ApplyJoint(group.joints[i].index, q ? q + i : nullptr, qdot ? qdot + i : nullptr);
    MarkTimeless(joints_, group.joints[i].index);
  }
  return internal::Report(why, ErrorCode::kOk);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointPositions(const JointGroup& group, std::span<const double> q,
                                           UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(q.size() == group.size());
  return SetGroup(group, q.data(), nullptr, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointVelocities(const JointGroup& group, std::span<const double> qdot,
                                            UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(qdot.size() == group.size());
  return SetGroup(group, nullptr, qdot.data(), why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetJointState(const JointGroup& group, std::span<const double> q,
                                       std::span<const double> qdot, UpdateError* why) noexcept {
  SEMGRAPH_DEMAND(q.size() == group.size() && qdot.size() == group.size());
  return SetGroup(group, q.data(), qdot.data(), why);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::CheckJointValues(std::span<const JointValue> positions,
                                            std::span<const JointValue> velocities) const {
  const auto what = [] { return std::string("joint state"); };
  // invalid_number -> unknown_joint -> mimic_joint -> joint_limit, over all values given.
  for (const auto* list : {&positions, &velocities}) {
    for (const JointValue& v : *list) {
      if (!std::isfinite(v.value)) {
        return Reject(ErrorCode::kInvalidNumber, what(),
                      std::string(list == &positions ? "position" : "velocity") + " of joint " +
                          std::string(v.joint) + " is not a finite number");
      }
    }
  }
  for (const auto* list : {&positions, &velocities}) {
    for (const JointValue& v : *list) {
      const internal::JointRecord* j = joints_.Find(v.joint);
      if (!j) return Reject(ErrorCode::kUnknownJoint, what(), "there is no joint named " + std::string(v.joint));
      if (!j->movable()) {
        return Reject(ErrorCode::kUnknownJoint, what(), "joint " + j->name + " is fixed: it has no state");
      }
    }
  }
  for (const auto* list : {&positions, &velocities}) {
    for (const JointValue& v : *list) {
      const internal::JointRecord* j = joints_.Find(v.joint);
      if (j->is_mimic()) {
        return Reject(ErrorCode::kMimicJoint, what(),
                      "joint " + j->name + " mimics joint " + joints_.joints[j->master].name +
                          "; set the master instead");
      }
    }
  }
  for (const JointValue& v : positions) {
    const internal::JointRecord* j = joints_.Find(v.joint);
    if (j->limited() && (v.value < j->lower - kLimitSlack || v.value > j->upper + kLimitSlack)) {
      return Reject(ErrorCode::kJointLimit, what(),
                    "position " + Num(v.value) + " of joint " + j->name + " is outside its limits [" + Num(j->lower) +
                        ", " + Num(j->upper) + "]");
    }
  }
  return Ok{};
}

template <coord::Backend B>
BuildResult SceneGraph<B>::SetJoints(std::span<const JointValue> positions, std::span<const JointValue> velocities) {
  const auto what = [] { return std::string("joint state"); };
  if (auto ok = CheckJointValues(positions, velocities); !ok) return ok;
  for (const auto* list : {&positions, &velocities}) {
    for (const JointValue& v : *list) {
      const internal::JointRecord* j = joints_.Find(v.joint);
      if (values_.history.pose_of(j->child.value()) != nullptr) {
        return Reject(ErrorCode::kStampMismatch, what(),
                      "joint " + j->name + ": " +
                          DescribeSampleRejection(ErrorCode::kStampMismatch, false, j->child.value(), std::nullopt));
      }
    }
  }
  for (const JointValue& v : positions) ApplyJoint(joints_.HandleOf(*joints_.Find(v.joint)).index, &v.value, nullptr);
  for (const JointValue& v : velocities) {
    ApplyJoint(joints_.HandleOf(*joints_.Find(v.joint)).index, nullptr, &v.value);
  }
  for (const auto* list : {&positions, &velocities}) {
    for (const JointValue& v : *list) MarkTimeless(joints_, joints_.HandleOf(*joints_.Find(v.joint)).index);
  }
  return Ok{};
}

template <coord::Backend B>
Expected<JointHandle, BuildError> SceneGraph<B>::FindJoint(std::string_view name) const {
  const internal::JointRecord* j = joints_.Find(name);
  if (!j) {
    return Unexpected{
        Reject(ErrorCode::kUnknownJoint, JointWhat(name), "there is no joint named " + std::string(name)).error()};
  }
  return joints_.HandleOf(*j);
}

template <coord::Backend B>
Expected<JointGroup, BuildError> SceneGraph<B>::MakeJointGroup(std::span<const std::string_view> names) const {
  JointGroup g;
  for (std::string_view n : names) {
    const internal::JointRecord* j = joints_.Find(n);
    const std::string what = "joint group";
    if (!j) return Unexpected{Reject(ErrorCode::kUnknownJoint, what, "there is no joint named " + std::string(n)).error()};
    if (!j->movable()) {
      return Unexpected{Reject(ErrorCode::kUnknownJoint, what, "joint " + j->name + " is fixed: it has no state").error()};
    }
    if (j->is_mimic()) {
      return Unexpected{Reject(ErrorCode::kMimicJoint, what,
                               "joint " + j->name + " mimics joint " + joints_.joints[j->master].name)
                            .error()};
    }
    const JointHandle h = joints_.HandleOf(*j);
    if (std::find(g.joints.begin(), g.joints.end(), h) != g.joints.end()) {
      return Unexpected{Reject(ErrorCode::kDuplicateJoint, what, "joint " + j->name + " is named twice").error()};
    }
    g.joints.push_back(h);
  }
  return g;
}

template <coord::Backend B>
JointGroup SceneGraph<B>::AllJoints() const {
  // Creation order: slots are reused, so order by the child frame (frames are never reused).
  std::vector<std::uint32_t> order;
  for (std::uint32_t i = 0; i < joints_.joints.size(); ++i) {
    const internal::JointRecord& j = joints_.joints[i];
    if (j.alive && j.movable() && !j.is_mimic()) order.push_back(i);
  }
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return joints_.joints[a].child.value() < joints_.joints[b].child.value();
  });
  JointGroup g;
  for (std::uint32_t i : order) g.joints.push_back(joints_.HandleOf(joints_.joints[i]));
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
std::string_view SceneGraph<B>::joint_name(JointHandle h) const noexcept {
  const internal::JointRecord* j = joints_.Get(h);
  return j ? std::string_view(j->name) : std::string_view();
}

// ====================================================================== Jacobians

template <coord::Backend B>
Expected<internal::JacobianPlan, QueryError> SceneGraph<B>::PlanJacobian(const TwistSpec& spec) const {
  auto twist = PlanTwist(topology_, spec);
  if (!twist) return Unexpected{twist.error()};
  internal::JacobianPlan plan;
  plan.twist = *twist;
  // The steps in path order from D to C: D's side as walked (D up to the ancestor), then C's
  // side reversed (the ancestor down to C).
  std::vector<TwistStep<ForestChain>> c_side, d_side;
  std::size_t c_count = 0;
  {
    // Count C's side first: ForEachTwistStep walks C's side, then D's side.
    BodyIndex body = plan.twist.body;
    if (plan.twist.tg) {
      for (; body != plan.twist.ancestor; body = plan.twist.tg->parent(body)) ++c_count;
    }
  }
  std::size_t seen = 0;
  ForEachTwistStep(topology_, plan.twist, [&](const TwistStep<ForestChain>& s) {
    (seen++ < c_count ? c_side : d_side).push_back(s);
  });
  std::vector<TwistStep<ForestChain>> path = d_side;
  path.insert(path.end(), c_side.rbegin(), c_side.rend());
  for (const TwistStep<ForestChain>& s : path) {
    const internal::JointRecord* j = joints_.OfChild(topology_.twist_edge(s.edge).head);
    if (!j || !j->movable()) continue;
    const JointHandle column_joint = j->is_mimic() ? joints_.HandleOf(joints_.joints[j->master]) : joints_.HandleOf(*j);
    const double scale = j->is_mimic() ? j->multiplier : 1.0;
    auto it = std::find(plan.columns.begin(), plan.columns.end(), column_joint);
    if (it == plan.columns.end()) it = plan.columns.insert(plan.columns.end(), column_joint);
    internal::JacobianStep<ForestChain> step;
    step.step = s;
    step.step.move_point = false;  // moved with positions in [r] (EvaluateJacobian)
    step.step.eh = {};
    j->TwistAt(scale, step.unit.v_DHo_H, step.unit.w_DH_H);
    step.column = static_cast<std::uint32_t>(it - plan.columns.begin());
    plan.steps.push_back(step);
  }
  if ((plan.change_point = plan.twist.point != plan.twist.frame && !plan.steps.empty())) {
    plan.er = PlanBasic(topology_, plan.twist.point, plan.twist.frame);
  }
  // Chain each step's h -> ancestor composition on the previous one's where it continues it:
  // same ancestor c and reference chain, and the previous h on the way from this h up to c.
  const auto continues = [&](const BasicPath<ForestChain>& prev, const BasicPath<ForestChain>& next) {
    if (prev.up_a.to != next.up_a.to || prev.up_b.from != next.up_b.from || prev.up_b.to != next.up_b.to) return false;
    for (FrameIndex g = next.up_a.from; g.is_valid(); g = topology_.pose_parent(g)) {
      if (g == prev.up_a.from) return true;
      if (g == next.up_a.to) return false;
    }
    return false;
  };
  const internal::JacobianStep<ForestChain>* prev = nullptr;
  for (internal::JacobianStep<ForestChain>& s : plan.steps) {
    if (!s.step.change_frame) {
      prev = nullptr;  // h == r: the running composition is not updated
      continue;
    }
    if (prev && continues(prev->step.hr, s.step.hr)) {
      s.chained = true;
      s.rest = ForestChain{s.step.hr.up_a.from, prev->step.hr.up_a.from};
    }
    prev = &s;
  }
  if (plan.change_point && prev && &plan.steps.back() == prev && continues(prev->step.hr, plan.er)) {
    plan.e_chained = true;
    plan.e_rest = ForestChain{plan.er.up_a.from, prev->step.hr.up_a.from};
  }
  return plan;
}

template <coord::Backend B>
Expected<Jacobian, QueryError> SceneGraph<B>::GetJacobian(const TwistSpec& spec) const {
  auto plan = PlanJacobian(spec);
  if (!plan) return Unexpected{plan.error()};
  Jacobian out;
  out.semantics = plan->twist.semantics;
  out.joints = plan->columns;
  out.J.setZero(6, static_cast<Eigen::Index>(plan->columns.size()));
  internal::EvaluateJacobian<B>(source(), plan->change_point, plan->er, plan->e_chained, plan->e_rest, plan->steps,
                                out.J);
  return out;
}

template <coord::Backend B>
Expected<CompiledJacobian<B>, QueryError> SceneGraph<B>::CompileJacobian(const TwistSpec& spec) const {
  auto plan = PlanJacobian(spec);
  if (!plan) return Unexpected{plan.error()};
  return CompiledJacobian<B>(topology_, values_, *plan);
}

template <coord::Backend B>
CompiledJacobian<B>::CompiledJacobian(const topology::SceneTopology& t, const EdgeValues<B>& values,
                                      const internal::JacobianPlan& plan)
    : CompiledQuery<B>(t, values), semantics_(plan.twist.semantics), joints_(plan.columns) {
  if ((change_point_ = plan.change_point)) er_ = this->Flatten(t, plan.er);
  if ((e_chained_ = plan.e_chained)) e_rest_ = this->Flatten(t, plan.e_rest);
  steps_.reserve(plan.steps.size());
  for (const internal::JacobianStep<ForestChain>& s : plan.steps) {
    internal::JacobianStep<typename CompiledQuery<B>::Chain> flat;
    flat.step.edge = s.step.edge;
    flat.step.epoch = values.V_DH[s.step.edge.value()].epoch();
    flat.step.invert = s.step.invert;
    if ((flat.step.change_frame = s.step.change_frame)) flat.step.hr = this->Flatten(t, s.step.hr);
    flat.unit = s.unit;
    flat.column = s.column;
    if ((flat.chained = s.chained)) flat.rest = this->Flatten(t, s.rest);
    steps_.push_back(flat);
  }
}

template <coord::Backend B>
ErrorCode CompiledJacobian<B>::Evaluate(Eigen::Ref<JacobianMatrix> J) const noexcept {
  SEMGRAPH_DEMAND(static_cast<std::size_t>(J.cols()) == joints_.size());
  return internal::EvaluateJacobian<B>(this->source(), change_point_, er_, e_chained_, e_rest_, steps_, J)
             ? ErrorCode::kOk
             : ErrorCode::kQueryInvalidated;
}

#define SEMGRAPH_INSTANTIATE_JOINTS(B)                                                                          \
  template BuildResult SceneGraph<B>::AddJoint(const JointSpec&);                                               \
  template BuildResult SceneGraph<B>::RemoveJoint(const internal::JointRecord&);                                \
  template void SceneGraph<B>::ApplyJoint(std::uint32_t, const double*, const double*) noexcept;               \
  template ErrorCode SceneGraph<B>::SetGroup(const JointGroup&, const double*, const double*,      \
                                             UpdateError*) noexcept;                               \
  template ErrorCode SceneGraph<B>::SetJointPositions(const JointGroup&, std::span<const double>,  \
                                                      UpdateError*) noexcept;                      \
  template ErrorCode SceneGraph<B>::SetJointVelocities(const JointGroup&, std::span<const double>, \
                                                       UpdateError*) noexcept;                     \
  template ErrorCode SceneGraph<B>::SetJointState(const JointGroup&, std::span<const double>,      \
                                                  std::span<const double>, UpdateError*) noexcept; \
  template BuildResult SceneGraph<B>::SetJoints(std::span<const JointValue>, std::span<const JointValue>);      \
  template BuildResult SceneGraph<B>::CheckJointValues(std::span<const JointValue>, std::span<const JointValue>) const; \
  template Expected<JointHandle, BuildError> SceneGraph<B>::FindJoint(std::string_view) const;                  \
  template Expected<JointGroup, BuildError> SceneGraph<B>::MakeJointGroup(std::span<const std::string_view>) const; \
  template JointGroup SceneGraph<B>::AllJoints() const;                                                         \
  template double SceneGraph<B>::joint_position(JointHandle) const noexcept;                                    \
  template double SceneGraph<B>::joint_velocity(JointHandle) const noexcept;                                    \
  template std::string_view SceneGraph<B>::joint_name(JointHandle) const noexcept;                              \
  template Expected<internal::JacobianPlan, QueryError> SceneGraph<B>::PlanJacobian(const TwistSpec&) const;     \
  template Expected<Jacobian, QueryError> SceneGraph<B>::GetJacobian(const TwistSpec&) const;                   \
  template Expected<CompiledJacobian<B>, QueryError> SceneGraph<B>::CompileJacobian(const TwistSpec&) const;    \
  template class CompiledJacobian<B>;
SEMGRAPH_INSTANTIATE_JOINTS(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_JOINTS(coord::HomogeneousBackend)

}  // namespace semgraph::core
