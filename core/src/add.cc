// Adds and removals: validate -> resolve nodes -> edge form (the plan run backwards, evaluate.h
// ToEdgeForm) -> rules (topology/rules.h, in the order of docs/rules.md) -> apply, through the
// one add pipeline of add_plan.h (joints.cc's AddJoint runs it too). Every early return leaves
// the graph as it was: names interned by the operation are rolled back, and nothing else
// changes before the last check passed. Removals: the one edge finder (edge_lookup.h), then
// the removal by index.
#include <algorithm>
#include <cmath>

#include "add_plan.h"
#include "covariance_input.h"
#include "edge_lookup.h"
#include "name_rollback.h"
#include "semgraph/core/propagate.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/semantics/describe.h"
#include "text.h"

namespace semgraph::core {

using internal::NameRollback;

using base::Unexpected;
using semantics::Field;
using semantics::FieldName;
using text::Reject;

namespace {

// A converted rotation is a product of stored ones: normalized as an input would be, so that
// every stored rotation is one that validation keeps as it is (coord/validate.h).
template <coord::Backend B>
typename B::Rotation Renormalized(const typename B::Rotation& M) noexcept {
  if constexpr (std::is_same_v<typename B::Rotation, Eigen::Quaterniond>) {
    const auto q = coord::ValidateQuaternion(M);
    return q ? *q : M;
  } else if constexpr (std::is_same_v<typename B::Rotation, Eigen::Matrix3d>) {
    const auto R = coord::ValidateRotationMatrix(M);
    return R ? *R : M;
  } else {
    return M;
  }
}

// The pose add's names by field, in the order of AddPoseImpl's `named`.
constexpr Field kPoseFields[] = {Field::kPoint,          Field::kOrientation,    Field::kBody,
                                 Field::kRefPoint,       Field::kRefOrientation, Field::kRefBody,
                                 Field::kCoordinateFrame};

// A pose add after its names are interned (id: AddPoseImpl's fields): node resolution
// (frame_body_mismatch, frame_without_body) -> self_edge -> representation_constraint ->
// pose_not_convertible. Fills the plan's ends and the frames the edge form is converted
// through: {e, f, r}, each the edge's own frame where the spec names it.
template <coord::Backend B>
BuildResult PlanPoseAdd(const topology::SceneTopology& t, const PoseSpec& spec,
                        const NameId (&id)[7], internal::AddPlan& plan, FrameIndex (&points)[3]) {
  const auto what = [&spec] { return text::PoseAdd(spec); };
  const NameId e_id = id[0], a_id = id[1], f_id = id[3], b_id = id[4], r_id = id[6];
  plan.pose_edge = true;
  if (auto p = internal::ResolveEnd(t, a_id, id[2], plan.head); p != internal::EndProblem::kNone) {
    return text::RejectEnd(t, p, plan.head, what(), spec.orientation, spec.body);
  }
  if (auto p = internal::ResolveEnd(t, b_id, id[5], plan.tail); p != internal::EndProblem::kNone) {
    return text::RejectEnd(t, p, plan.tail, what(), spec.ref_orientation, spec.ref_body);
  }
  const FrameIndex a = plan.head.frame, b = plan.tail.frame;
  const NameId C_name = plan.head.body_name, D_name = plan.tail.body_name;
  const semantics::NameTable& names = t.names();
  const FrameIndex e = t.FrameOfName(e_id), f = t.FrameOfName(f_id), r = t.FrameOfName(r_id);
  if (e.is_valid() && e != a && t.body_of(e) != plan.head.body) {
    return Reject(ErrorCode::kFrameBodyMismatch, what(),
                  "point " + std::string(spec.point) + " is the origin of " + text::Frame(t, e) +
                      ", not of a frame of body " + std::string(names.name(C_name)));
  }
  if (f.is_valid() && f != b && t.body_of(f) != plan.tail.body) {
    return Reject(ErrorCode::kFrameBodyMismatch, what(),
                  "reference point " + std::string(spec.ref_point) + " is the origin of " +
                      text::Frame(t, f) + ", not of a frame of body " +
                      std::string(names.name(D_name)));
  }
  // 5. self_edge.
  if (a_id == b_id) {
    return Reject(
        ErrorCode::kSelfEdge, what(),
        "a pose edge from {" + std::string(spec.orientation) + "} to itself is meaningless");
  }
  // 6. representation_constraint.
  const semantics::PoseSemantics given{
      semantics::Point(e_id),           semantics::OrientationFrame(a_id), semantics::Body(C_name),
      semantics::Point(f_id),           semantics::OrientationFrame(b_id), semantics::Body(D_name),
      semantics::OrientationFrame(r_id)};
  if (auto ok = coord::CheckRepresentation<B>(given); !ok) {
    return Reject(ErrorCode::kRepresentationConstraint, what(), coord::Describe(ok.error(), names));
  }
  // 7. pose_not_convertible: e, f and [r] must be frames of the edge's trees.
  if (e_id != a_id && !(a.is_valid() && e.is_valid() && t.SameTree(a, e))) {
    return Reject(ErrorCode::kPoseNotConvertible, what(),
                  "point " + std::string(spec.point) + " must be a frame of " +
                      std::string(names.name(C_name)) + " in the pose tree of {" +
                      std::string(spec.orientation) + "}");
  }
  if (f_id != b_id && !(b.is_valid() && f.is_valid() && t.SameTree(b, f))) {
    return Reject(ErrorCode::kPoseNotConvertible, what(),
                  "reference point " + std::string(spec.ref_point) + " must be a frame of " +
                      std::string(names.name(D_name)) + " in the pose tree of {" +
                      std::string(spec.ref_orientation) + "}");
  }
  if (r_id != b_id && !(b.is_valid() && r.is_valid() && t.SameTree(b, r))) {
    return Reject(ErrorCode::kPoseNotConvertible, what(),
                  "coordinate frame [" + std::string(spec.coordinate_frame) +
                      "] must be a frame in the pose tree of {" +
                      std::string(spec.ref_orientation) + "}");
  }
  points[0] = e_id != a_id ? e : a;
  points[1] = f_id != b_id ? f : b;
  points[2] = r_id != b_id ? r : b;
  return Ok{};
}

}  // namespace

// ====================================================================== nodes

template <coord::Backend B>
void SceneGraph<B>::Reserve(std::size_t frames, std::size_t bodies) {
  const topology::SceneTopology::ChangeScope change(topology_);  // readers validate
  topology_.Reserve(frames, bodies);
  values_.ReserveFrames(frames);
}

template <coord::Backend B>
FrameIndex SceneGraph<B>::CreateFrame(NameId name, BodyIndex body) {
  // Every allocation before the first change (all or nothing); the value before the frame, so
  // that a reader on another thread that finds the frame finds its value constructed.
  values_.ReserveFrames(values_.X_PF.size() + 1);
  topology_.ReserveNodes(0, 1);
  values_.AddFrame();
  return topology_.CreateFrame(name, body);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddBody(std::string_view name) {
  const topology::SceneTopology::ChangeScope change(topology_);  // readers validate
  const auto what = [&] {
    return name.empty() ? std::string("body with an empty name") : "body " + std::string(name);
  };
  if (auto ok = semantics::ValidateName(name); !ok) {
    return Reject(ErrorCode::kInvalidName, what(), semantics::Describe(ok.error(), name));
  }
  if (FindBody(name).is_valid()) {
    return Reject(ErrorCode::kDuplicateBody, what(),
                  "body " + std::string(name) + " already exists");
  }
  NameRollback rollback(topology_.mutable_names());
  topology_.CreateBody(*topology_.mutable_names().Intern(name));
  rollback.Commit();
  return Ok{};
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddFrame(std::string_view name, std::string_view body) {
  const topology::SceneTopology::ChangeScope change(topology_);  // readers validate
  const auto what = [&] { return "frame " + text::Braced(name, body); };
  if (auto ok = semantics::ValidateName(name); !ok) {
    return Reject(ErrorCode::kInvalidName, what(), semantics::Describe(ok.error(), name));
  }
  if (body.empty()) {
    return Reject(ErrorCode::kFrameWithoutBody, "frame {" + std::string(name) + "}",
                  "a frame must name the body it is attached to");
  }
  if (auto ok = semantics::ValidateName(body); !ok) {
    return Reject(ErrorCode::kInvalidName, what(),
                  "body: " + semantics::Describe(ok.error(), body));
  }
  if (const FrameIndex f = FindFrame(name); f.is_valid()) {
    return Reject(ErrorCode::kDuplicateFrame, what(),
                  "frame " + text::Frame(topology_, f) + " already exists");
  }
  const BodyIndex b = FindBody(body);
  if (!b.is_valid()) {
    return Reject(ErrorCode::kUnknownBody, what(), "body " + std::string(body) + " does not exist");
  }
  NameRollback rollback(topology_.mutable_names());
  CreateFrame(*topology_.mutable_names().Intern(name), b);
  rollback.Commit();
  return Ok{};
}

// ====================================================================== poses

template <coord::Backend B>
BuildResult SceneGraph<B>::AddPose(const PoseSpec& spec, const Eigen::Quaterniond& q_rotation,
                                   const Eigen::Vector3d& p_position) {
  return AddPoseImpl(spec, q_rotation, p_position);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddPose(const PoseSpec& spec, const Eigen::Matrix3d& R_rotation,
                                   const Eigen::Vector3d& p_position) {
  return AddPoseImpl(spec, R_rotation, p_position);
}

// With a covariance (docs/uncertainty.md).
template <coord::Backend B>
BuildResult SceneGraph<B>::AddPose(const PoseSpec& spec, const Eigen::Quaterniond& q_rotation,
                                   const Eigen::Vector3d& p_position,
                                   const CovarianceInput& covariance) {
  return AddPoseImpl(spec, q_rotation, p_position, std::nullopt, &covariance);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddPose(const PoseSpec& spec, const Eigen::Matrix3d& R_rotation,
                                   const Eigen::Vector3d& p_position,
                                   const CovarianceInput& covariance) {
  return AddPoseImpl(spec, R_rotation, p_position, std::nullopt, &covariance);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                                    const Eigen::Vector3d& w_angular,
                                    const CovarianceInput& covariance) {
  return AddTwistImpl(spec, v_linear, w_angular, std::nullopt, &covariance);
}

// Stamped values (docs/time.md; the stamp rules live in time_add.cc).
template <coord::Backend B>
BuildResult SceneGraph<B>::AddPose(const PoseSpec& spec, const Eigen::Quaterniond& q_rotation,
                                   const Eigen::Vector3d& p_position, Stamp stamp) {
  return AddPoseImpl(spec, q_rotation, p_position, stamp);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddPose(const PoseSpec& spec, const Eigen::Matrix3d& R_rotation,
                                   const Eigen::Vector3d& p_position, Stamp stamp) {
  return AddPoseImpl(spec, R_rotation, p_position, stamp);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                                    const Eigen::Vector3d& w_angular, Stamp stamp) {
  return AddTwistImpl(spec, v_linear, w_angular, stamp);
}

// Stamped values with a covariance (docs/uncertainty.md, "Time").
template <coord::Backend B>
BuildResult SceneGraph<B>::AddPose(const PoseSpec& spec, const Eigen::Quaterniond& q_rotation,
                                   const Eigen::Vector3d& p_position, Stamp stamp,
                                   const CovarianceInput& covariance) {
  return AddPoseImpl(spec, q_rotation, p_position, stamp, &covariance);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddPose(const PoseSpec& spec, const Eigen::Matrix3d& R_rotation,
                                   const Eigen::Vector3d& p_position, Stamp stamp,
                                   const CovarianceInput& covariance) {
  return AddPoseImpl(spec, R_rotation, p_position, stamp, &covariance);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                                    const Eigen::Vector3d& w_angular, Stamp stamp,
                                    const CovarianceInput& covariance) {
  return AddTwistImpl(spec, v_linear, w_angular, stamp, &covariance);
}

template <coord::Backend B>
template <class R>
BuildResult SceneGraph<B>::AddPoseImpl(const PoseSpec& spec, const R& rotation,
                                       const Eigen::Vector3d& p_position,
                                       std::optional<Stamp> stamp,
                                       const CovarianceInput* covariance) {
  const topology::SceneTopology::ChangeScope change(topology_);  // readers validate
  semantics::NameTable& names = topology_.mutable_names();
  NameRollback rollback(names);
  const auto what = [&spec] { return text::PoseAdd(spec); };  // formatted only on rejection

  // 1. invalid_name. Each distinct name is looked up once; an interned name is valid by the
  // table's invariant, so only new names are validated (the edge form repeats names).
  const internal::NamedField named[] = {
      {spec.point},           {spec.orientation},     {spec.body, false},     {spec.ref_point},
      {spec.ref_orientation}, {spec.ref_body, false}, {spec.coordinate_frame}};
  internal::AddNames<7> ids;
  semantics::NameError name_error;
  if (const int bad = ids.LookUp(names, named, name_error); bad >= 0) {
    return Reject(ErrorCode::kInvalidName, what(),
                  std::string(FieldName(kPoseFields[bad])) + ": " +
                      semantics::Describe(name_error, named[bad].value));
  }
  // 2-3. invalid_number -> invalid_rotation.
  auto p_ok = coord::ValidateVector(p_position, coord::ValueRole::kPosition);
  if (!p_ok) return Reject(p_ok.error().code, what(), coord::Describe(p_ok.error(), names));
  // A covariance's entries are numbers too: invalid_number in that code's place, before
  // invalid_rotation (docs/uncertainty.md §2); its invalid_covariance comes after.
  if (covariance != nullptr && covariance->matrix != nullptr) {
    if (const coord::CovarianceCheck c = coord::CheckCovariance(*covariance->matrix);
        c.is_number_problem()) {
      return Reject(c.code(), what(), coord::Describe(c));
    }
  }
  typename B::Rotation M;
  if constexpr (std::is_same_v<R, Eigen::Quaterniond>) {
    auto q_ok = coord::ValidateQuaternion(rotation);
    if (!q_ok) return Reject(q_ok.error().code, what(), coord::Describe(q_ok.error(), names));
    M = B::FromQuaternion(*q_ok);
  } else {
    auto R_ok = coord::ValidateRotationMatrix(rotation);
    if (!R_ok) return Reject(R_ok.error().code, what(), coord::Describe(R_ok.error(), names));
    M = B::FromMatrix(*R_ok);
  }
  // 3'. invalid_number -> invalid_covariance of a covariance (docs/uncertainty.md §2).
  const bool has_covariance = covariance != nullptr && covariance->matrix != nullptr;
  coord::Covariance6 S_BA;  // the covariance of the value as given, then of the edge form
  if (has_covariance) {
    const bool edge_form = spec.point == spec.orientation &&
                           spec.ref_point == spec.ref_orientation &&
                           spec.coordinate_frame == spec.ref_orientation;
    if (auto bad = internal::CheckCovarianceInput(*covariance, edge_form, false)) {
      return Reject(bad->code, what(), bad->message);
    }
    S_BA = internal::CoordinatesCovariance(*covariance, B::ToMatrix(M));
  }
  const coord::Covariance6* S = has_covariance ? &S_BA : nullptr;

  // 4-7. Node resolution (names are interned now, rolled back on rejection) -> self_edge ->
  // representation_constraint -> pose_not_convertible.
  ids.Intern(names, named);
  internal::AddPlan plan;
  FrameIndex points[3];  // e, f, r
  if (auto ok = PlanPoseAdd<B>(topology_, spec, ids.id, plan, points); !ok) return ok;
  const topology::SceneTopology& t = topology_;
  const FrameIndex a = plan.head.frame, b = plan.tail.frame;
  const FrameIndex e = points[0], f = points[1], r = points[2];
  // The edge form: PoseCoord({a}|C, {b}|D, [b]).
  typename B::PoseCoords X_BA = B::MakePose(M, *p_ok);
  if (ids.id[0] != ids.id[1] || ids.id[3] != ids.id[4] || ids.id[6] != ids.id[4]) {
    const PoseSteps<ForestChain> steps = PlanChanges(t, e, a, f, b, r);
    // A stamped value is converted with the values at its stamp (docs/time.md).
    internal::TimeContext at_stamp = ConversionContext(stamp);
    const internal::ForestSource<B> src(topology_, values_, stamp ? &at_stamp : nullptr);
    X_BA = internal::ToEdgeForm<B>(src, steps, X_BA);
    if (at_stamp.error() != ErrorCode::kOk) {
      return Reject(ErrorCode::kExtrapolation, what(), DescribeConversionGap(at_stamp, *stamp));
    }
    if (has_covariance) internal::ToEdgeFormCovariance<B>(src, steps, X_BA, S_BA, S_BA);
    X_BA = B::MakePose(Renormalized<B>(B::RotationOf(X_BA)), B::TranslationOf(X_BA));
  }

  // 8. P4: an existing edge b -> a is a value update, or constant_pose_change; a joint's edge
  // is driven by its state only (joint_edge, in P4's place).
  if (topology::PoseEdgeExists(t, b, a)) {
    if (const internal::JointRecord* j = joints_.OfChild(a)) {
      return Reject(ErrorCode::kJointEdge, what(),
                    "the pose edge " + text::Frame(t, b) + " -> " + text::Frame(t, a) +
                        " belongs to joint " + std::string(joints_.name(*j)) +
                        "; set the joint's position instead");
    }
    if (topology::IsConstantEdge(t, b, a)) {
      const auto stored = values_.X_PF[a.value()].Load();
      const Eigen::Matrix3d dR =
          B::ToMatrix(B::RotationOf(stored)) - B::ToMatrix(B::RotationOf(X_BA));
      const Eigen::Vector3d p_stored = B::TranslationOf(stored);
      const double dp = (p_stored - B::TranslationOf(X_BA)).norm();
      const coord::Covariance6 S_stored = values_.PoseCovarianceOf(a.value());
      const bool same_covariance = internal::SameCovariance(S_stored, S);
      if (dR.cwiseAbs().maxCoeff() <= 1e-6 && dp <= 1e-6 * std::max(1.0, p_stored.norm()) &&
          same_covariance) {
        rollback.Commit();
        return Ok{};  // same value again: accepted, stored value kept
      }
      if (!same_covariance) {
        return Reject(ErrorCode::kConstantPoseChange, what(),
                      text::Frame(t, a) + " and " + text::Frame(t, b) + " are both fixed to body " +
                          std::string(t.body_name(t.body_of(a))) +
                          ", so their pose and its covariance are constant; the covariance "
                          "given differs from the stored one; remove the edge first to "
                          "recalibrate");
      }
      return Reject(ErrorCode::kConstantPoseChange, what(),
                    text::Frame(t, a) + " and " + text::Frame(t, b) + " are both fixed to body " +
                        std::string(t.body_name(t.body_of(a))) +
                        ", so their pose is constant; it is already set (position " +
                        text::Vector(p_stored) + "); remove the edge first to recalibrate");
    }
    // A value update: the stamp rules, then the value (and the sample of a stamped edge).
    if (const ErrorCode code = CheckPoseSample(a, X_BA, stamp, S); code != ErrorCode::kOk) {
      return Reject(code, what(), DescribeSampleRejection(code, false, a.value(), stamp));
    }
    if (S) ReservePoseSampleCovariance(a);  // may throw: nothing changed yet
    StorePoseSample(a, X_BA, stamp, S);
    rollback.Commit();
    return Ok{};
  }
  // 9-12. P1 -> P2 -> P3 -> W4.
  if (auto v = topology::CheckNewPoseEdge(t, plan.pose_ends())) {
    return Reject(v->code, what(), text::PoseRule(t, *v, plan.pose_ends(), spec));
  }

  // 13. Apply: every allocation first (a std::bad_alloc there still rolls the names back and
  // changes nothing else; a stamped inter-body edge's history too), then the changes, none of
  // which allocates.
  ReserveAdd(plan);
  if (S) values_.ReservePoseCovariances(values_.X_PF.size() + plan.new_frames());
  PoseHistoryLease history;
  if (stamp && !plan.same_body()) history = NewPoseHistory();
  if (history && S) history->EnsureCovariances();
  rollback.Commit();
  const FrameIndex head = CommitAdd(plan).head;
  values_.StorePoseCovariance(head.value(), X_BA, S);  // before the value (edge_values.h)
  values_.X_PF[head.value()].Store(X_BA);
  if (history) InstallPoseHistory(head, std::move(history), X_BA, *stamp, S);
  return Ok{};
}

// ====================================================================== twists

template <coord::Backend B>
BuildResult SceneGraph<B>::AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                                    const Eigen::Vector3d& w_angular) {
  return AddTwistImpl(spec, v_linear, w_angular, std::nullopt);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddTwistImpl(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                                        const Eigen::Vector3d& w_angular,
                                        std::optional<Stamp> stamp,
                                        const CovarianceInput* covariance,
                                        const AccelerationInput* acceleration) {
  const topology::SceneTopology::ChangeScope change(topology_);  // readers validate
  semantics::NameTable& names = topology_.mutable_names();
  NameRollback rollback(names);
  const auto what = [&spec] { return text::TwistAdd(spec); };  // formatted only on rejection
  const internal::NamedField named[] = {
      {spec.point}, {spec.body, false}, {spec.ref_body}, {spec.coordinate_frame}};
  constexpr Field kFields[] = {Field::kPoint, Field::kBody, Field::kRefBody,
                               Field::kCoordinateFrame};
  internal::AddNames<4> ids;
  semantics::NameError name_error;
  if (const int bad = ids.LookUp(names, named, name_error); bad >= 0) {
    return Reject(ErrorCode::kInvalidName, what(),
                  std::string(FieldName(kFields[bad])) + ": " +
                      semantics::Describe(name_error, named[bad].value));
  }
  auto v_ok = coord::ValidateVector(v_linear, coord::ValueRole::kLinearVelocity);
  if (!v_ok) return Reject(v_ok.error().code, what(), coord::Describe(v_ok.error(), names));
  auto w_ok = coord::ValidateVector(w_angular, coord::ValueRole::kAngularVelocity);
  if (!w_ok) return Reject(w_ok.error().code, what(), coord::Describe(w_ok.error(), names));
  std::optional<AccelerationNumbers> A;  // as given, then at {e} in [e]
  if (acceleration != nullptr) {
    auto a_ok = coord::ValidateVector(acceleration->linear, coord::ValueRole::kLinearAcceleration);
    if (!a_ok) return Reject(a_ok.error().code, what(), coord::Describe(a_ok.error(), names));
    auto alpha_ok =
        coord::ValidateVector(acceleration->angular, coord::ValueRole::kAngularAcceleration);
    if (!alpha_ok) {
      return Reject(alpha_ok.error().code, what(), coord::Describe(alpha_ok.error(), names));
    }
    A = AccelerationNumbers{*a_ok, *alpha_ok};
  }
  const bool has_covariance = covariance != nullptr && covariance->matrix != nullptr;
  coord::Covariance6 S_V;  // as given, then at {e} in [e]
  if (has_covariance) {
    if (auto bad = internal::CheckCovarianceInput(*covariance, false, true)) {
      return Reject(bad->code, what(), bad->message);
    }
    S_V = internal::CoordinatesCovariance(*covariance, Eigen::Matrix3d::Identity());
  }
  const coord::Covariance6* S = has_covariance ? &S_V : nullptr;

  // Node resolution: the point must be the origin of a frame on the moving body.
  ids.Intern(names, named);
  const NameId e_id = ids.id[0], D_id = ids.id[2], r_id = ids.id[3];
  const topology::SceneTopology& t = topology_;
  internal::AddPlan plan;
  plan.twist_edge = true;
  switch (internal::ResolveEnd(t, e_id, ids.id[1], plan.head)) {
    case internal::EndProblem::kFrameBodyMismatch:
      return Reject(ErrorCode::kFrameBodyMismatch, what(),
                    "the point of a twist must be the origin of a frame on the moving body: " +
                        text::Frame(t, plan.head.frame) + " is not on body " +
                        std::string(spec.body));
    case internal::EndProblem::kFrameWithoutBody:
      return Reject(ErrorCode::kFrameWithoutBody, what(),
                    "frame {" + std::string(spec.point) + "} does not exist and no body is given");
    case internal::EndProblem::kNone:
      break;
  }
  plan.tail = internal::AddEnd{NameId(), FrameIndex(), D_id, t.BodyOfName(D_id)};
  const FrameIndex e = plan.head.frame;
  // W2.
  if (plan.head.body_name == D_id) {
    return Reject(ErrorCode::kTwistSameBody, what(),
                  "a twist of body " + std::string(names.name(D_id)) + " relative to itself");
  }
  // twist_not_convertible: [r] must be in the pose tree of {e}; then the screw twist at {e} in [e].
  TwistNumbers V{*v_ok, *w_ok};  // v_DEo_E, w_DE_E
  if (r_id != e_id) {
    const FrameIndex r = t.FrameOfName(r_id);
    if (!(e.is_valid() && r.is_valid() && t.SameTree(e, r))) {
      return Reject(ErrorCode::kTwistNotConvertible, what(),
                    "coordinate frame [" + std::string(spec.coordinate_frame) +
                        "] must be a frame in the pose tree of {" + std::string(spec.point) + "}");
    }
    typename B::PoseCoords X_ER;  // [r] wrt [e] in [e], at the stamp of a stamped value
    internal::TimeContext at_stamp = ConversionContext(stamp);
    internal::EvalBasic<B>(
        internal::ForestSource<B>(topology_, values_, stamp ? &at_stamp : nullptr),
        PlanBasic(t, r, e), X_ER);
    if (at_stamp.error() != ErrorCode::kOk) {
      return Reject(ErrorCode::kExtrapolation, what(), DescribeConversionGap(at_stamp, *stamp));
    }
    V.v_DHo_H = B::Rotate(B::RotationOf(X_ER), V.v_DHo_H);
    V.w_DH_H = B::Rotate(B::RotationOf(X_ER), V.w_DH_H);
    if (A) {  // the same point: only the frame changes
      A->a_DHo_H = B::Rotate(B::RotationOf(X_ER), A->a_DHo_H);
      A->alpha_DH_H = B::Rotate(B::RotationOf(X_ER), A->alpha_DH_H);
    }
    if (has_covariance) {  // re-expressed with the same rotation, taken as exact
      coord::Covariance6 S_E = coord::Covariance6::Zero();
      coord::jacobians::AddPropagated(coord::jacobians::Reexpress(B::ToMatrix(B::RotationOf(X_ER))),
                                      S_V, S_E);
      S_V = S_E;
    }
  }
  // W1 -> W3; an existing edge D -> {e} is a value update.
  const BodyIndex D = plan.tail.body;
  if (e.is_valid() && t.twist_edge_of(e).is_valid() && D.is_valid() &&
      t.twist_edge(t.twist_edge_of(e)).tail == D) {
    if (const internal::JointRecord* j = joints_.OfChild(e)) {  // joint_edge, before W1
      return Reject(ErrorCode::kJointEdge, what(),
                    "the twist edge " + std::string(t.body_name(D)) + " -> " + text::Frame(t, e) +
                        " belongs to joint " + std::string(joints_.name(*j)) +
                        "; set the joint's velocity instead");
    }
    const TwistEdgeIndex existing = t.twist_edge_of(e);
    if (const ErrorCode code = CheckTwistSample(existing, V, stamp, S, A ? &*A : nullptr);
        code != ErrorCode::kOk) {
      return Reject(code, what(), DescribeSampleRejection(code, true, existing.value(), stamp));
    }
    if (S) ReserveTwistSampleCovariance(existing);  // may throw: no change yet
    if (A) values_.ReserveTwistSampleAccelerations(existing.value());
    StoreTwistSample(existing, V, stamp, S, A ? &*A : nullptr);
    rollback.Commit();
    return Ok{};
  }
  if (auto v = topology::CheckNewTwistEdge(t, plan.twist_ends())) {
    return Reject(v->code, what(), text::TwistRule(t, *v, plan.twist_ends()));
  }

  // Apply: every allocation first (as in AddPose; a stamped edge's history too), then the
  // changes.
  ReserveAdd(plan);
  if (S) values_.ReserveTwistCovariances(t.num_twist_edge_slots() + 1);  // any slot it may get
  TwistHistoryLease history;
  if (stamp) history = NewTwistHistory();
  if (history && S) history->EnsureCovariances();
  if (history && A) history->EnsureAccelerations();
  rollback.Commit();
  const TwistEdgeIndex edge = CommitAdd(plan).twist;
  values_.StoreTwistCovariance(edge.value(), V, S);  // before the value (edge_values.h)
  values_.StoreAcceleration(edge.value(), V, A ? &*A : nullptr);  // a reused slot's: cleared
  values_.V_DH[edge.value()].Store(V);
  if (history) InstallTwistHistory(edge, std::move(history), V, *stamp, S, A ? &*A : nullptr);
  return Ok{};
}

// ====================================================================== apply

template <coord::Backend B>
void SceneGraph<B>::ReserveAdd(const internal::AddPlan& plan) {
  const std::size_t new_frames = plan.new_frames();
  topology_.ReserveNodes(plan.new_bodies(), new_frames);
  values_.ReserveFrames(values_.X_PF.size() + new_frames);
  if (plan.pose_edge && plan.twist_edge) {
    topology_.ReserveLinkJoint(plan.tail.frame, plan.head.frame);
  } else if (plan.pose_edge) {
    topology_.ReserveLinkPose(plan.tail.frame, plan.head.frame);
  } else {
    topology_.ReserveLinkTwist(plan.head.frame);
  }
  if (plan.twist_edge) values_.ReserveTwistSlots(topology_.num_twist_edge_slots() + 1);
}

template <coord::Backend B>
internal::AddedEdges SceneGraph<B>::CommitAdd(const internal::AddPlan& plan) {
  internal::AddedEdges out{plan.tail.frame, plan.head.frame, plan.tail.body, plan.head.body, {}};
  if (plan.tail_body_first && !out.tail_body.is_valid())
    out.tail_body = topology_.CreateBody(plan.tail.body_name);
  if (!out.head_body.is_valid()) out.head_body = topology_.CreateBody(plan.head.body_name);
  if (!out.tail_body.is_valid()) {
    out.tail_body = plan.same_body() ? out.head_body : topology_.CreateBody(plan.tail.body_name);
  }
  if (!out.head.is_valid()) out.head = CreateFrame(plan.head.frame_name, out.head_body);
  if (plan.pose_edge) {
    if (!out.tail.is_valid()) out.tail = CreateFrame(plan.tail.frame_name, out.tail_body);
    topology_.LinkPoseReserved(out.tail, out.head);  // reserved by ReserveAdd
  }
  if (plan.twist_edge) {
    const topology::SceneTopology& t = topology_;
    const NameId h = plan.head.frame_name;
    // The value slot first (reserved by ReserveAdd): a reader thread that sees the edge in the
    // topology then finds its value constructed (LinkTwist takes a free slot, whose value
    // exists, or this one).
    values_.AddTwistSlot(
        topology::TwistEdgeIndex(static_cast<std::uint32_t>(topology_.num_twist_edge_slots())));
    out.twist = topology_.LinkTwist(
        out.tail_body, out.head,
        semantics::TwistSemantics{semantics::Point(h), t.BodySem(out.head_body),
                                  t.BodySem(out.tail_body), semantics::OrientationFrame(h)});
    values_.AddTwistSlot(out.twist);
  }
  return out;
}

// ====================================================================== removal

template <coord::Backend B>
BuildResult SceneGraph<B>::RemovePose(std::string_view of, std::string_view relative_to) {
  const topology::SceneTopology::ChangeScope change(topology_);  // readers validate
  const auto what = [&] {
    return "removal of the pose of {" + std::string(of) + "} wrt {" + std::string(relative_to) +
           "}";
  };
  const internal::EdgeLookup l = internal::LookUpPoseEdge(topology_, of, relative_to);
  if (l.code != ErrorCode::kOk)
    return Reject(l.code, what(), text::EdgeReason(topology_, l, relative_to, true));
  if (const internal::JointRecord* j = joints_.OfChild(l.head))
    return RemoveJoint(*j);  // joints.cc
  RemovePoseEdge(l.head);
  return Ok{};
}

template <coord::Backend B>
BuildResult SceneGraph<B>::RemoveTwist(std::string_view of, std::string_view relative_to) {
  const topology::SceneTopology::ChangeScope change(topology_);  // readers validate
  const auto shown = [](std::string_view n) {
    return n.empty() ? std::string("\"\"") : std::string(n);
  };
  const auto what = [&] {
    return "removal of the twist of " + shown(of) + " wrt " + shown(relative_to);
  };
  const internal::EdgeLookup l = internal::LookUpTwistEdge(topology_, of, relative_to);
  if (l.code != ErrorCode::kOk)
    return Reject(l.code, what(), text::EdgeReason(topology_, l, relative_to, true));
  if (const internal::JointRecord* j = joints_.OfChild(l.head)) {
    return Reject(ErrorCode::kJointEdge, what(),
                  "it is the twist edge of joint " + std::string(joints_.name(*j)) +
                      "; remove the joint's pose edge to remove the joint");
  }
  RemoveTwistEdge(l.edge);
  return Ok{};
}

// Removal by index: no allocation before the first change (CutPose allocates before its own).
template <coord::Backend B>
void SceneGraph<B>::RemovePoseEdge(FrameIndex head) {
  topology_.CutPose(head);
  values_.ClearPoseCovariance(head.value());
  values_.X_PF[head.value()]
      .BumpEpoch();       // compiled queries and handles using this edge become invalid
  DropPoseHistory(head);  // removing an edge drops its history
}

template <coord::Backend B>
void SceneGraph<B>::RemoveTwistEdge(TwistEdgeIndex edge) {
  topology_.UnlinkTwist(edge);
  values_.ClearTwistCovariance(edge.value());
  values_.StoreAcceleration(edge.value(), values_.V_DH[edge.value()].Load(), nullptr);
  values_.V_DH[edge.value()]
      .BumpEpoch();  // compiled queries and handles using this edge become invalid
  values_.A_DH[edge.value()].BumpEpoch();
  DropTwistHistory(edge);
}

#define SEMGRAPH_INSTANTIATE_ADD(B)                                                             \
  template void SceneGraph<B>::Reserve(std::size_t, std::size_t);                               \
  template FrameIndex SceneGraph<B>::CreateFrame(NameId, BodyIndex);                            \
  template BuildResult SceneGraph<B>::AddBody(std::string_view);                                \
  template BuildResult SceneGraph<B>::AddFrame(std::string_view, std::string_view);             \
  template BuildResult SceneGraph<B>::AddPose(const PoseSpec&, const Eigen::Quaterniond&,       \
                                              const Eigen::Vector3d&);                          \
  template BuildResult SceneGraph<B>::AddPose(const PoseSpec&, const Eigen::Matrix3d&,          \
                                              const Eigen::Vector3d&);                          \
  template BuildResult SceneGraph<B>::AddTwist(const TwistSpec&, const Eigen::Vector3d&,        \
                                               const Eigen::Vector3d&);                         \
  template BuildResult SceneGraph<B>::AddPose(const PoseSpec&, const Eigen::Quaterniond&,       \
                                              const Eigen::Vector3d&, Stamp);                   \
  template BuildResult SceneGraph<B>::AddPose(const PoseSpec&, const Eigen::Matrix3d&,          \
                                              const Eigen::Vector3d&, Stamp);                   \
  template BuildResult SceneGraph<B>::AddTwist(const TwistSpec&, const Eigen::Vector3d&,        \
                                               const Eigen::Vector3d&, Stamp);                  \
  template BuildResult SceneGraph<B>::AddPose(const PoseSpec&, const Eigen::Quaterniond&,       \
                                              const Eigen::Vector3d&, const CovarianceInput&);  \
  template BuildResult SceneGraph<B>::AddPose(const PoseSpec&, const Eigen::Matrix3d&,          \
                                              const Eigen::Vector3d&, const CovarianceInput&);  \
  template BuildResult SceneGraph<B>::AddTwist(const TwistSpec&, const Eigen::Vector3d&,        \
                                               const Eigen::Vector3d&, const CovarianceInput&); \
  template BuildResult SceneGraph<B>::AddPose(const PoseSpec&, const Eigen::Quaterniond&,       \
                                              const Eigen::Vector3d&, Stamp,                    \
                                              const CovarianceInput&);                          \
  template BuildResult SceneGraph<B>::AddPose(const PoseSpec&, const Eigen::Matrix3d&,          \
                                              const Eigen::Vector3d&, Stamp,                    \
                                              const CovarianceInput&);                          \
  template BuildResult SceneGraph<B>::AddTwist(const TwistSpec&, const Eigen::Vector3d&,        \
                                               const Eigen::Vector3d&, Stamp,                   \
                                               const CovarianceInput&);                         \
  template BuildResult SceneGraph<B>::AddTwistImpl(                                             \
      const TwistSpec&, const Eigen::Vector3d&, const Eigen::Vector3d&, std::optional<Stamp>,   \
      const CovarianceInput*, const AccelerationInput*);                                        \
  template BuildResult SceneGraph<B>::RemovePose(std::string_view, std::string_view);           \
  template BuildResult SceneGraph<B>::RemoveTwist(std::string_view, std::string_view);          \
  template void SceneGraph<B>::RemovePoseEdge(FrameIndex);                                      \
  template void SceneGraph<B>::RemoveTwistEdge(TwistEdgeIndex);                                 \
  template void SceneGraph<B>::ReserveAdd(const internal::AddPlan&);                            \
  template internal::AddedEdges SceneGraph<B>::CommitAdd(const internal::AddPlan&);
SEMGRAPH_INSTANTIATE_ADD(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_ADD(coord::HomogeneousBackend)

}  // namespace semgraph::core
