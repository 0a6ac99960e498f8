// Repair of rejected relations (the paper's §VI future work), opt-in per add: the plain add runs
// first, and only a rejection by one of the rules below is repaired. Every repair goes through
// the plain add again (same checks, same atomicity), so a repair that does not take changes
// nothing; the one extra mutation, re-rooting, is undone when the add after it fails.
//
//   P1 multiple_pose_parents, the two frames in different trees -> add the inverse pose
//      (b wrt a in [a]); if the inverse is refused by P1 too, re-root b's tree at b first.
//   already determined: pose_cycle, or P1 within one tree -> compare with the derived pose.
//   W1 multiple_twist_parents -> the inverse twist, moved to a frame of the reference body in
//      the same pose tree that has no twist parent.
//   W3 duplicate_twist_path -> compare with the derived twist.
// duplicate_pose_path (P3) is never "already determined": it joins two trees, so the graph
// derives no value to compare with; it keeps its error. Contract: scene_graph.h, docs/repair.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "semgraph/coord/jacobians.h"
#include "semgraph/core/scene_graph.h"
#include "text.h"

namespace semgraph::core {

using base::Unexpected;

namespace {

std::string Number(double x) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.3g", x);
  return buf;
}

// The refused relation with the discrepancy appended to its message.
BuildError WithDiscrepancy(BuildError error, const Discrepancy& d, const char* position_unit,
                           const char* angle_unit, const char* what) {
  error.message += "; it differs from the " + std::string(what) + " the graph derives by " +
                   Number(d.position) + " " + position_unit + " and " + Number(d.angle) + " " +
                   angle_unit;
  error.discrepancy = d;
  return error;
}

}  // namespace

// Reverses the pose edges on v's path to its root; each edge value is inverted exactly as the
// backend inverts (X_PC -> X_CP). The reversed edges' epochs are bumped: their handles and the
// compiled queries that read them report kNoSuchEdge / kQueryInvalidated, never a wrong number.
template <coord::Backend B>
void SceneGraph<B>::RerootAt(FrameIndex v) {
  // One change for readers (the repair's own queries run before it, outside any change).
  const topology::SceneTopology::ChangeScope change(topology_);
  std::vector<FrameIndex> path;  // v = x0, x1, ..., xk = root
  for (FrameIndex x = v; x.is_valid(); x = topology_.pose_parent(x)) path.push_back(x);
  std::vector<typename B::PoseCoords> X_old;  // X_old[i]: the edge x_{i+1} -> x_i
  std::vector<coord::Covariance6> S_old;      // its covariance (docs/uncertainty.md)
  X_old.reserve(path.size());
  S_old.reserve(path.size());
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    X_old.push_back(values_.X_PF[path[i].value()].Load());
    S_old.push_back(values_.PoseCovarianceOf(path[i].value()));
  }
  std::uint32_t highest = 0;  // room for the inverted covariances, before any change
  for (const FrameIndex x : path) highest = std::max(highest, x.value());
  if (std::any_of(S_old.begin(), S_old.end(), [](const auto& S) { return !S.isZero(0.0); })) {
    values_.ReservePoseCovariances(highest + 1);
  }
  topology_.RerootPose(v);
  for (const FrameIndex x : path) values_.X_PF[x.value()].BumpEpoch();
  values_.ClearPoseCovariance(v.value());
  values_.X_PF[v.value()].Store(B::Identity());
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const typename B::PoseCoords X_inv = B::InvertChain(X_old[i]);  // the edge x_i -> x_{i+1}
    if (S_old[i].isZero(0.0)) {
      values_.StorePoseCovariance(path[i + 1].value(), X_inv, nullptr);
    } else {  // the inverse's covariance (coord/jacobians.h)
      coord::Covariance6 S_inv = coord::Covariance6::Zero();
      coord::jacobians::AddPropagated(
          coord::jacobians::Inverse(B::ToMatrix(B::RotationOf(X_old[i])),
                                    B::TranslationOf(X_old[i])),
          S_old[i], S_inv);
      values_.StorePoseCovariance(path[i + 1].value(), X_inv, &S_inv);
    }
    values_.X_PF[path[i + 1].value()].Store(X_inv);
  }
}

