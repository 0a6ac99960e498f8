// Acceleration adds (scene_graph.h "accelerations"; contract: accelerations.h): a twist with
// its acceleration, and an acceleration on its own, converted to the edge form
// AccelerationCoord(h|H, D, [h]) with the current poses and the edge's twist, or, stamped (docs/
// dynamics.md, "Stamped accelerations"), with the poses at the stamp and the twist sample of that
// stamp. Every check runs before the only change (one record or sample store), so a rejected
// call leaves the graph as it was.
#include <string>

#include "semgraph/core/scene_graph.h"
#include "text.h"

namespace semgraph::core {

using text::Reject;

namespace {

std::string AccelerationAdd(const TwistSpec& spec) {
  return "acceleration of " + std::string(spec.point) +
         (spec.body.empty() ? "" : "|" + std::string(spec.body)) + " wrt " +
         std::string(spec.ref_body) + " in [" + std::string(spec.coordinate_frame) + "]";
}

// The twist edge between C and D in the pose tree of e (at most one: W3), or invalid: D -> {h}|C
// (along the relation C wrt D) or C -> {h}|D (`against`: the edge holds the inverse). O(1).
TwistEdgeIndex EdgeBetween(const topology::SceneTopology& t, FrameIndex e, BodyIndex C, BodyIndex D,
                           bool& against) noexcept {
  const topology::TreeRecord* rec = t.RecordOf(e);
  if (rec == nullptr || C == D) return {};
  const topology::TwistForest& tg = rec->twists;
  TwistEdgeIndex edge;
  if (tg.parent(C) == D) {
    edge = tg.parent_edge(C);
  } else if (tg.parent(D) == C) {
    edge = tg.parent_edge(D);
  }
  if (!edge.is_valid()) return {};
  const auto& ends = t.twist_edge(edge);
  against = ends.tail == C && t.body_of(ends.head) == D;
  return against || (ends.tail == D && t.body_of(ends.head) == C) ? edge : TwistEdgeIndex();
}

}  // namespace

template <coord::Backend B>
BuildResult SceneGraph<B>::AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                                    const Eigen::Vector3d& w_angular,
                                    const AccelerationInput& acceleration) {
  return AddTwistImpl(spec, v_linear, w_angular, std::nullopt, nullptr, &acceleration);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                                    const Eigen::Vector3d& w_angular, Stamp stamp,
                                    const AccelerationInput& acceleration) {
  return AddTwistImpl(spec, v_linear, w_angular, stamp, nullptr, &acceleration);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddAcceleration(const TwistSpec& spec, const Eigen::Vector3d& a_linear,
                                           const Eigen::Vector3d& alpha_angular) {
  return AddAccelerationImpl(spec, a_linear, alpha_angular, std::nullopt);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddAcceleration(const TwistSpec& spec, const Eigen::Vector3d& a_linear,
                                           const Eigen::Vector3d& alpha_angular, Stamp stamp) {
  return AddAccelerationImpl(spec, a_linear, alpha_angular, stamp);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddAccelerationImpl(const TwistSpec& spec,
                                               const Eigen::Vector3d& a_linear,
                                               const Eigen::Vector3d& alpha_angular,
                                               std::optional<Stamp> stamp) {
  const topology::SceneTopology& t = topology_;
  const auto what = [&spec] { return AccelerationAdd(spec); };  // formatted only on rejection
  // invalid_name: point, ref_body, coord required; body optional.
  const struct {
    std::string_view name;
    const char* field;
    bool required;
  } fields[] = {{spec.point, "point", true},
                {spec.body, "body", false},
                {spec.ref_body, "ref_body", true},
                {spec.coordinate_frame, "coord", true}};
  for (const auto& f : fields) {
    if (f.name.empty() && !f.required) continue;
    if (!t.names().Find(f.name).is_valid() && !semantics::ValidateName(f.name)) {
      return Reject(ErrorCode::kInvalidName, what(),
                    std::string(f.field) + ": the name is missing or invalid");
    }
  }
  auto a = coord::ValidateVector(a_linear, coord::ValueRole::kLinearAcceleration);
  if (!a) return Reject(a.error().code, what(), coord::Describe(a.error(), names()));
  auto alpha = coord::ValidateVector(alpha_angular, coord::ValueRole::kAngularAcceleration);
  if (!alpha) return Reject(alpha.error().code, what(), coord::Describe(alpha.error(), names()));
  // Node resolution: unknown_frame (point, coord) -> unknown_body (body, ref_body).
  const FrameIndex e = t.FindFrame(spec.point), r = t.FindFrame(spec.coordinate_frame);
  if (!e.is_valid()) {
    return Reject(ErrorCode::kUnknownFrame, what(),
                  "point: no frame named " + std::string(spec.point));
  }
  if (!r.is_valid()) {
    return Reject(ErrorCode::kUnknownFrame, what(),
                  "coord: no frame named " + std::string(spec.coordinate_frame));
  }
  const BodyIndex C = spec.body.empty() ? t.body_of(e) : t.FindBody(spec.body);
  if (!C.is_valid()) {
    return Reject(ErrorCode::kUnknownBody, what(), "body: no body named " + std::string(spec.body));
  }
  const BodyIndex D = t.FindBody(spec.ref_body);
  if (!D.is_valid()) {
    return Reject(ErrorCode::kUnknownBody, what(),
                  "ref_body: no body named " + std::string(spec.ref_body));
  }
  // no_such_edge -> joint_edge -> stamp_mismatch -> acceleration_not_convertible.
  bool against = false;
  const TwistEdgeIndex edge = EdgeBetween(t, e, C, D, against);
  if (!edge.is_valid()) {
    return Reject(ErrorCode::kNoSuchEdge, what(),
                  "no twist edge between " + std::string(t.body_name(D)) + " and " +
                      std::string(t.body_name(C)) + " (in either direction) in the pose tree of {" +
                      std::string(spec.point) + "}; add the twist first");
  }
  const FrameIndex h = t.twist_edge(edge).head;
  const BodyIndex tail = t.twist_edge(edge).tail;
  if (const internal::JointRecord* j = joints_.OfChild(h)) {
    return Reject(ErrorCode::kJointEdge, what(),
                  "the twist edge " + std::string(t.body_name(tail)) + " -> " + text::Frame(t, h) +
                      " belongs to joint " + std::string(joints_.name(*j)));
  }
  const TwistHistory* history = values_.history.twist_of(edge.value());
  if ((history != nullptr) != stamp.has_value()) {
    return Reject(ErrorCode::kStampMismatch, what(),
                  DescribeSampleRejection(ErrorCode::kStampMismatch, true, edge.value(), stamp));
  }
  if (!t.SameTree(r, h)) {
    return Reject(ErrorCode::kAccelerationNotConvertible, what(),
                  "coordinate frame [" + std::string(spec.coordinate_frame) +
                      "] is not in the pose tree of the twist edge's head " + text::Frame(t, h));
  }
  // The twist it goes with: the edge's, or its sample at the stamp (no interpolated twist: the
  // acceleration is stored with a sample).
  TwistNumbers V = values_.V_DH[edge.value()].Load();
  if (history != nullptr) {
    double w[6];
    if (!history->ValueAt(stamp->nanoseconds(), w)) {
      return Reject(ErrorCode::kAccelerationNotConvertible, what(),
                    "the twist edge " + std::string(t.body_name(tail)) + " -> " +
                        text::Frame(t, h) + " has no twist sample at " +
                        text::StampText(stamp->nanoseconds()) + " (samples in " +
                        text::StampRange(history->oldest_stamp(), history->newest_stamp()) +
                        "); a stamped acceleration belongs to the twist sample of its stamp");
    }
    V = internal::TwistFromWords(w);
  }
  // The edge form: [r] -> [h] (R_HR), then the point e -> h with the given relation's angular
  // velocity (+-w_DH: the shift's w x (w x .) is even in w), then, against the edge, the inverse
  // relation at h (alpha' = -alpha, a' = -a + 2 w' x v', (v', w') = -(v, w) its twist at h).
  // A stamped value: with the poses at its stamp.
  internal::TimeContext at_stamp = ConversionContext(stamp);
  const internal::ForestSource<B> src(topology_, values_, stamp ? &at_stamp : nullptr);
  typename B::PoseCoords X_HR, X_HE;  // [r] wrt [h] and e wrt h, in [h]
  internal::EvalBasic<B>(src, PlanBasic(t, r, h), X_HR);
  internal::EvalBasic<B>(src, PlanBasic(t, e, h), X_HE);
  if (at_stamp.error() != ErrorCode::kOk) {
    return Reject(ErrorCode::kAccelerationNotConvertible, what(),
                  DescribeConversionGap(at_stamp, *stamp));
  }
  const typename B::Rotation R_HR = B::RotationOf(X_HR);
  AccelerationNumbers A{B::Rotate(R_HR, *a), B::Rotate(R_HR, *alpha)};
  // p_A = old point - new point = e - h = p_HE.
  A.a_DHo_H =
      coord::kernels::ShiftAcceleration(A.a_DHo_H, A.alpha_DH_H, V.w_DH_H, B::TranslationOf(X_HE));
  if (against) {
    const auto inv =
        coord::kernels::InvertAcceleration(A.a_DHo_H, A.alpha_DH_H, -V.v_DHo_H, -V.w_DH_H);
    A = AccelerationNumbers{inv.linear, inv.angular};
  }
  if (history == nullptr) {
    values_.StoreAcceleration(edge.value(), V, &A);
    return Ok{};
  }
  values_.ReserveTwistSampleAccelerations(edge.value());  // may throw: nothing changed yet
  if (const ErrorCode code = StoreSampleAcceleration(edge, *stamp, A); code != ErrorCode::kOk) {
    return Reject(code, what(), DescribeSampleRejection(code, true, edge.value(), stamp));
  }
  return Ok{};
}

// A stamped acceleration's store: the duplicate rule of a value at a stored stamp (another
// acceleration there, under the reject policy: duplicate_stamp), then the sample's words and,
// for the newest sample, the edge's acceleration record. The caller found the sample and
// reserved the history's acceleration words (the real-time SetAcceleration shares it).
template <coord::Backend B>
ErrorCode SceneGraph<B>::StoreSampleAcceleration(TwistEdgeIndex edge, Stamp stamp,
                                                 const AccelerationNumbers& A) noexcept {
  TwistHistory& h = values_.history.twist.writable(edge.value());
  const std::int64_t s = stamp.nanoseconds();
  double stored[7], a[7], w[6];
  internal::WordsFromAcceleration(A, a);
  if (h.AccelerationAt(s, stored) && stored[6] != 0.0) {
    if (SameSampleAcceleration(h, s, a)) return ErrorCode::kOk;
    if (values_.history.options.duplicate_stamp == DuplicatePolicy::kReject) {
      return ErrorCode::kDuplicateStamp;
    }
  }
  if (!h.SetAccelerationAt(s, a)) return ErrorCode::kStampMismatch;
  if (s == h.newest_stamp() && h.ValueAt(s, w)) {
    values_.StoreAcceleration(edge.value(), internal::TwistFromWords(w), &A);
  }
  return ErrorCode::kOk;
}

#define SEMGRAPH_INSTANTIATE_ACCELERATIONS(B)                                                     \
  template BuildResult SceneGraph<B>::AddTwist(const TwistSpec&, const Eigen::Vector3d&,          \
                                               const Eigen::Vector3d&, const AccelerationInput&); \
  template BuildResult SceneGraph<B>::AddTwist(const TwistSpec&, const Eigen::Vector3d&,          \
                                               const Eigen::Vector3d&, Stamp,                     \
                                               const AccelerationInput&);                         \
  template BuildResult SceneGraph<B>::AddAcceleration(const TwistSpec&, const Eigen::Vector3d&,   \
                                                      const Eigen::Vector3d&);                    \
  template BuildResult SceneGraph<B>::AddAcceleration(const TwistSpec&, const Eigen::Vector3d&,   \
                                                      const Eigen::Vector3d&, Stamp);             \
  template BuildResult SceneGraph<B>::AddAccelerationImpl(                                        \
      const TwistSpec&, const Eigen::Vector3d&, const Eigen::Vector3d&, std::optional<Stamp>);    \
  template ErrorCode SceneGraph<B>::StoreSampleAcceleration(TwistEdgeIndex, Stamp,                \
                                                            const AccelerationNumbers&) noexcept;
SEMGRAPH_INSTANTIATE_ACCELERATIONS(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_ACCELERATIONS(coord::HomogeneousBackend)

}  // namespace semgraph::core
