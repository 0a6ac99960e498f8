// File: tests/support/rigid_body_scene.h
//
// RigidBodyScene: a seeded random *independent ground truth* for scene-graph tests, built the
// way a robot scene is: rigid bodies that move, and frames bolted to them. Like WorldScene
// (world_scene.h, whose random helpers it reuses) it knows only absolute quantities in one
// world frame W and derives every relation from them with plain Eigen, never through semgraph.
// Unlike WorldScene, a frame's pose on its body is a fixed offset, so the bodies can be moved
// (Move) while every same-body relation stays constant, as spec P4 requires.
//
// The scene:
//   - K bodies B0 .. B(K-1), each with an absolute pose and twist in W:
//       R_WB, p_WB_W   pose of the body's reference frame in W (random unit quaternion, [-2,2]^3);
//       w_WB_W         angular velocity of the body relative to W, in W;
//       v_WBo_W        velocity of the body point that coincides with the WORLD ORIGIN, relative
//                      to W, in W (the body point at world location x moves at v_WBo_W + w x x).
//   - frames f0 .. f(N-1), each fixed to one body at a constant offset X_BF:
//       R_BF, p_BF_B   random unit quaternion, [-1,1]^3.
//     Body k owns frames_per_body[k] consecutive frames (at least one each). Frame i is named
//     "f<i>", body k "B<k>" (plain strings: the scene graph interns them itself).
//
// Derived quantities (R_WF = R_WB R_BF, p_WF_W = p_WB_W + R_WB p_BF_B):
//   Rotation(b, a)                R_BA = R[b<-a] = R_WB^T R_WA
//   Position(e, f, r)             p_FE_R = R_WR^T (p_WE - p_WF)
//   OrientationOperator(a, b, r)  the operator carrying [b] onto [a], expressed in [r]:
//                                 R_RB R_BA R_BR (= R_BA when r = b)
//   LinearVelocity(e, C, D, r)    velocity of the point of body C coinciding with point e,
//                                 relative to body D, in [r]: R_WR^T (v_C(p_WE) - v_D(p_WE))
//   AngularVelocity(C, D, r)      R_WR^T (w_WC_W - w_WD_W)
// The scene-graph pose edge t -> h stores (Rotation(t, h), Position(h, t, t)); the twist edge
// D -> {h}|H stores the screw twist (LinearVelocity(h, H, D, h), AngularVelocity(H, D, h)).
//
// Randomness: std::mt19937_64 through world_scene.h's hand-made mappings, so a seed gives the
// same scene on every standard library. Cost: construction O(N + K); queries O(1), no allocation.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "support/world_scene.h"

namespace semgraph::testing {

struct RigidBody {
  Eigen::Matrix3d R_WB;
  Eigen::Vector3d p_WB_W;
  Eigen::Vector3d w_WB_W;
  Eigen::Vector3d v_WBo_W;
};

struct BodyFixedFrame {
  int body = 0;
  Eigen::Matrix3d R_BF;    ///< R[B<-f], constant
  Eigen::Vector3d p_BF_B;  ///< position of point f wrt the body's reference point, in B; constant
};

class RigidBodyScene {
 public:
  /// K = num_bodies bodies, each with a random number of frames in [min_frames, max_frames].
  RigidBodyScene(std::uint64_t seed, int num_bodies, int min_frames, int max_frames) : rng_(seed) {
    if (num_bodies < 1) num_bodies = 1;
    if (min_frames < 1) min_frames = 1;
    if (max_frames < min_frames) max_frames = min_frames;
    for (int k = 0; k < num_bodies; ++k) {
      bodies_.push_back(RandomBody());
      body_names_.push_back("B" + std::to_string(k));
      const int n = min_frames + UniformIndex(rng_, max_frames - min_frames + 1);
      for (int j = 0; j < n; ++j) {
        BodyFixedFrame f;
        f.body = k;
        f.R_BF = RandomUnitQuaternion(rng_).toRotationMatrix();
        f.p_BF_B = RandomVector(rng_, 1.0);
        frame_names_.push_back("f" + std::to_string(frames_.size()));
        frames_.push_back(f);
      }
    }
  }

