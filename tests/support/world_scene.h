// File: tests/support/world_scene.h
//
// WorldScene: a seeded random *independent ground truth* for coordinate tests. It knows only
// absolute quantities in one world frame W and derives every relation directly from them with
// plain Eigen, never through semgraph operations, so a semgraph result can be checked against
// the physics rather than against another semgraph computation.
//
// The scene:
//   - K bodies B0 .. B(K-1), each with an absolute twist in W:
//       w_WB_W   angular velocity of the body relative to W, expressed in W;
//       v_WBo_W  linear velocity, relative to W and expressed in W, of the point of the body that
//                coincides with the WORLD ORIGIN (not the body's centre, not a frame origin).
//     The velocity of the body point at world location x is then v_WBo_W + w_WB_W x x.
//   - N frames f0 .. f(N-1) (N >= K), each fixed to one body (frame i < K is on body i, so every
//     body has a frame; the others are on random bodies), with an absolute pose in W:
//       R_WF     R[W<-f], columns = the axes of [f] in W (random unit quaternion, Shoemake);
//       p_WF_W   position of point f (the frame origin) wrt the world origin, in W, in [-2,2]^3.
//   Frame i is named "f<i>": its origin point and its orientation frame share that name (the
//   semgraph frame convention); body k is named "B<k>". names() holds them.
//
// Derived quantities (each is a one-line formula below; notation of docs/semantics.md §1):
//   Position(e, f, r)             p_FE_R = R_WR^T (p_WE - p_WF)
//   Rotation(b, a)                R_BA = R[b<-a] = R_WB^T R_WA
//   OrientationOperator(a, b, r)  operator carrying [b] onto [a], expressed in [r]:
//                                 R_RB R_BA R_BR (= R_BA when r = b)
//   LinearVelocity(e, C, D, r)    velocity of the point of C coinciding with e, relative to D, in
//                                 [r]: R_WR^T (v_C(e) - v_D(e)), v_X(e) = velocity of the point of
//                                 X at e's location (relative to W, in W)
//   AngularVelocity(C, D, r)      R_WR^T (w_WC_W - w_WD_W)
//
// Randomness: std::mt19937_64, mapped to doubles by hand (top 53 bits), so a seed gives the same
// scene on every standard library. Build cost: O(N + K) plus interning N + K names (allocates);
// every query is O(1) and allocation-free.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "semgraph/semantics/names.h"
#include "semgraph/semantics/primitives.h"