template <coord::Backend B>
Expected<RepairReport, BuildError> SceneGraph<B>::AddPose(const PoseSpec& spec,
                                                          const Eigen::Quaterniond& q_rotation,
                                                          const Eigen::Vector3d& p_position,
                                                          const RepairPolicy& repair) {
  auto plain = AddPose(spec, q_rotation, p_position);
  if (plain) return RepairReport{};
  BuildError error = std::move(plain).error();
  if (error.code != ErrorCode::kMultiplePoseParents && error.code != ErrorCode::kPoseCycle)
    return Unexpected{error};
  // Both codes come after every argument check and the conversion, so the numbers are valid,
  // [a] exists, and every frame a conversion needs exists in the edge's trees.
  const topology::SceneTopology& t = topology_;
  const FrameIndex a = FindFrame(spec.orientation), b = FindFrame(spec.ref_orientation);
  const Eigen::Quaterniond q_BA = *coord::ValidateQuaternion(q_rotation);
  const bool determined = a.is_valid() && b.is_valid() && t.SameTree(a, b);

  if (determined) {  // the graph already derives this relation: compare
    if (!repair.check_consistency) return Unexpected{error};
    auto derived = GetPose(spec);
    if (!derived) return Unexpected{error};
    const Eigen::Quaterniond q_derived = B::ToQuaternion(B::RotationOf(derived->value));
    const Discrepancy d{(B::TranslationOf(derived->value) - p_position).norm(),
                        q_derived.angularDistance(q_BA)};
    if (d.position > repair.position_tolerance || d.angle > repair.angle_tolerance) {
      return Unexpected{WithDiscrepancy(std::move(error), d, "m", "rad", "pose")};
    }
    return RepairReport{
        RepairKind::kConsistent,
        text::PoseAdd(spec) + " is already determined by the graph, and agrees with it", 0, d};
  }
  if (error.code != ErrorCode::kMultiplePoseParents || !repair.invert) return Unexpected{error};

  // The edge form X_BA of the given relation, then its inverse X_AB: {b} wrt {a} in [a].
  const auto named = [&](std::string_view x, std::string_view y, FrameIndex frame_y) {
    return x == y ? frame_y : FindFrame(x);
  };
  typename B::PoseCoords X_BA = B::MakePose(B::FromQuaternion(q_BA), p_position);
  if (spec.point != spec.orientation || spec.ref_point != spec.ref_orientation ||
      spec.coordinate_frame != spec.ref_orientation) {
    const PoseSteps<ForestChain> steps =
        PlanChanges(t, named(spec.point, spec.orientation, a), a,
                    named(spec.ref_point, spec.ref_orientation, b), b,
                    named(spec.coordinate_frame, spec.ref_orientation, b));
    X_BA = internal::ToEdgeForm<B>(source(), steps, X_BA);
  }
  const typename B::PoseCoords X_AB = B::InvertChain(X_BA);
  const PoseSpec inverse =
      PoseSpec::Of(spec.ref_orientation, spec.ref_body).RelativeTo(spec.orientation, spec.body);
  const Eigen::Quaterniond q_AB = B::ToQuaternion(B::RotationOf(X_AB));
  const Eigen::Vector3d p_AB = B::TranslationOf(X_AB);
  // Reports are written before the graph changes: a std::bad_alloc after the change would
  // break the all-or-nothing promise of a build operation.
  std::string inverted_text = "added the inverse: " + text::PoseAdd(inverse);
  auto inverted = AddPose(inverse, q_AB, p_AB);
  if (inverted) return RepairReport{RepairKind::kInverted, std::move(inverted_text), 0, {}};
  if (inverted.error().code != ErrorCode::kMultiplePoseParents || !repair.reroot || !b.is_valid()) {
    return Unexpected{error};
  }
  // The inverse's head {b} has a pose parent: re-root b's tree at b, if the inverse edge then
  // passes every other rule (P2, P3 and W4 do not depend on where a tree is rooted).
  const topology::NewPoseEdge ends{a, b, t.body_of(a), t.body_of(b), t.body_of(a) == t.body_of(b)};
  if (topology::CheckP2(t, ends) || topology::CheckP3(t, ends) || topology::CheckW4(t, ends)) {
    return Unexpected{error};
  }
  // A joint's pose edge has a direction (parent -> child: X_origin M(q)); re-rooting through
  // one would reverse it, so a path with a joint is not re-rooted (kinematics.md). Nor one with
  // a stamped edge: its history belongs to the edge into its head frame, and linear
  // interpolation of inverted samples is not the inverse of the interpolation (docs/repair.md).
  for (FrameIndex x = b; x.is_valid() && t.pose_parent(x).is_valid(); x = t.pose_parent(x)) {
    if (joints_.OfChild(x) || values_.history.pose_of(x.value())) return Unexpected{error};
  }
  const FrameIndex old_root = t.forest().Root(b);
  const std::size_t reversed = t.forest().depth(b);
  std::string rerooted_text = "re-rooted the pose tree of " + text::Frame(t, b) + " at it (" +
                              std::to_string(reversed) +
                              " edges reversed), then added the inverse: " + text::PoseAdd(inverse);
  // For an exact undo: the path b -> root and its edge values, saved before the re-root (an
  // undo by a second re-root would invert every value twice, off by rounding).
  std::vector<FrameIndex> path;
  std::vector<typename B::PoseCoords> X_saved;
  std::vector<coord::Covariance6> S_saved;
  path.reserve(reversed + 1);
  X_saved.reserve(reversed + 1);
  S_saved.reserve(reversed + 1);
  for (FrameIndex x = b; x.is_valid(); x = t.pose_parent(x)) {
    path.push_back(x);
    X_saved.push_back(values_.X_PF[x.value()].Load());
    S_saved.push_back(values_.PoseCovarianceOf(x.value()));
  }
  topology_.ReserveLinkPose(a, b);    // the add's link, reserved before anything changes
  const auto undo = [&]() noexcept {  // allocation-free: the forest re-roots in place
    const topology::SceneTopology::ChangeScope change(topology_);
    topology_.RerootPose(old_root);
    for (std::size_t i = 0; i < path.size(); ++i) {
      values_.X_PF[path[i].value()]
          .BumpEpoch();  // handles of the twice-reversed edges stay invalid
      if (S_saved[i].isZero(0.0)) {
        values_.ClearPoseCovariance(path[i].value());
      } else {
        values_.StorePoseCovariance(path[i].value(), X_saved[i], &S_saved[i]);
      }
      values_.X_PF[path[i].value()].Store(X_saved[i]);
    }
  };
  RerootAt(b);
  std::optional<BuildResult> rerooted;
  try {
    rerooted = AddPose(inverse, q_AB, p_AB);
  } catch (...) {  // out of memory in the add (its rule checks allocate): back to the old tree
    undo();
    throw;
  }
  if (!*rerooted) {  // not expected (the rules passed above); leave the graph as it was
    undo();
    return Unexpected{error};
  }
  return RepairReport{RepairKind::kRerooted, std::move(rerooted_text), reversed, {}};
}

