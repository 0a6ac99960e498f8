// Adds and removals: validate -> resolve nodes -> edge form (the plan run backwards, evaluate.h
// ToEdgeForm) -> rules (topology/rules.h, in the order of docs/rules.md) -> apply. Every early
// return leaves the graph as it was: names interned by the operation are rolled back, and
// nothing else changes before the last check passed.
#include <algorithm>
#include <cmath>

#include "semgraph/core/scene_graph.h"
#include "semgraph/semantics/describe.h"
#include "text.h"

namespace semgraph::core {

using base::Unexpected;
using semantics::Field;
using semantics::FieldName;
using text::Reject;

namespace {

// Restores the name table on every early return of a build operation (atomicity).
class NameRollback {
 public:
  explicit NameRollback(semantics::NameTable& names) : names_(names), size_(names.size()) {}
  ~NameRollback() {
    if (armed_) names_.TruncateTo(size_);
  }
  void Commit() { armed_ = false; }

 private:
  semantics::NameTable& names_;
  std::size_t size_;
  bool armed_ = true;
};

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

}  // namespace

// ====================================================================== nodes

template <coord::Backend B>
void SceneGraph<B>::Reserve(std::size_t frames, std::size_t bodies) {
  topology_.Reserve(frames, bodies);
  values_.ReserveFrames(frames);
}

template <coord::Backend B>
FrameIndex SceneGraph<B>::CreateFrame(NameId name, BodyIndex body) {
  values_.ReserveFrames(values_.X_PF.size() + 1);  // before the topology changes: all or nothing
  const FrameIndex f = topology_.CreateFrame(name, body);
  values_.AddFrame();
  return f;
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddBody(std::string_view name) {
  const auto what = [&] { return name.empty() ? std::string("body with an empty name") : "body " + std::string(name); };
  if (auto ok = semantics::ValidateName(name); !ok) {
    return Reject(ErrorCode::kInvalidName, what(), semantics::Describe(ok.error(), name));
  }
  if (FindBody(name).is_valid()) {
    return Reject(ErrorCode::kDuplicateBody, what(), "body " + std::string(name) + " already exists");
  }
  NameRollback rollback(topology_.mutable_names());
  topology_.CreateBody(*topology_.mutable_names().Intern(name));
  rollback.Commit();
  return Ok{};
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddFrame(std::string_view name, std::string_view body) {
  const auto what = [&] { return "frame " + text::Braced(name, body); };
  if (auto ok = semantics::ValidateName(name); !ok) {
    return Reject(ErrorCode::kInvalidName, what(), semantics::Describe(ok.error(), name));
  }
  if (body.empty()) {
    return Reject(ErrorCode::kFrameWithoutBody, "frame {" + std::string(name) + "}",
                  "a frame must name the body it is attached to");
  }
  if (auto ok = semantics::ValidateName(body); !ok) {
    return Reject(ErrorCode::kInvalidName, what(), "body: " + semantics::Describe(ok.error(), body));
  }
  if (const FrameIndex f = FindFrame(name); f.is_valid()) {
    return Reject(ErrorCode::kDuplicateFrame, what(), "frame " + text::Frame(topology_, f) + " already exists");
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

template <coord::Backend B>
template <class R>
BuildResult SceneGraph<B>::AddPoseImpl(const PoseSpec& spec, const R& rotation, const Eigen::Vector3d& p_position,
                                       std::optional<Stamp> stamp) {
  semantics::NameTable& names = topology_.mutable_names();
  NameRollback rollback(names);
  const auto what = [&spec] { return text::PoseAdd(spec); };  // formatted only on rejection

  // 1. invalid_name. Each distinct name is looked up once; an interned name is valid by the
  // table's invariant, so only new names are validated (the edge form repeats names).
  struct NamedField {
    std::string_view value;
    Field field;
    bool required;
  };
  const NamedField named[] = {{spec.point, Field::kPoint, true},
                              {spec.orientation, Field::kOrientation, true},
                              {spec.body, Field::kBody, false},
                              {spec.ref_point, Field::kRefPoint, true},
                              {spec.ref_orientation, Field::kRefOrientation, true},
                              {spec.ref_body, Field::kRefBody, false},
                              {spec.coordinate_frame, Field::kCoordinateFrame, true}};
  // Same view (the builders copy one view into several fields) before same text; the last byte
  // decides most mismatches of names that share a prefix.
  const auto same_name = [](std::string_view x, std::string_view y) {
    return x.size() == y.size() && (x.data() == y.data() || (!x.empty() && x.back() == y.back() && x == y));
  };
  NameId found[7];
  std::uint32_t hash[7] = {};
  int first[7];  // the first field with the same name
  for (int i = 0; i < 7; ++i) {
    const NamedField& n = named[i];
    first[i] = i;
    if (n.value.empty() && !n.required) continue;
    for (int j = 0; j < i && first[i] == i; ++j) {
      if (same_name(named[j].value, n.value)) first[i] = j;
    }
    if (first[i] < i) {
      found[i] = found[first[i]];
      hash[i] = hash[first[i]];
      continue;
    }
    const semantics::NameTable::Lookup lookup = names.FindWithHash(n.value);
    found[i] = lookup.id;
    hash[i] = lookup.hash;
    if (found[i].is_valid()) continue;
    if (auto ok = semantics::ValidateName(n.value); !ok) {
      return Reject(ErrorCode::kInvalidName, what(),
                    std::string(FieldName(n.field)) + ": " + semantics::Describe(ok.error(), n.value));
    }
  }
  // 2-3. invalid_number -> invalid_rotation.
  auto p_ok = coord::ValidateVector(p_position, coord::ValueRole::kPosition);
  if (!p_ok) return Reject(p_ok.error().code, what(), coord::Describe(p_ok.error(), names));
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

  // 4. Node resolution. Names are interned now (rolled back on rejection).
  for (int i = 0; i < 7; ++i) {
    if (found[i].is_valid() || named[i].value.empty()) continue;
    found[i] = first[i] < i ? found[first[i]] : names.InternNew(named[i].value, hash[i]);
  }
  const NameId e_id = found[0], a_id = found[1], C_id = found[2];
  const NameId f_id = found[3], b_id = found[4], D_id = found[5];
  const NameId r_id = found[6];
  const topology::SceneTopology& t = topology_;
  const FrameIndex a = t.FrameOfName(a_id), b = t.FrameOfName(b_id);
  BodyIndex C = t.BodyOfName(C_id), D = t.BodyOfName(D_id);
  NameId C_name = C_id, D_name = D_id;
  const auto resolve = [&](FrameIndex x, std::string_view frame, std::string_view body_text, BodyIndex& body,
                           NameId& body_name_id) -> BuildResult {
    if (x.is_valid()) {
      if (!body_text.empty() && body != t.body_of(x)) {
        return Reject(ErrorCode::kFrameBodyMismatch, what(),
                      "frame {" + std::string(frame) + "} is attached to body " +
                          std::string(t.body_name(t.body_of(x))) + ", not " + std::string(body_text));
      }
      body = t.body_of(x);
      body_name_id = t.body_name_id(body);
      return Ok{};
    }
    if (body_text.empty()) {
      return Reject(ErrorCode::kFrameWithoutBody, what(),
                    "frame {" + std::string(frame) + "} does not exist and no body is given to attach it to");
    }
    return Ok{};
  };
  if (auto ok = resolve(a, spec.orientation, spec.body, C, C_name); !ok) return ok;
  if (auto ok = resolve(b, spec.ref_orientation, spec.ref_body, D, D_name); !ok) return ok;
  const FrameIndex e = t.FrameOfName(e_id), f = t.FrameOfName(f_id), r = t.FrameOfName(r_id);
  if (e.is_valid() && e != a && t.body_of(e) != C) {
    return Reject(ErrorCode::kFrameBodyMismatch, what(),
                  "point " + std::string(spec.point) + " is the origin of " + text::Frame(t, e) +
                      ", not of a frame of body " + std::string(names.name(C_name)));
  }
  if (f.is_valid() && f != b && t.body_of(f) != D) {
    return Reject(ErrorCode::kFrameBodyMismatch, what(),
                  "reference point " + std::string(spec.ref_point) + " is the origin of " + text::Frame(t, f) +
                      ", not of a frame of body " + std::string(names.name(D_name)));
  }
  // 5. self_edge.
  if (a_id == b_id) {
    return Reject(ErrorCode::kSelfEdge, what(),
                  "a pose edge from {" + std::string(spec.orientation) + "} to itself is meaningless");
  }
  // 6. representation_constraint.
  const semantics::PoseSemantics given{semantics::Point(e_id), semantics::OrientationFrame(a_id),
                                       semantics::Body(C_name), semantics::Point(f_id),
                                       semantics::OrientationFrame(b_id), semantics::Body(D_name),
                                       semantics::OrientationFrame(r_id)};
  if (auto ok = coord::CheckRepresentation<B>(given); !ok) {
    return Reject(ErrorCode::kRepresentationConstraint, what(), coord::Describe(ok.error(), names));
  }
  // 7. pose_not_convertible: e, f and [r] must be frames of the edge's trees; then the edge form.
  if (e_id != a_id && !(a.is_valid() && e.is_valid() && t.SameTree(a, e))) {
    return Reject(ErrorCode::kPoseNotConvertible, what(),
                  "point " + std::string(spec.point) + " must be a frame of " + std::string(names.name(C_name)) +
                      " in the pose tree of {" + std::string(spec.orientation) + "}");
  }
  if (f_id != b_id && !(b.is_valid() && f.is_valid() && t.SameTree(b, f))) {
    return Reject(ErrorCode::kPoseNotConvertible, what(),
                  "reference point " + std::string(spec.ref_point) + " must be a frame of " +
                      std::string(names.name(D_name)) + " in the pose tree of {" + std::string(spec.ref_orientation) +
                      "}");
  }
  if (r_id != b_id && !(b.is_valid() && r.is_valid() && t.SameTree(b, r))) {
    return Reject(ErrorCode::kPoseNotConvertible, what(),
                  "coordinate frame [" + std::string(spec.coordinate_frame) +
                      "] must be a frame in the pose tree of {" + std::string(spec.ref_orientation) + "}");
  }
  typename B::PoseCoords X_BA = B::MakePose(M, *p_ok);  // edge form: PoseCoord({a}|C, {b}|D, [b])
  if (e_id != a_id || f_id != b_id || r_id != b_id) {
    const PoseSteps<ForestChain> steps =
        PlanChanges(t, e_id != a_id ? e : a, a, f_id != b_id ? f : b, b, r_id != b_id ? r : b);
    // A stamped value is converted with the values at its stamp (docs/time.md).
    internal::TimeContext at_stamp = ConversionContext(stamp);
    X_BA = internal::ToEdgeForm<B>(internal::ForestSource<B>(topology_, values_, stamp ? &at_stamp : nullptr), steps,
                                   X_BA);
    if (at_stamp.error() != ErrorCode::kOk) {
      return Reject(ErrorCode::kExtrapolation, what(), DescribeConversionGap(at_stamp, *stamp));
    }
    X_BA = B::MakePose(Renormalized<B>(B::RotationOf(X_BA)), B::TranslationOf(X_BA));
  }

  // 8. P4: an existing edge b -> a is a value update, or constant_pose_change; a joint's edge
  // is driven by its state only (joint_edge, in P4's place).
  if (topology::PoseEdgeExists(t, b, a)) {
    if (const internal::JointRecord* j = joints_.OfChild(a)) {
      return Reject(ErrorCode::kJointEdge, what(),
                    "the pose edge " + text::Frame(t, b) + " -> " + text::Frame(t, a) + " belongs to joint " + j->name +
                        "; set the joint's position instead");
    }
    if (topology::IsConstantEdge(t, b, a)) {
      const auto stored = values_.X_PF[a.value()].Load();
      const Eigen::Matrix3d dR = B::ToMatrix(B::RotationOf(stored)) - B::ToMatrix(B::RotationOf(X_BA));
      const Eigen::Vector3d p_stored = B::TranslationOf(stored);
      const double dp = (p_stored - B::TranslationOf(X_BA)).norm();
      if (dR.cwiseAbs().maxCoeff() <= 1e-6 && dp <= 1e-6 * std::max(1.0, p_stored.norm())) {
        rollback.Commit();
        return Ok{};  // same value again: accepted, stored value kept
      }
      return Reject(ErrorCode::kConstantPoseChange, what(),
                    text::Frame(t, a) + " and " + text::Frame(t, b) + " are both fixed to body " +
                        std::string(t.body_name(t.body_of(a))) +
                        ", so their pose is constant; it is already set (position " + text::Vector(p_stored) +
                        "); remove the edge first to recalibrate");
    }
    // A value update: the stamp rules, then the value (and the sample of a stamped edge).
    if (const ErrorCode code = CheckPoseSample(a, X_BA, stamp); code != ErrorCode::kOk) {
      return Reject(code, what(), DescribeSampleRejection(code, false, a.value(), stamp));
    }
    StorePoseSample(a, X_BA, stamp);
    rollback.Commit();
    return Ok{};
  }
  // 9-12. P1 -> P2 -> P3 -> W4.
  const topology::NewPoseEdge ends{b, a, D, C, C_name == D_name};
  if (auto v = topology::CheckNewPoseEdge(t, ends)) {
    return Reject(v->code, what(), text::PoseRule(t, *v, ends, spec));
  }

  // 13. Apply: create nodes, link, store the value. Every allocation first (a std::bad_alloc
  // there still rolls the names back and changes nothing else; a stamped inter-body edge's
  // history too), then the changes, none of which allocates.
  const std::size_t new_bodies = (C.is_valid() ? 0 : 1) + (D.is_valid() || C_name == D_name ? 0 : 1);
  const std::size_t new_frames = (a.is_valid() ? 0 : 1) + (b.is_valid() ? 0 : 1);
  topology_.ReserveNodes(new_bodies, new_frames);
  values_.ReserveFrames(values_.X_PF.size() + new_frames);
  topology_.ReserveLinkPose(b, a);
  PoseHistoryLease history;
  if (stamp && !ends.same_body) history = NewPoseHistory();
  rollback.Commit();
  if (!C.is_valid()) C = topology_.CreateBody(C_name);
  if (!D.is_valid()) D = C_name == D_name ? C : topology_.CreateBody(D_name);
  const FrameIndex head = a.is_valid() ? a : CreateFrame(a_id, C);
  const FrameIndex tail = b.is_valid() ? b : CreateFrame(b_id, D);
  topology_.LinkPoseReserved(tail, head);  // reserved above
  values_.X_PF[head.value()].Store(X_BA);
  if (history) InstallPoseHistory(head, std::move(history), X_BA, *stamp);
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
                                        const Eigen::Vector3d& w_angular, std::optional<Stamp> stamp) {
  semantics::NameTable& names = topology_.mutable_names();
  NameRollback rollback(names);
  const auto what = [&spec] { return text::TwistAdd(spec); };  // formatted only on rejection
  struct NamedField {
    std::string_view value;
    Field field;
    bool required;
  };
  const NamedField named[] = {{spec.point, Field::kPoint, true},
                              {spec.body, Field::kBody, false},
                              {spec.ref_body, Field::kRefBody, true},
                              {spec.coordinate_frame, Field::kCoordinateFrame, true}};
  for (const NamedField& n : named) {
    if (n.value.empty() && !n.required) continue;
    if (auto ok = semantics::ValidateName(n.value); !ok) {
      return Reject(ErrorCode::kInvalidName, what(),
                    std::string(FieldName(n.field)) + ": " + semantics::Describe(ok.error(), n.value));
    }
  }
  auto v_ok = coord::ValidateVector(v_linear, coord::ValueRole::kLinearVelocity);
  if (!v_ok) return Reject(v_ok.error().code, what(), coord::Describe(v_ok.error(), names));
  auto w_ok = coord::ValidateVector(w_angular, coord::ValueRole::kAngularVelocity);
  if (!w_ok) return Reject(w_ok.error().code, what(), coord::Describe(w_ok.error(), names));

  // Node resolution: the point must be the origin of a frame on the moving body.
  const NameId e_id = *names.Intern(spec.point);
  const NameId C_id = spec.body.empty() ? NameId() : *names.Intern(spec.body);
  const NameId D_id = *names.Intern(spec.ref_body);
  const NameId r_id = *names.Intern(spec.coordinate_frame);
  const topology::SceneTopology& t = topology_;
  const FrameIndex e = t.FrameOfName(e_id);
  BodyIndex C = t.BodyOfName(C_id);
  NameId C_name = C_id;
  if (e.is_valid()) {
    if (C_id.is_valid() && C != t.body_of(e)) {
      return Reject(ErrorCode::kFrameBodyMismatch, what(),
                    "the point of a twist must be the origin of a frame on the moving body: " + text::Frame(t, e) +
                        " is not on body " + std::string(spec.body));
    }
    C = t.body_of(e);
    C_name = t.body_name_id(C);
  } else if (!C_id.is_valid()) {
    return Reject(ErrorCode::kFrameWithoutBody, what(),
                  "frame {" + std::string(spec.point) + "} does not exist and no body is given");
  }
  const BodyIndex D = t.BodyOfName(D_id);
  // W2.
  if (C_name == D_id) {
    return Reject(ErrorCode::kTwistSameBody, what(),
                  "a twist of body " + std::string(names.name(C_name)) + " relative to itself");
  }
  // twist_not_convertible: [r] must be in the pose tree of {e}; then the screw twist at {e} in [e].
  const FrameIndex r = t.FrameOfName(r_id);
  Eigen::Vector3d v_DEo_E = *v_ok, w_DE_E = *w_ok;
  if (r_id != e_id) {
    if (!(e.is_valid() && r.is_valid() && t.SameTree(e, r))) {
      return Reject(ErrorCode::kTwistNotConvertible, what(),
                    "coordinate frame [" + std::string(spec.coordinate_frame) +
                        "] must be a frame in the pose tree of {" + std::string(spec.point) + "}");
    }
    typename B::PoseCoords X_ER;  // [r] wrt [e] in [e], at the stamp of a stamped value
    internal::TimeContext at_stamp = ConversionContext(stamp);
    internal::EvalBasic<B>(internal::ForestSource<B>(topology_, values_, stamp ? &at_stamp : nullptr),
                           PlanBasic(t, r, e), X_ER);
    if (at_stamp.error() != ErrorCode::kOk) {
      return Reject(ErrorCode::kExtrapolation, what(), DescribeConversionGap(at_stamp, *stamp));
    }
    const typename B::Rotation R_ER = B::RotationOf(X_ER);
    v_DEo_E = B::Rotate(R_ER, v_DEo_E);
    w_DE_E = B::Rotate(R_ER, w_DE_E);
  }
  // W1 -> W3; an existing edge D -> {e} is a value update.
  const topology::NewTwistEdge ends{D, e, C};
  if (e.is_valid() && t.twist_edge_of(e).is_valid() && D.is_valid() && t.twist_edge(t.twist_edge_of(e)).tail == D) {
    if (const internal::JointRecord* j = joints_.OfChild(e)) {  // joint_edge, before W1
      return Reject(ErrorCode::kJointEdge, what(),
                    "the twist edge " + std::string(t.body_name(D)) + " -> " + text::Frame(t, e) + " belongs to joint " +
                        j->name + "; set the joint's velocity instead");
    }
    const TwistEdgeIndex existing = t.twist_edge_of(e);
    const TwistNumbers V{v_DEo_E, w_DE_E};
    if (const ErrorCode code = CheckTwistSample(existing, V, stamp); code != ErrorCode::kOk) {
      return Reject(code, what(), DescribeSampleRejection(code, true, existing.value(), stamp));
    }
    StoreTwistSample(existing, V, stamp);
    rollback.Commit();
    return Ok{};
  }
  if (auto v = topology::CheckNewTwistEdge(t, ends)) return Reject(v->code, what(), text::TwistRule(t, *v, ends));

  // Apply: every allocation first (as in AddPose; a stamped edge's history too), then the
  // changes.
  topology_.ReserveNodes((C.is_valid() ? 0 : 1) + (D.is_valid() ? 0 : 1), e.is_valid() ? 0 : 1);
  values_.ReserveFrames(values_.X_PF.size() + (e.is_valid() ? 0 : 1));
  values_.ReserveTwistSlots(t.num_twist_edge_slots() + 1);
  topology_.ReserveLinkTwist(e);
  TwistHistoryLease history;
  if (stamp) history = NewTwistHistory();
  rollback.Commit();
  if (!C.is_valid()) C = topology_.CreateBody(C_name);
  const BodyIndex tail = D.is_valid() ? D : topology_.CreateBody(D_id);
  const FrameIndex head = e.is_valid() ? e : CreateFrame(e_id, C);
  const TwistEdgeIndex edge = topology_.LinkTwist(
      tail, head,
      semantics::TwistSemantics{semantics::Point(e_id), t.BodySem(C), t.BodySem(tail), semantics::OrientationFrame(e_id)});
  values_.AddTwistSlot(edge);
  values_.V_DH[edge.value()].Store(TwistNumbers{v_DEo_E, w_DE_E});
  if (history) InstallTwistHistory(edge, std::move(history), TwistNumbers{v_DEo_E, w_DE_E}, *stamp);
  return Ok{};
}

// ====================================================================== removal

template <coord::Backend B>
BuildResult SceneGraph<B>::RemovePose(std::string_view of, std::string_view relative_to) {
  const auto what = [&] {
    return "removal of the pose of {" + std::string(of) + "} wrt {" + std::string(relative_to) + "}";
  };
  for (std::string_view n : {of, relative_to}) {
    if (auto ok = semantics::ValidateName(n); !ok) {
      return Reject(ErrorCode::kInvalidName, what(), semantics::Describe(ok.error(), n));
    }
  }
  const topology::SceneTopology& t = topology_;
  const FrameIndex h = FindFrame(of), tail = FindFrame(relative_to);
  if (!h.is_valid()) return Reject(ErrorCode::kUnknownFrame, what(), "frame {" + std::string(of) + "} does not exist");
  if (!tail.is_valid()) {
    return Reject(ErrorCode::kUnknownFrame, what(), "frame {" + std::string(relative_to) + "} does not exist");
  }
  if (!topology::PoseEdgeExists(t, tail, h)) {
    const FrameIndex p = t.pose_parent(h);
    return Reject(ErrorCode::kNoSuchEdge, what(),
                  "there is no pose edge " + text::Frame(t, tail) + " -> " + text::Frame(t, h) +
                      (p.is_valid() ? " (the pose parent of " + text::Frame(t, h) + " is " + text::Frame(t, p) + ")"
                                    : " (" + text::Frame(t, h) + " has no pose parent)"));
  }
  if (const internal::JointRecord* j = joints_.OfChild(h)) return RemoveJoint(*j);  // joints.cc
  topology_.CutPose(h);
  values_.X_PF[h.value()].BumpEpoch();  // compiled queries and handles using this edge become invalid
  DropPoseHistory(h);                   // removing an edge drops its history
  return Ok{};
}

template <coord::Backend B>
BuildResult SceneGraph<B>::RemoveTwist(std::string_view of, std::string_view relative_to) {
  const auto shown = [](std::string_view n) { return n.empty() ? std::string("\"\"") : std::string(n); };
  const auto what = [&] { return "removal of the twist of " + shown(of) + " wrt " + shown(relative_to); };
  for (std::string_view n : {of, relative_to}) {
    if (auto ok = semantics::ValidateName(n); !ok) {
      return Reject(ErrorCode::kInvalidName, what(), semantics::Describe(ok.error(), n));
    }
  }
  const topology::SceneTopology& t = topology_;
  const FrameIndex h = FindFrame(of);
  if (!h.is_valid()) return Reject(ErrorCode::kUnknownFrame, what(), "frame {" + std::string(of) + "} does not exist");
  const BodyIndex D = FindBody(relative_to);
  if (!D.is_valid()) {
    return Reject(ErrorCode::kUnknownBody, what(), "body " + std::string(relative_to) + " does not exist");
  }
  const TwistEdgeIndex edge = t.twist_edge_of(h);
  if (!edge.is_valid() || t.twist_edge(edge).tail != D) {
    return Reject(ErrorCode::kNoSuchEdge, what(),
                  "there is no twist edge " + std::string(relative_to) + " -> " + text::Frame(t, h) +
                      (!edge.is_valid() ? " (" + text::Frame(t, h) + " has no twist parent)"
                                        : " (its twist parent is " + std::string(t.body_name(t.twist_edge(edge).tail)) +
                                              ")"));
  }
  if (const internal::JointRecord* j = joints_.OfChild(h)) {
    return Reject(ErrorCode::kJointEdge, what(),
                  "it is the twist edge of joint " + j->name + "; remove the joint's pose edge to remove the joint");
  }
  topology_.UnlinkTwist(edge);
  values_.V_DH[edge.value()].BumpEpoch();  // compiled queries and handles using this edge become invalid
  DropTwistHistory(edge);
  return Ok{};
}

#define SEMGRAPH_INSTANTIATE_ADD(B)                                                                         \
  template void SceneGraph<B>::Reserve(std::size_t, std::size_t);                                           \
  template FrameIndex SceneGraph<B>::CreateFrame(NameId, BodyIndex);                                        \
  template BuildResult SceneGraph<B>::AddBody(std::string_view);                                            \
  template BuildResult SceneGraph<B>::AddFrame(std::string_view, std::string_view);                         \
  template BuildResult SceneGraph<B>::AddPose(const PoseSpec&, const Eigen::Quaterniond&,                   \
                                              const Eigen::Vector3d&);                                      \
  template BuildResult SceneGraph<B>::AddPose(const PoseSpec&, const Eigen::Matrix3d&, const Eigen::Vector3d&); \
  template BuildResult SceneGraph<B>::AddTwist(const TwistSpec&, const Eigen::Vector3d&, const Eigen::Vector3d&); \
  template BuildResult SceneGraph<B>::AddPose(const PoseSpec&, const Eigen::Quaterniond&, const Eigen::Vector3d&, Stamp); \
  template BuildResult SceneGraph<B>::AddPose(const PoseSpec&, const Eigen::Matrix3d&, const Eigen::Vector3d&, Stamp); \
  template BuildResult SceneGraph<B>::AddTwist(const TwistSpec&, const Eigen::Vector3d&, const Eigen::Vector3d&, Stamp); \
  template BuildResult SceneGraph<B>::AddTwistImpl(const TwistSpec&, const Eigen::Vector3d&, const Eigen::Vector3d&, \
                                                   std::optional<Stamp>);                                   \
  template BuildResult SceneGraph<B>::RemovePose(std::string_view, std::string_view);                       \
  template BuildResult SceneGraph<B>::RemoveTwist(std::string_view, std::string_view);
SEMGRAPH_INSTANTIATE_ADD(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_ADD(coord::HomogeneousBackend)

}  // namespace semgraph::core
