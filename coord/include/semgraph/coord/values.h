// File: semgraph/coord/values.h
//
// Checked relation values: semantics + coordinates. Build them with the Make* functions of
// validate.h (which validate numbers and the representation's constraints); transform them with
// the checked operations of operations.h.
//
//   Position            value = p: position of point e wrt point f, expressed in [r]
//   Orientation<B>      value = M: operator carrying [b] onto [a], expressed in [r]
//                       (= R[b<-a] when [r] = [b])
//   Pose<B>             value = (M, p) in one B::PoseCoords; ToIsometry / FromIsometry convert
//                       to and from Eigen::Isometry3d
//   LinearVelocity      value = v of point e fixed to C, relative to D, in [r]
//   AngularVelocity     value = w of C relative to D, in [r]
//   Twist               linear = v (of the velocity reference point), angular = w, both in [r]
//   Acceleration        linear = a (classical, of the point of C at e), angular = alpha, in [r]
//   Wrench              force = f, moment = m about the point e, both in [r]
//   Power               value = f.v + m.w, the power delivered to C by D (W)
//
// Positions, velocities, twists, accelerations and wrenches are 3-vectors in every backend (no
// constraints), so they are not templates. Invariant (established by Make*, kept by every
// operation): numbers are finite, rotations proper and normalized, semantics admitted by the
// backend. Cost: fixed-size values, trivially copyable, no allocation.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "semgraph/base/expected.h"
#include "semgraph/coord/backend.h"
#include "semgraph/coord/error.h"
#include "semgraph/semantics/relations.h"

namespace semgraph::coord {

using semantics::AccelerationSemantics;
using semantics::AngularVelocitySemantics;
using semantics::LinearVelocitySemantics;
using semantics::OrientationSemantics;
using semantics::PoseSemantics;
using semantics::PositionSemantics;
using semantics::PowerSemantics;
using semantics::TwistSemantics;
using semantics::WrenchSemantics;

struct Position {
  PositionSemantics semantics;
  Eigen::Vector3d value;
};

template <Backend B>
struct Orientation {
  OrientationSemantics semantics;
  typename B::Rotation value;
};

template <Backend B>
struct Pose {
  PoseSemantics semantics;
  typename B::PoseCoords value;

  /// The value as an Eigen isometry: linear() = M, translation() = p (both in [r]), e.g.
  /// X_BA for PoseSpec::Of("a").RelativeTo("b"). O(1).
  [[nodiscard]] Eigen::Isometry3d ToIsometry() const noexcept {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = B::ToMatrix(B::RotationOf(value));
    X.translation() = B::TranslationOf(value);
    return X;
  }
  /// A checked pose from an isometry, as MakePose(s, X.linear(), X.translation()) (validate.h):
  /// invalid_number -> invalid_rotation -> representation_constraint. O(1) (one 3x3 SVD when
  /// the rotation is not orthonormal to rounding).
  [[nodiscard]] static base::Expected<Pose, Error> FromIsometry(
      const PoseSemantics& s, const Eigen::Isometry3d& X) noexcept;
};

struct LinearVelocity {
  LinearVelocitySemantics semantics;
  Eigen::Vector3d value;
};

struct AngularVelocity {
  AngularVelocitySemantics semantics;
  Eigen::Vector3d value;
};

struct Twist {
  TwistSemantics semantics;
  Eigen::Vector3d linear;
  Eigen::Vector3d angular;
};

struct Acceleration {
  AccelerationSemantics semantics;
  Eigen::Vector3d linear;   // a
  Eigen::Vector3d angular;  // alpha
};

struct Wrench {
  WrenchSemantics semantics;
  Eigen::Vector3d force;   // f
  Eigen::Vector3d moment;  // m, about semantics.point
};

struct Power {
  PowerSemantics semantics;
  double value = 0.0;
};

}  // namespace semgraph::coord

// Pose<B>::FromIsometry is defined with the checked constructors it uses.
#include "semgraph/coord/validate.h"
