// Time on the write side (docs/time.md): graph options, the stamp rules of a value update
// (stamp_mismatch -> stamp_too_old -> duplicate_stamp), histories made, filled and dropped, and
// the messages of those rejections. Check* never change anything; Store* never allocate.
// A sample's covariance (docs/uncertainty.md, "Time") is part of its value for the duplicate
// rule, stored beside it in the history (edge_history.h) and, for the newest sample, in the
// edge's covariance record (the untimed readers' value, edge_values.h). A twist sample's
// acceleration (docs/dynamics.md, "Stamped accelerations") likewise: part of its value, beside it
// in the history, and the newest sample's in the edge's acceleration record.
#include <cinttypes>
#include <cmath>
#include <cstdio>

#include "covariance_input.h"
#include "sample_rules.h"
#include "semgraph/core/scene_graph.h"
#include "text.h"

namespace semgraph::core {

using base::Unexpected;

__extension__ typedef __int128 Int128;  // GCC and clang; exact products of a mantissa and 1e9

std::optional<std::int64_t> NanosecondsFromSeconds(double seconds) noexcept {
  if (!std::isfinite(seconds) || std::abs(seconds) > kMaxStampSeconds) return std::nullopt;
  // Exactly: seconds = m * 2^e with an integer mantissa m (53 bits); ns = m * 1e9 * 2^e, rounded
  // to nearest with ties away from zero, in 128-bit integers (1e9 * m < 2^83).
  int e = 0;
  const double frac =
      std::frexp(std::abs(seconds), &e);  // |seconds| = frac * 2^e, frac in [0.5, 1)
  const auto m = static_cast<Int128>(std::ldexp(frac, 53));  // exact
  e -= 53;
  Int128 ns = m * 1000000000;
  if (e >= 0) {
    ns <<= e;  // |seconds| >= 2^53 s never passes the range check; kept for completeness
  } else if (e > -127) {
    const Int128 half = static_cast<Int128>(1) << (-e - 1);
    ns = (ns + half) >> -e;  // round half up on the magnitude = ties away from zero
  } else {
    ns = 0;
  }
  const auto r = static_cast<std::int64_t>(ns);
  return seconds < 0 ? -r : r;
}

namespace {
std::string Seconds(std::int64_t ns) { return text::StampText(ns); }

// P4's tolerance for poses; for twists, each vector within 1e-6 max(1, |stored|).
template <coord::Backend B>
bool SamePose(const double (&stored)[7], const typename B::PoseCoords& X) {
  const auto S = internal::PoseFromWords(stored);
  const Eigen::Matrix3d dR =
      S.q.toRotationMatrix() - B::ToQuaternion(B::RotationOf(X)).toRotationMatrix();
  return dR.cwiseAbs().maxCoeff() <= 1e-6 &&
         (S.p - B::TranslationOf(X)).norm() <= 1e-6 * std::max(1.0, S.p.norm());
}
bool SameTwist(const double (&stored)[6], const TwistNumbers& V) {
  const TwistNumbers S = internal::TwistFromWords(stored);
  return (S.v_DHo_H - V.v_DHo_H).norm() <= 1e-6 * std::max(1.0, S.v_DHo_H.norm()) &&
         (S.w_DH_H - V.w_DH_H).norm() <= 1e-6 * std::max(1.0, S.w_DH_H.norm());
}
template <coord::Backend B>
void PoseWords(const typename B::PoseCoords& X, double (&w)[7]) {
  internal::WordsFromPose(B::ToQuaternion(B::RotationOf(X)), B::TranslationOf(X), w);
}
}  // namespace

template <coord::Backend B>
Expected<SceneGraph<B>, BuildError> SceneGraph<B>::Create(const TimeOptions& options) {
  if (options.window.nanoseconds() <= 0) {
    return Unexpected{BuildError{
        ErrorCode::kInvalidNumber,
        "time options rejected (invalid_number): the history window must be a positive time, "
        "not " +
            Seconds(options.window.nanoseconds())}};
  }
  if (options.sample_capacity < 2 || options.sample_capacity > (1u << 30)) {
    return Unexpected{BuildError{
        ErrorCode::kInvalidNumber,
        "time options rejected (invalid_number): the sample capacity per edge must be in "
        "[2, 2^30], not " +
            std::to_string(options.sample_capacity)}};
  }
  SceneGraph g;
  g.values_.history.options = options;
  return g;
}

// ---------------------------------------------------------------- conversions at a stamp

template <coord::Backend B>
internal::TimeContext SceneGraph<B>::ConversionContext(std::optional<Stamp> stamp) const noexcept {
  internal::TimeContext tc;
  tc.at = true;
  tc.t = stamp ? stamp->nanoseconds() : 0;
  tc.histories = &values_.history;
  tc.topology = &topology_;
  return tc;
}

template <coord::Backend B>
std::string SceneGraph<B>::DescribeConversionGap(const internal::TimeContext& tc,
                                                 Stamp stamp) const {
  const internal::TimeFailure& f = tc.failure();
  std::string edge;
  if (f.twist_edge) {
    const auto& e = topology_.twist_edge(TwistEdgeIndex(f.index));
    edge = "twist of " + text::Frame(topology_, e.head) + " wrt " +
           std::string(topology_.body_name(e.tail));
  } else {
    const FrameIndex h(f.index);
    edge = "pose of " + text::Frame(topology_, h) + " wrt " +
           text::Frame(topology_, topology_.pose_parent(h));
  }
  return "the value is converted with the graph's values at its stamp " +
         Seconds(stamp.nanoseconds()) + ", but the " + edge + " has samples in " +
         text::StampRange(f.first, f.last);
}

// ---------------------------------------------------------------- histories

// A retired history is reused (no allocation in a loop that removes and re-adds stamped edges);
// see HistoryTable (edge_history.h) for why readers may still hold a retired one.
template <coord::Backend B>
PoseHistoryLease SceneGraph<B>::NewPoseHistory() {
  return values_.history.pose.New(values_.history.options.sample_capacity);
}

template <coord::Backend B>
TwistHistoryLease SceneGraph<B>::NewTwistHistory() {
  return values_.history.twist.New(values_.history.options.sample_capacity);
}

template <coord::Backend B>
void SceneGraph<B>::InstallPoseHistory(FrameIndex head, PoseHistoryLease h,
                                       const typename B::PoseCoords& X, Stamp s,
                                       const coord::Covariance6* S) {
  double w[7], c[21];
  PoseWords<B>(X, w);
  if (S) internal::WordsFromCovariance(*S, c);
  values_.history.pose.Install(head.value(), std::move(h), s.nanoseconds(), w, S ? c : nullptr);
}

template <coord::Backend B>
void SceneGraph<B>::InstallTwistHistory(TwistEdgeIndex edge, TwistHistoryLease h,
                                        const TwistNumbers& V, Stamp s, const coord::Covariance6* S,
                                        const AccelerationNumbers* A) {
  double w[6], c[21], a[7];
  internal::WordsFromTwist(V, w);
  if (S) internal::WordsFromCovariance(*S, c);
  if (A) internal::WordsFromAcceleration(*A, a);
  values_.history.twist.Install(edge.value(), std::move(h), s.nanoseconds(), w, S ? c : nullptr,
                                A ? a : nullptr);
}

// Room for a covariance with the next sample of a stamped edge (a history's covariance array,
// the edge's record); nothing for a timeless edge but the record. May throw: nothing changed.
template <coord::Backend B>
void SceneGraph<B>::ReservePoseSampleCovariance(FrameIndex head) {
  values_.ReservePoseCovariances(head.value() + 1);
  values_.ReservePoseSampleCovariances(head.value());
}

template <coord::Backend B>
void SceneGraph<B>::ReserveTwistSampleCovariance(TwistEdgeIndex edge) {
  values_.ReserveTwistCovariances(edge.value() + 1);
  values_.ReserveTwistSampleCovariances(edge.value());
}

// The caller bumped the edge's epoch first: a reader that sees the retirement (or a reuse) sees
// the new epoch too.
template <coord::Backend B>
void SceneGraph<B>::DropPoseHistory(FrameIndex head) noexcept {
  values_.history.pose.Retire(head.value());
}

template <coord::Backend B>
void SceneGraph<B>::DropTwistHistory(TwistEdgeIndex edge) noexcept {
  values_.history.twist.Retire(edge.value());
}

// ---------------------------------------------------------------- the stamp rules of an update

template <coord::Backend B>
ErrorCode SceneGraph<B>::CheckPoseSample(FrameIndex head, const typename B::PoseCoords& X,
                                         std::optional<Stamp> stamp,
                                         const coord::Covariance6* S) const noexcept {
  return internal::CheckSample(values_.history.pose_of(head.value()), stamp,
                               values_.history.options, S, nullptr,
                               [&](const double(&w)[7]) { return SamePose<B>(w, X); });
}

template <coord::Backend B>
void SceneGraph<B>::StorePoseSample(FrameIndex head, const typename B::PoseCoords& X,
                                    std::optional<Stamp> stamp,
                                    const coord::Covariance6* S) noexcept {
  internal::StoreSample(
      values_.X_PF[head.value()], X, stamp, values_.history.options.window.nanoseconds(), S,
      nullptr, [&]() -> PoseHistory& { return values_.history.pose.writable(head.value()); },
      [&](const double(&w)[7]) { return SamePose<B>(w, X); },
      [&](double(&w)[7]) { PoseWords<B>(X, w); },
      [&] { values_.StorePoseCovariance(head.value(), X, S); });
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::CheckTwistSample(TwistEdgeIndex edge, const TwistNumbers& V,
                                          std::optional<Stamp> stamp, const coord::Covariance6* S,
                                          const AccelerationNumbers* A) const noexcept {
  double a[7];
  if (A) internal::WordsFromAcceleration(*A, a);
  return internal::CheckSample(values_.history.twist_of(edge.value()), stamp,
                               values_.history.options, S, A ? a : nullptr,
                               [&](const double(&w)[6]) { return SameTwist(w, V); });
}

template <coord::Backend B>
void SceneGraph<B>::StoreTwistSample(TwistEdgeIndex edge, const TwistNumbers& V,
                                     std::optional<Stamp> stamp, const coord::Covariance6* S,
                                     const AccelerationNumbers* A) noexcept {
  double a[7];
  if (A) internal::WordsFromAcceleration(*A, a);
  internal::StoreSample(
      values_.V_DH[edge.value()], V, stamp, values_.history.options.window.nanoseconds(), S,
      A ? a : nullptr,
      [&]() -> TwistHistory& { return values_.history.twist.writable(edge.value()); },
      [&](const double(&w)[6]) { return SameTwist(w, V); },
      [&](double(&w)[6]) { internal::WordsFromTwist(V, w); },
      [&] {
        // The acceleration record first (edge_values.h): a twist without one clears it.
        values_.StoreAcceleration(edge.value(), V, A);
        values_.StoreTwistCovariance(edge.value(), V, S);
      });
}

template <coord::Backend B>
std::string SceneGraph<B>::DescribeSampleRejection(ErrorCode code, bool twist, std::uint32_t index,
                                                   std::optional<Stamp> stamp) const {
  std::string edge;
  std::int64_t first = 0, last = 0;
  bool stamped = false;
  if (twist) {
    const auto& e = topology_.twist_edge(TwistEdgeIndex(index));
    edge = "the twist edge " + std::string(topology_.body_name(e.tail)) + " -> " +
           text::Frame(topology_, e.head);
    if (const TwistHistory* h = values_.history.twist_of(index)) {
      stamped = true;
      first = h->oldest_stamp();
      last = h->newest_stamp();
    }
  } else {
    const FrameIndex h(index);
    edge = "the pose edge " + text::Frame(topology_, topology_.pose_parent(h)) + " -> " +
           text::Frame(topology_, h);
    if (const PoseHistory* p = values_.history.pose_of(index)) {
      stamped = true;
      first = p->oldest_stamp();
      last = p->newest_stamp();
    }
  }
  const std::string range = text::StampRange(first, last);
  switch (code) {
    case ErrorCode::kStampMismatch:
      return stamped
                 ? edge + " is stamped (samples in " + range + "): its values need a stamp"
                 : edge + " is timeless (its first value had no stamp): it takes no stamped value";
    case ErrorCode::kStampTooOld:
      return "stamp " + Seconds(stamp->nanoseconds()) + " is older than the newest sample of " +
             edge + " (" + Seconds(last) + ") minus the window (" +
             Seconds(values_.history.options.window.nanoseconds()) + ")";
    case ErrorCode::kDuplicateStamp:
      return edge + " already has another value at " + Seconds(stamp->nanoseconds()) +
             " (duplicate stamps are rejected by this graph's policy)";
    default:
      return std::string(base::ToString(code));
  }
}

#define SEMGRAPH_INSTANTIATE_TIME_ADD(B)                                                          \
  template Expected<SceneGraph<B>, BuildError> SceneGraph<B>::Create(const TimeOptions&);         \
  template internal::TimeContext SceneGraph<B>::ConversionContext(std::optional<Stamp>)           \
      const noexcept;                                                                             \
  template std::string SceneGraph<B>::DescribeConversionGap(const internal::TimeContext&, Stamp)  \
      const;                                                                                      \
  template PoseHistoryLease SceneGraph<B>::NewPoseHistory();                                      \
  template TwistHistoryLease SceneGraph<B>::NewTwistHistory();                                    \
  template void SceneGraph<B>::InstallPoseHistory(FrameIndex, PoseHistoryLease,                   \
                                                  const typename B::PoseCoords&, Stamp,           \
                                                  const coord::Covariance6*);                     \
  template void SceneGraph<B>::InstallTwistHistory(                                               \
      TwistEdgeIndex, TwistHistoryLease, const TwistNumbers&, Stamp, const coord::Covariance6*,   \
      const AccelerationNumbers*);                                                                \
  template void SceneGraph<B>::ReservePoseSampleCovariance(FrameIndex);                           \
  template void SceneGraph<B>::ReserveTwistSampleCovariance(TwistEdgeIndex);                      \
  template void SceneGraph<B>::DropPoseHistory(FrameIndex) noexcept;                              \
  template void SceneGraph<B>::DropTwistHistory(TwistEdgeIndex) noexcept;                         \
  template ErrorCode SceneGraph<B>::CheckPoseSample(                                              \
      FrameIndex, const typename B::PoseCoords&, std::optional<Stamp>, const coord::Covariance6*) \
      const noexcept;                                                                             \
  template void SceneGraph<B>::StorePoseSample(FrameIndex, const typename B::PoseCoords&,         \
                                               std::optional<Stamp>,                              \
                                               const coord::Covariance6*) noexcept;               \
  template ErrorCode SceneGraph<B>::CheckTwistSample(                                             \
      TwistEdgeIndex, const TwistNumbers&, std::optional<Stamp>, const coord::Covariance6*,       \
      const AccelerationNumbers*) const noexcept;                                                 \
  template void SceneGraph<B>::StoreTwistSample(TwistEdgeIndex, const TwistNumbers&,              \
                                                std::optional<Stamp>, const coord::Covariance6*,  \
                                                const AccelerationNumbers*) noexcept;             \
  template std::string SceneGraph<B>::DescribeSampleRejection(ErrorCode, bool, std::uint32_t,     \
                                                              std::optional<Stamp>) const;
SEMGRAPH_INSTANTIATE_TIME_ADD(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_TIME_ADD(coord::HomogeneousBackend)

}  // namespace semgraph::core