  // ------------------------------------------------------------ the scene
  [[nodiscard]] int num_frames() const { return static_cast<int>(frames_.size()); }
  [[nodiscard]] int num_bodies() const { return static_cast<int>(bodies_.size()); }
  [[nodiscard]] int BodyOf(int frame) const { return frames_[Index(frame)].body; }
  [[nodiscard]] const std::string& frame_name(int i) const { return frame_names_[Index(i)]; }
  [[nodiscard]] const std::string& body_name(int k) const { return body_names_[Index(k)]; }
  [[nodiscard]] const RigidBody& body_data(int k) const { return bodies_[Index(k)]; }
  [[nodiscard]] const BodyFixedFrame& frame_data(int i) const { return frames_[Index(i)]; }

  /// New random poses and twists for every body; the frame offsets stay (same-body relations
  /// are unchanged, every relation between different bodies changes).
  void Move() {
    for (RigidBody& b : bodies_) b = RandomBody();
  }

  std::mt19937_64& rng() { return rng_; }

  // ------------------------------------------------------------ absolute frame poses
  [[nodiscard]] Eigen::Matrix3d R_WF(int i) const {
    const BodyFixedFrame& f = frames_[Index(i)];
    return bodies_[Index(f.body)].R_WB * f.R_BF;
  }
  [[nodiscard]] Eigen::Vector3d p_WF_W(int i) const {
    const BodyFixedFrame& f = frames_[Index(i)];
    const RigidBody& b = bodies_[Index(f.body)];
    return b.p_WB_W + b.R_WB * f.p_BF_B;
  }

  // ------------------------------------------------------------ ground truth
  /// R[b<-a] = R_WB^T R_WA.
  [[nodiscard]] Eigen::Matrix3d Rotation(int b, int a) const {
    return R_WF(b).transpose() * R_WF(a);
  }
  /// p_FE_R: position of point e wrt point f, expressed in [r].
  [[nodiscard]] Eigen::Vector3d Position(int e, int f, int r) const {
    return R_WF(r).transpose() * (p_WF_W(e) - p_WF_W(f));
  }
  /// The operator carrying [b] onto [a], expressed in [r]: R_RB R_BA R_BR.
  [[nodiscard]] Eigen::Matrix3d OrientationOperator(int a, int b, int r) const {
    return Rotation(r, b) * Rotation(b, a) * Rotation(b, r);
  }
  /// Velocity (relative to W, in W) of the point of `body` at world location x_W.
  [[nodiscard]] Eigen::Vector3d VelocityOfBodyPointAt(int body, const Eigen::Vector3d& x_W) const {
    const RigidBody& b = bodies_[Index(body)];
    return b.v_WBo_W + b.w_WB_W.cross(x_W);
  }
  /// Velocity of the point of body C coinciding with point e, relative to body D, in [r].
  [[nodiscard]] Eigen::Vector3d LinearVelocity(int e, int C, int D, int r) const {
    const Eigen::Vector3d x_W = p_WF_W(e);
    return R_WF(r).transpose() * (VelocityOfBodyPointAt(C, x_W) - VelocityOfBodyPointAt(D, x_W));
  }
  /// Angular velocity of body C relative to body D, in [r].
  [[nodiscard]] Eigen::Vector3d AngularVelocity(int C, int D, int r) const {
    return R_WF(r).transpose() * (bodies_[Index(C)].w_WB_W - bodies_[Index(D)].w_WB_W);
  }

 private:
  static std::size_t Index(int i) { return static_cast<std::size_t>(i); }

  RigidBody RandomBody() {
    RigidBody b;
    b.R_WB = RandomUnitQuaternion(rng_).toRotationMatrix();
    b.p_WB_W = RandomVector(rng_, 2.0);
    b.w_WB_W = RandomVector(rng_, 1.0);
    b.v_WBo_W = RandomVector(rng_, 1.0);
    return b;
  }

  std::mt19937_64 rng_;
  std::vector<RigidBody> bodies_;
  std::vector<BodyFixedFrame> frames_;
  std::vector<std::string> body_names_;
  std::vector<std::string> frame_names_;
};

}  // namespace semgraph::testing
