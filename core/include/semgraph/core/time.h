// File: semgraph/core/time.h
//
// The words of time (docs/time.md): stamps and durations (integer nanoseconds, strong types),
// the graph's time options, the query time policies as explicit types, the twist source, and
// what every timed answer reports. No numbers of the scene here, no strings on query paths.
//
//   Stamp          a time, int64 nanoseconds on the user's clock (wall, sim, bag)
//   Duration       a signed span of nanoseconds (window, horizon)
//   TimeOptions    per graph: history window (default 10 s), interpolation (screw | linear),
//                  duplicate-stamp policy (replace | reject), per-edge sample capacity
//                  (default kDefaultSampleCapacity = 1024; preallocated when an edge becomes
//                  stamped, so stamped updates never allocate)
//   Latest, At, LatestCommon       the policies of one query (TimePolicy = one of them); At
//                  and LatestCommon take a horizon (max_extrapolation)
//   TimeTravel     point side at one time, reference side at another, through a fixed frame
//   TwistSource    twists from the twist edges (default) or by differentiating the pose history
//   TimeReport     the time answered, oldest / newest stamps read, extrapolated or not
//
// Invariants: all time comparisons are exact, in integer nanoseconds; seconds are converted
// once (StampFromSeconds: the double's value rounded to the nearest nanosecond, ties away
// from zero, exactly, not through a rounded product). Cost: O(1) plain values.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <variant>

#include "semgraph/base/expected.h"
#include "semgraph/coord/se3.h"
#include "semgraph/core/export.h"

namespace semgraph::core {

/// A span of time in nanoseconds.
class Duration {
 public:
  constexpr Duration() noexcept = default;
  [[nodiscard]] static constexpr Duration Nanoseconds(std::int64_t ns) noexcept {
    return Duration(ns);
  }
  [[nodiscard]] static constexpr Duration Milliseconds(std::int64_t ms) noexcept {
    return Duration(ms * 1000000);
  }
  [[nodiscard]] static constexpr Duration Seconds(std::int64_t s) noexcept {
    return Duration(s * 1000000000);
  }
  [[nodiscard]] constexpr std::int64_t nanoseconds() const noexcept { return ns_; }
  [[nodiscard]] constexpr double seconds() const noexcept {
    return static_cast<double>(ns_) * 1e-9;
  }
  friend constexpr auto operator<=>(Duration, Duration) noexcept = default;

 private:
  constexpr explicit Duration(std::int64_t ns) noexcept : ns_(ns) {}
  std::int64_t ns_ = 0;
};

/// A time in nanoseconds on the user's clock.
class Stamp {
 public:
  constexpr Stamp() noexcept = default;
  [[nodiscard]] static constexpr Stamp Nanoseconds(std::int64_t ns) noexcept { return Stamp(ns); }
  [[nodiscard]] constexpr std::int64_t nanoseconds() const noexcept { return ns_; }
  /// Seconds as a double (for printing: the nearest double).
  [[nodiscard]] constexpr double seconds() const noexcept {
    return static_cast<double>(ns_) * 1e-9;
  }
  friend constexpr auto operator<=>(Stamp, Stamp) noexcept = default;