template <coord::Backend B>
Expected<RepairReport, BuildError> SceneGraph<B>::AddTwist(const TwistSpec& spec,
                                                           const Eigen::Vector3d& v_linear,
                                                           const Eigen::Vector3d& w_angular,
                                                           const RepairPolicy& repair) {
  auto plain = AddTwist(spec, v_linear, w_angular);
  if (plain) return RepairReport{};
  BuildError error = std::move(plain).error();
  const topology::SceneTopology& t = topology_;
  if (error.code == ErrorCode::kDuplicateTwistPath) {  // already determined: compare
    if (!repair.check_consistency) return Unexpected{error};
    auto derived = GetTwist(spec);
    if (!derived) return Unexpected{error};
    const Discrepancy d{(derived->linear - v_linear).norm(), (derived->angular - w_angular).norm()};
    if (d.position > repair.position_tolerance || d.angle > repair.angle_tolerance) {
      return Unexpected{WithDiscrepancy(std::move(error), d, "m/s", "rad/s", "twist")};
    }
    return RepairReport{
        RepairKind::kConsistent,
        text::TwistAdd(spec) + " is already determined by the graph, and agrees with it", 0, d};
  }
  if (error.code != ErrorCode::kMultipleTwistParents || !repair.invert) return Unexpected{error};
  // W1 comes after the conversion: {e} and [r] exist in one tree. The inverse twist of D wrt C
  // at e, moved to a frame {h} of D in that tree with no twist parent: v_h = v_e + p_HE x w.
  const FrameIndex e = FindFrame(spec.point), r = FindFrame(spec.coordinate_frame);
  const BodyIndex C = t.body_of(e), D = FindBody(spec.ref_body);
  if (!D.is_valid()) return Unexpected{error};
  FrameIndex h;
  t.ForEachFrameOfBody(D, [&](FrameIndex x) {
    if (!h.is_valid() && t.SameTree(x, e) && !t.twist_edge_of(x).is_valid()) h = x;
  });
  if (!h.is_valid()) return Unexpected{error};
  auto p_HE_R = GetPosition(
      PoseSpec::Of(spec.point).RelativeTo(t.frame_name(h)).ExpressedIn(spec.coordinate_frame));
  if (!p_HE_R || !r.is_valid()) return Unexpected{error};
  const Eigen::Vector3d w_CD_R = -w_angular;
  const Eigen::Vector3d v_CDh_R = coord::kernels::ShiftLinear(-v_linear, w_CD_R, p_HE_R->value);
  const TwistSpec inverse = TwistSpec::Of(t.frame_name(h), t.body_name(D))
                                .RelativeTo(t.body_name(C))
                                .ExpressedIn(spec.coordinate_frame);
  std::string inverted_text = "added the inverse: " + text::TwistAdd(inverse);  // before the change
  auto inverted = AddTwist(inverse, v_CDh_R, w_CD_R);
  if (!inverted) return Unexpected{error};
  return RepairReport{RepairKind::kInverted, std::move(inverted_text), 0, {}};
}

#define SEMGRAPH_INSTANTIATE_REPAIR(B)                                                          \
  template void SceneGraph<B>::RerootAt(FrameIndex);                                            \
  template Expected<RepairReport, BuildError> SceneGraph<B>::AddPose(                           \
      const PoseSpec&, const Eigen::Quaterniond&, const Eigen::Vector3d&, const RepairPolicy&); \
  template Expected<RepairReport, BuildError> SceneGraph<B>::AddTwist(                          \
      const TwistSpec&, const Eigen::Vector3d&, const Eigen::Vector3d&, const RepairPolicy&);
SEMGRAPH_INSTANTIATE_REPAIR(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_REPAIR(coord::HomogeneousBackend)

}  // namespace semgraph::core