namespace semgraph::testing {

/// Uniform double in [0, 1) from the top 53 bits of one draw.
inline double UnitDouble(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Uniform double in [lo, hi).
inline double UniformDouble(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * UnitDouble(rng);
}

/// Uniform integer in [0, n) (modulo bias below 2^-50 for the small n used here).
inline int UniformIndex(std::mt19937_64& rng, int n) {
  return static_cast<int>(rng() % static_cast<std::uint64_t>(n));
}

/// Uniform random unit quaternion (K. Shoemake, "Uniform random rotations", Graphics Gems III).
inline Eigen::Quaterniond RandomUnitQuaternion(std::mt19937_64& rng) {
  constexpr double kTwoPi = 6.283185307179586476925286766559;
  const double u1 = UnitDouble(rng), u2 = UnitDouble(rng), u3 = UnitDouble(rng);
  const double s1 = std::sqrt(1.0 - u1), s2 = std::sqrt(u1);
  // Eigen's constructor order is (w, x, y, z).
  return Eigen::Quaterniond(s2 * std::cos(kTwoPi * u3), s1 * std::sin(kTwoPi * u2),
                            s1 * std::cos(kTwoPi * u2), s2 * std::sin(kTwoPi * u3));
}

/// Each component uniform in [-half_width, half_width).
inline Eigen::Vector3d RandomVector(std::mt19937_64& rng, double half_width) {
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = UniformDouble(rng, -half_width, half_width);
  return v;
}

struct WorldFrame {
  int body = 0;
  Eigen::Matrix3d R_WF;  ///< R[W<-f]
  Eigen::Vector3d p_WF_W;
};

struct WorldBody {
  Eigen::Vector3d w_WB_W;   ///< angular velocity of the body relative to W, in W
  Eigen::Vector3d v_WBo_W;  ///< velocity of the body point at the world origin, relative to W, in W
};

class WorldScene {
 public:
  WorldScene(std::uint64_t seed, int num_frames, int num_bodies) : rng_(seed) {
    if (num_bodies < 1) num_bodies = 1;
    if (num_frames < num_bodies) num_frames = num_bodies;
    bodies_.reserve(static_cast<std::size_t>(num_bodies));
    for (int k = 0; k < num_bodies; ++k) {
      WorldBody b;
      b.w_WB_W = RandomVector(rng_, 1.0);
      b.v_WBo_W = RandomVector(rng_, 1.0);
      bodies_.push_back(b);
      body_ids_.push_back(semantics::Body(*names_.Intern("B" + std::to_string(k))));
    }
    frames_.reserve(static_cast<std::size_t>(num_frames));
    for (int i = 0; i < num_frames; ++i) {
      WorldFrame f;
      f.body = i < num_bodies ? i : UniformIndex(rng_, num_bodies);
      f.R_WF = RandomUnitQuaternion(rng_).toRotationMatrix();
      f.p_WF_W = RandomVector(rng_, 2.0);
      frames_.push_back(f);
      frame_ids_.push_back(semantics::Frame(*names_.Intern("f" + std::to_string(i))));
    }
  }

  // ------------------------------------------------------------ the scene
  [[nodiscard]] int num_frames() const { return static_cast<int>(frames_.size()); }
  [[nodiscard]] int num_bodies() const { return static_cast<int>(bodies_.size()); }
  [[nodiscard]] const WorldFrame& frame_data(int i) const { return frames_[Index(i)]; }
  [[nodiscard]] const WorldBody& body_data(int k) const { return bodies_[Index(k)]; }
  [[nodiscard]] int BodyOf(int frame) const { return frames_[Index(frame)].body; }

  // ------------------------------------------------------------ names
  [[nodiscard]] const semantics::NameTable& names() const { return names_; }
  [[nodiscard]] semantics::Frame frame(int i) const { return frame_ids_[Index(i)]; }
  [[nodiscard]] semantics::Point point(int i) const { return frame(i).origin(); }
  [[nodiscard]] semantics::OrientationFrame axes(int i) const { return frame(i).axes(); }
  [[nodiscard]] semantics::Body body(int k) const { return body_ids_[Index(k)]; }
  [[nodiscard]] semantics::Body body_of(int frame) const { return body(BodyOf(frame)); }

  // ------------------------------------------------------------ random choices
  std::mt19937_64& rng() { return rng_; }
  bool Coin() { return (rng_() >> 63) != 0; }
  int RandomFrame() { return UniformIndex(rng_, num_frames()); }
  int RandomBody() { return UniformIndex(rng_, num_bodies()); }
  /// A random frame fixed to `body` (every body has one).
  int RandomFrameOn(int body) {
    for (;;) {
      const int i = RandomFrame();
      if (frames_[Index(i)].body == body) return i;
    }
  }
  /// A random frame other than `frame` (needs two frames).
  int RandomFrameOtherThan(int frame) {
    for (;;) {
      const int i = RandomFrame();
      if (i != frame) return i;
    }
  }
  /// A random body other than `body` (needs two bodies).
  int RandomBodyOtherThan(int body) {
    for (;;) {
      const int k = RandomBody();
      if (k != body) return k;
    }
  }
  /// A random frame on a body other than `body`.
  int RandomFrameNotOn(int body) { return RandomFrameOn(RandomBodyOtherThan(body)); }

  // ------------------------------------------------------------ ground truth
  /// R[b<-a] = R_WB^T R_WA.
  [[nodiscard]] Eigen::Matrix3d Rotation(int b, int a) const {
    return frame_data(b).R_WF.transpose() * frame_data(a).R_WF;
  }

  /// p_FE_R: position of point e wrt point f, expressed in [r].
  [[nodiscard]] Eigen::Vector3d Position(int e, int f, int r) const {
    return frame_data(r).R_WF.transpose() * (frame_data(e).p_WF_W - frame_data(f).p_WF_W);
  }

  /// The operator carrying [b] onto [a], expressed in [r]: R_RB R_BA R_BR.
  [[nodiscard]] Eigen::Matrix3d OrientationOperator(int a, int b, int r) const {
    return Rotation(r, b) * Rotation(b, a) * Rotation(b, r);
  }

  /// Velocity (relative to W, in W) of the point of `body` at world location x_W.
  [[nodiscard]] Eigen::Vector3d VelocityOfBodyPointAt(int body, const Eigen::Vector3d& x_W) const {
    const WorldBody& b = body_data(body);
    return b.v_WBo_W + b.w_WB_W.cross(x_W);
  }

  /// Velocity of the point of body C coinciding with point e, relative to body D, in [r].
  [[nodiscard]] Eigen::Vector3d LinearVelocity(int e, int C, int D, int r) const {
    const Eigen::Vector3d& x_W = frame_data(e).p_WF_W;
    return frame_data(r).R_WF.transpose() *
           (VelocityOfBodyPointAt(C, x_W) - VelocityOfBodyPointAt(D, x_W));
  }

  /// Angular velocity of body C relative to body D, in [r].
  [[nodiscard]] Eigen::Vector3d AngularVelocity(int C, int D, int r) const {
    return frame_data(r).R_WF.transpose() * (body_data(C).w_WB_W - body_data(D).w_WB_W);
  }

 private:
  static std::size_t Index(int i) { return static_cast<std::size_t>(i); }

  std::mt19937_64 rng_;
  std::vector<WorldBody> bodies_;
  std::vector<WorldFrame> frames_;
  std::vector<semantics::Body> body_ids_;
  std::vector<semantics::Frame> frame_ids_;
  semantics::NameTable names_;
};

}  // namespace semgraph::testing
