// Converting handles: a conversion's plan flattened like a compiled query's, evaluated by the
// one evaluator (evaluate.h), and the SceneGraph calls that make and use them. Contract:
// converting_handles.h, scene_graph.h, docs/realtime.md.
#include "semgraph/core/converting_handles.h"

#include <type_traits>

#include "covariance_input.h"
#include "semgraph/core/propagate.h"
#include "semgraph/core/scene_graph.h"
#include "text.h"

namespace semgraph::core {

using base::Unexpected;
using text::Reject;

// ====================================================================== the handles

template <coord::Backend B>
ConvertingTwistHandle<B>::ConvertingTwistHandle(const topology::SceneTopology& t,
                                                const EdgeValues<B>& values, TwistHandle edge,
                                                FrameIndex h, FrameIndex r,
                                                const semantics::TwistSemantics& given)
    : CompiledQuery<B>(t, values), edge_(edge), change_frame_(r != h), semantics_(given) {
  if (change_frame_) rh_ = this->Flatten(t, PlanBasic(t, r, h));
}

template <coord::Backend B>
bool ConvertingTwistHandle<B>::ToEdgeFrame(Eigen::Vector3d& v, Eigen::Vector3d& w,
                                           Covariance6* S) const noexcept {
  if (!change_frame_) return true;
  typename B::PoseCoords X_HR;  // [r] wrt [h]: R_HR carries [r] coordinates into [h]
  if (!internal::EvalBasic<B>(this->source(), rh_, X_HR)) return false;
  const typename B::Rotation R_HR = B::RotationOf(X_HR);
  v = B::Rotate(R_HR, v);
  w = B::Rotate(R_HR, w);
  if (S != nullptr) {
    Covariance6 S_H = Covariance6::Zero();
    coord::jacobians::AddPropagated(coord::jacobians::Reexpress(B::ToMatrix(R_HR)), *S, S_H);
    *S = S_H;
  }
  return true;
}

template <coord::Backend B>
ConvertingPoseHandle<B>::ConvertingPoseHandle(const topology::SceneTopology& t,
                                              const EdgeValues<B>& values, PoseHandle edge,
                                              const PoseSteps<ForestChain>& steps,
                                              const semantics::PoseSemantics& given)
    : CompiledQuery<B>(t, values),
      edge_(edge),
      steps_(this->Flatten(t, steps)),
      semantics_(given) {}

template <coord::Backend B>
bool ConvertingPoseHandle<B>::ToEdgeForm(const typename B::PoseCoords& X_given,
                                         typename B::PoseCoords& X_BA) const noexcept {
  return internal::ToEdgeForm<B>(this->source(), steps_, X_given, X_BA);
}

template <coord::Backend B>
bool ConvertingPoseHandle<B>::ToEdgeForm(const typename B::PoseCoords& X_given,
                                         const coord::Covariance6& S_given,
                                         typename B::PoseCoords& X_BA,
                                         coord::Covariance6& S_BA) const noexcept {
  return ToEdgeForm(X_given, X_BA) &&
         internal::ToEdgeFormCovariance<B>(this->source(), steps_, X_BA, S_given, S_BA);
}

template class ConvertingTwistHandle<coord::QuaternionBackend>;
template class ConvertingTwistHandle<coord::HomogeneousBackend>;
template class ConvertingPoseHandle<coord::QuaternionBackend>;
template class ConvertingPoseHandle<coord::HomogeneousBackend>;

// ====================================================================== build time

template <coord::Backend B>
Expected<ConvertingTwistHandle<B>, BuildError> SceneGraph<B>::FindTwistEdge(
    std::string_view of, std::string_view relative_to, std::string_view expressed_in) const {
  const auto what = [&] {
    return "handle of the twist of " + std::string(of) + " wrt " + std::string(relative_to) +
           " in [" + std::string(expressed_in) + "]";
  };
  auto edge = FindTwistEdge(of, relative_to);
  if (!edge) return Unexpected{std::move(edge).error()};
  const topology::SceneTopology& t = topology_;
  const FrameIndex h = FindFrame(of), r = FindFrame(expressed_in);
  if (!r.is_valid()) {
    if (auto ok = semantics::ValidateName(expressed_in); !ok) {
      return Unexpected{Reject(ErrorCode::kInvalidName, what(),
                               "coordinate frame: " + semantics::Describe(ok.error(), expressed_in))
                            .error()};
    }
    return Unexpected{Reject(ErrorCode::kUnknownFrame, what(),
                             "frame {" + std::string(expressed_in) + "} does not exist")
                          .error()};
  }
  if (r != h && !t.SameTree(r, h)) {
    return Unexpected{Reject(ErrorCode::kTwistNotConvertible, what(),
                             "coordinate frame [" + std::string(expressed_in) +
                                 "] must be a frame in the pose tree of {" + std::string(of) + "}")
                          .error()};
  }
  const TwistEdgeIndex slot = t.twist_edge_of(h);
  const topology::TwistEdge& e = t.twist_edge(slot);
  const semantics::TwistSemantics given{t.FrameSem(h).origin(), t.BodyOfSem(h), t.BodySem(e.tail),
                                        t.FrameSem(r).axes()};
  return ConvertingTwistHandle<B>(t, values_, *edge, h, r, given);
}

template <coord::Backend B>
Expected<ConvertingPoseHandle<B>, BuildError> SceneGraph<B>::FindPoseEdge(
    const PoseSpec& spec) const {
  const auto what = [&] { return "handle of the " + text::PoseAdd(spec); };
  const topology::SceneTopology& t = topology_;
  // The names, bodies and trees as a query checks them: e, f and [r] in the trees of {a}, {b}.
  const auto plan = PlanPose(t, spec);
  if (!plan)
    return Unexpected{
        Reject(plan.error().code, what(), text::QueryReason(t, plan.error(), &spec)).error()};
  const semantics::PoseSemantics& s = plan->semantics;
  const FrameIndex a = t.FrameOfName(s.orientation.id()), b = t.FrameOfName(s.ref_orientation.id());
  auto edge = FindPoseEdge(t.frame_name(a), t.frame_name(b));
  if (!edge) return Unexpected{std::move(edge).error()};
  if (auto ok = coord::CheckRepresentation<B>(s); !ok) {
    return Unexpected{
        Reject(ErrorCode::kRepresentationConstraint, what(), coord::Describe(ok.error(), t.names()))
            .error()};
  }
  const FrameIndex e = t.FrameOfName(s.point.id()), f = t.FrameOfName(s.ref_point.id());
  const FrameIndex r = t.FrameOfName(s.coordinate_frame.id());
  // [r] below the edge (or {a} itself) would make the conversion read the value being set. (The
  // point and the reference point cannot be: they are joined to {a} and {b} through frames of
  // their own bodies, P3, which the edge between two bodies is not.)
  if (t.forest().IsAncestor(a, r)) {
    return Unexpected{Reject(ErrorCode::kPoseNotConvertible, what(),
                             "the coordinate frame " + text::Frame(t, r) + " lies below the edge " +
                                 text::Frame(t, b) + " -> " + text::Frame(t, a) +
                                 " itself, so converting from it would read the value being set")
                          .error()};
  }
  return ConvertingPoseHandle<B>(t, values_, *edge, PlanChanges(t, e, a, f, b, r), s);
}

// ====================================================================== real time

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetTwist(const ConvertingTwistHandle<B>& edge,
                                  const Eigen::Vector3d& v_DHo_R, const Eigen::Vector3d& w_DH_R,
                                  UpdateError* why) noexcept {
  using internal::Report;
  auto v = coord::ValidateVector(v_DHo_R, coord::ValueRole::kLinearVelocity);
  if (!v) return Report(why, v.error());
  auto w = coord::ValidateVector(w_DH_R, coord::ValueRole::kAngularVelocity);
  if (!w) return Report(why, w.error());
  Eigen::Vector3d v_DHo_H = *v, w_DH_H = *w;
  if (!edge.ToEdgeFrame(v_DHo_H, w_DH_H)) return Report(why, ErrorCode::kQueryInvalidated);
  return SetTwist(edge.edge(), v_DHo_H, w_DH_H, why);
}

// With a covariance of (v, w) in [r] (any order; a twist has no convention): rotated into [h]
// with the value, then written as SetTwist(edge.edge(), ..., covariance) writes (its checks).
template <coord::Backend B>
ErrorCode SceneGraph<B>::SetTwist(const ConvertingTwistHandle<B>& edge,
                                  const Eigen::Vector3d& v_DHo_R, const Eigen::Vector3d& w_DH_R,
                                  const CovarianceInput& covariance, UpdateError* why) noexcept {
  using internal::Report;
  if (covariance.matrix == nullptr) return SetTwist(edge, v_DHo_R, w_DH_R, why);
  auto v = coord::ValidateVector(v_DHo_R, coord::ValueRole::kLinearVelocity);
  if (!v) return Report(why, v.error());
  auto w = coord::ValidateVector(w_DH_R, coord::ValueRole::kAngularVelocity);
  if (!w) return Report(why, w.error());
  const coord::CovarianceCheck check = coord::CheckCovariance(*covariance.matrix);
  if (!check.ok()) return Report(why, check.error());
  if (covariance.convention != PoseCovarianceConvention::kCoordinates) {
    return Report(why, ErrorCode::kInvalidCovariance);  // a twist has no convention
  }
  Covariance6 S = internal::CoordinatesCovariance(covariance, Eigen::Matrix3d::Identity());
  Eigen::Vector3d v_DHo_H = *v, w_DH_H = *w;
  if (!edge.ToEdgeFrame(v_DHo_H, w_DH_H, &S)) return Report(why, ErrorCode::kQueryInvalidated);
  return SetTwist(edge.edge(), v_DHo_H, w_DH_H, CovarianceInput{&S}, why);
}

template <coord::Backend B>
template <class R>
ErrorCode SceneGraph<B>::SetConvertedPose(const ConvertingPoseHandle<B>& edge, const R& rotation,
                                          const Eigen::Vector3d& p, UpdateError* why) noexcept {
  using internal::Report;
  auto p_ok = coord::ValidateVector(p, coord::ValueRole::kPosition);
  if (!p_ok) return Report(why, p_ok.error());
  typename B::Rotation M;
  if constexpr (std::is_same_v<R, Eigen::Quaterniond>) {
    auto q_ok = coord::ValidateQuaternion(rotation);
    if (!q_ok) return Report(why, q_ok.error());
    M = B::FromQuaternion(*q_ok);
  } else {
    auto R_ok = coord::ValidateRotationMatrix(rotation);
    if (!R_ok) return Report(why, R_ok.error());
    M = B::FromMatrix(*R_ok);
  }
  typename B::PoseCoords X_BA;
  if (!edge.ToEdgeForm(B::MakePose(M, *p_ok), X_BA)) {
    return Report(why, ErrorCode::kQueryInvalidated);
  }
  // Through the plain handle, which checks it and normalizes the product as AddPose does.
  if constexpr (std::is_same_v<typename B::Rotation, Eigen::Quaterniond>) {
    return SetPose(edge.edge(), B::RotationOf(X_BA), B::TranslationOf(X_BA), why);
  } else {
    return SetPose(edge.edge(), Eigen::Matrix3d(B::ToMatrix(B::RotationOf(X_BA))),
                   B::TranslationOf(X_BA), why);
  }
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPose(const ConvertingPoseHandle<B>& edge, const Eigen::Quaterniond& q,
                                 const Eigen::Vector3d& p, UpdateError* why) noexcept {
  return SetConvertedPose(edge, q, p, why);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPose(const ConvertingPoseHandle<B>& edge, const Eigen::Matrix3d& R,
                                 const Eigen::Vector3d& p, UpdateError* why) noexcept {
  return SetConvertedPose(edge, R, p, why);
}

// With a covariance of the given pose (CovarianceInput: order and convention as AddPose's, the
// body convention for an edge-form handle only):
// converted with the value through the conversion's Jacobian, then written as SetPose(
// edge.edge(), ..., covariance) writes (its checks). Quaternion input, as the plain handles'.
template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPose(const ConvertingPoseHandle<B>& edge, const Eigen::Quaterniond& q,
                                 const Eigen::Vector3d& p, const CovarianceInput& covariance,
                                 UpdateError* why) noexcept {
  using internal::Report;
  if (covariance.matrix == nullptr) return SetConvertedPose(edge, q, p, why);
  auto p_ok = coord::ValidateVector(p, coord::ValueRole::kPosition);
  if (!p_ok) return Report(why, p_ok.error());
  auto q_ok = coord::ValidateQuaternion(q);
  if (!q_ok) return Report(why, q_ok.error());
  const coord::CovarianceCheck check = coord::CheckCovariance(*covariance.matrix);
  if (!check.ok()) return Report(why, check.error());
  if (covariance.convention == PoseCovarianceConvention::kBody && !edge.edge_form()) {
    return Report(why, ErrorCode::kInvalidCovariance);  // as AddPose: body is for edge forms
  }
  const Covariance6 S_given = internal::CoordinatesCovariance(covariance, q_ok->toRotationMatrix());
  typename B::PoseCoords X_BA;
  Covariance6 S_BA;
  if (!edge.ToEdgeForm(B::MakePose(B::FromQuaternion(*q_ok), *p_ok), S_given, X_BA, S_BA)) {
    return Report(why, ErrorCode::kQueryInvalidated);
  }
  // Through the plain handle, which checks both and normalizes the product as AddPose does.
  Eigen::Quaterniond q_BA;
  if constexpr (std::is_same_v<typename B::Rotation, Eigen::Quaterniond>) {
    q_BA = B::RotationOf(X_BA);
  } else {
    q_BA = Eigen::Quaterniond(B::ToMatrix(B::RotationOf(X_BA)));
  }
  return SetPose(edge.edge(), q_BA, B::TranslationOf(X_BA), CovarianceInput{&S_BA}, why);
}

#define SEMGRAPH_INSTANTIATE_CONVERTING(B)                                                     \
  template Expected<ConvertingTwistHandle<B>, BuildError> SceneGraph<B>::FindTwistEdge(        \
      std::string_view, std::string_view, std::string_view) const;                             \
  template Expected<ConvertingPoseHandle<B>, BuildError> SceneGraph<B>::FindPoseEdge(          \
      const PoseSpec&) const;                                                                  \
  template ErrorCode SceneGraph<B>::SetTwist(const ConvertingTwistHandle<B>&,                  \
                                             const Eigen::Vector3d&, const Eigen::Vector3d&,   \
                                             UpdateError*) noexcept;                           \
  template ErrorCode SceneGraph<B>::SetTwist(const ConvertingTwistHandle<B>&,                  \
                                             const Eigen::Vector3d&, const Eigen::Vector3d&,   \
                                             const CovarianceInput&, UpdateError*) noexcept;   \
  template ErrorCode SceneGraph<B>::SetPose(const ConvertingPoseHandle<B>&,                    \
                                            const Eigen::Quaterniond&, const Eigen::Vector3d&, \
                                            UpdateError*) noexcept;                            \
  template ErrorCode SceneGraph<B>::SetPose(const ConvertingPoseHandle<B>&,                    \
                                            const Eigen::Quaterniond&, const Eigen::Vector3d&, \
                                            const CovarianceInput&, UpdateError*) noexcept;    \
  template ErrorCode SceneGraph<B>::SetPose(const ConvertingPoseHandle<B>&,                    \
                                            const Eigen::Matrix3d&, const Eigen::Vector3d&,    \
                                            UpdateError*) noexcept;
SEMGRAPH_INSTANTIATE_CONVERTING(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_CONVERTING(coord::HomogeneousBackend)

}  // namespace semgraph::core