 private:
  constexpr explicit Stamp(std::int64_t ns) noexcept : ns_(ns) {}
  std::int64_t ns_ = 0;
};

/// Largest accepted |time| in seconds: 9.2e9 s (9.2e18 ns fits int64 with margin for sums).
inline constexpr double kMaxStampSeconds = 9.2e9;
/// The same bound in nanoseconds, for stamps given as integers (the DDS wire).
inline constexpr std::int64_t kMaxStampNanoseconds = 9'200'000'000'000'000'000;
static_assert(kMaxStampSeconds * 1e9 == static_cast<double>(kMaxStampNanoseconds));

/// Seconds -> nanoseconds, rounded to nearest (ties away from zero), exactly. nullopt when the
/// value is not finite or |seconds| > kMaxStampSeconds (the caller reports invalid_number).
[[nodiscard]] SEMGRAPH_CORE_EXPORT std::optional<std::int64_t> NanosecondsFromSeconds(
    double seconds) noexcept;
[[nodiscard]] inline std::optional<Stamp> StampFromSeconds(double seconds) noexcept {
  auto ns = NanosecondsFromSeconds(seconds);
  if (!ns) return std::nullopt;
  return Stamp::Nanoseconds(*ns);
}
[[nodiscard]] inline std::optional<Duration> DurationFromSeconds(double seconds) noexcept {
  auto ns = NanosecondsFromSeconds(seconds);
  if (!ns) return std::nullopt;
  return Duration::Nanoseconds(*ns);
}

using coord::Interpolation;

/// What a sample at an existing stamp with another value does.
enum class DuplicatePolicy : std::uint8_t { kReplace, kReject };

inline constexpr std::size_t kDefaultSampleCapacity = 1024;

struct TimeOptions {
  Duration window = Duration::Seconds(10);  ///< samples older than newest - window are dropped
  Interpolation interpolation = Interpolation::kScrew;
  DuplicatePolicy duplicate_stamp = DuplicatePolicy::kReplace;
  std::size_t sample_capacity = kDefaultSampleCapacity;  ///< per stamped edge, >= 2
};

// ---------------------------------------------------------------- query policies

/// Each stamped edge's newest sample (the default).
struct Latest {
  constexpr explicit Latest(std::optional<Stamp> not_before_ = std::nullopt) noexcept
      : not_before(not_before_) {}
  std::optional<Stamp> not_before;  ///< a used edge whose newest sample is older: stale
};
/// Every edge at `time`; outside an edge's samples, extrapolate up to max_extrapolation.
struct At {
  constexpr explicit At(Stamp time_, Duration max_extrapolation_ = {},
                        std::optional<Stamp> not_before_ = std::nullopt) noexcept
      : time(time_), max_extrapolation(max_extrapolation_), not_before(not_before_) {}
  Stamp time;
  Duration max_extrapolation;  ///< 0: never extrapolate; negative: invalid_number
  std::optional<Stamp> not_before;
};
/// At the newest time all used stamped edges have (tf2's Time(0)), t*; then as At{t*}: an edge
/// whose samples start after t* is extrapolated (integrated back) up to max_extrapolation.
struct LatestCommon {
  constexpr explicit LatestCommon(std::optional<Stamp> not_before_ = std::nullopt) noexcept
      : not_before(not_before_) {}
  constexpr explicit LatestCommon(Duration max_extrapolation_,
                                  std::optional<Stamp> not_before_ = std::nullopt) noexcept
      : max_extrapolation(max_extrapolation_), not_before(not_before_) {}
  Duration max_extrapolation;  ///< 0: never extrapolate; negative: invalid_number
  std::optional<Stamp> not_before;
};
using TimePolicy = std::variant<Latest, At, LatestCommon>;

/// Pose, position, orientation: the point side at `time`, the reference side at `ref_time`,
/// through `fixed_frame`, assumed fixed between the two ([r] taken at ref_time).
struct TimeTravel {
  constexpr TimeTravel(Stamp time_, Stamp ref_time_, std::string_view fixed_frame_,
                       Duration max_extrapolation_ = {},
                       std::optional<Stamp> not_before_ = std::nullopt) noexcept
      : time(time_),
        ref_time(ref_time_),
        fixed_frame(fixed_frame_),
        max_extrapolation(max_extrapolation_),
        not_before(not_before_) {}
  Stamp time;
  Stamp ref_time;
  std::string_view fixed_frame;
  Duration max_extrapolation;
  std::optional<Stamp> not_before;
};

/// Where a twist query's twists come from.
enum class TwistSource : std::uint8_t {
  kTwists,  ///< the twist edges (the default)
  kPoses,   ///< the time derivative of the pose history (no twist edge read); never
            ///< extrapolates: the policy's horizon is ignored
};

/// What a timed answer reports. Fields that do not apply are empty.
struct TimeReport {
  std::optional<Stamp> time;      ///< the time answered (At; LatestCommon with a stamped edge)
  std::optional<Stamp> ref_time;  ///< TimeTravel: the reference side's time
  std::optional<Stamp> oldest;    ///< the oldest stamp of the samples read
  std::optional<Stamp> newest;    ///< the newest stamp of the samples read
  bool extrapolated = false;
};

template <class T>
struct Timed {
  T value;
  TimeReport time;
};

/// One edge a query used, with the samples it read (ExplainPose / ExplainTwist).
struct EdgeUse {
  enum class Kind : std::uint8_t { kPose, kTwist, kPoseDerivative };
  Kind kind = Kind::kPose;
  std::string_view of;                      ///< the edge's head frame
  std::string_view relative_to;             ///< the tail frame (pose) or tail body (twist)
  bool stamped = false;                     ///< false: timeless or constant
  std::optional<Stamp> first, last;         ///< the edge's whole sample range
  std::optional<Stamp> read_from, read_to;  ///< the samples read (one stamp, or the bracket)
  bool extrapolated = false;
};

}  // namespace semgraph::core
