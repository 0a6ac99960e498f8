// File: semgraph/core/compiled_query.h
//
// Compiled queries: a query's semantics checked and its path resolved once (SceneGraph::Compile*,
// build time, allocates), then evaluated any number of times on the real-time path.
//
// What compiling resolves: every pose edge on the (up to four) frame-to-frame paths the query
// needs (paper Algorithm 1: the basic pose, the reference-point, point and coordinate-frame
// changes), and for twists every twist edge on the TG path with its direction and the pose paths
// that move it to the query's point and frame. Evaluate() then runs only the arithmetic: for a
// frame-to-frame pose, one composition per edge, as a hand-written chain would.
//
// Invariants: a compiled query holds, for every edge it reads, the edge's epoch at compile time;
// removing an edge bumps its epoch, so Evaluate() of an affected query returns
// kQueryInvalidated (never a wrong number). Adding edges never changes an existing path (pose
// trees and TG(P) stay forests), so it invalidates nothing. Recompile to recover.
// Costs: Evaluate O(edges on the path), noexcept, no allocation, no lock, no string.
// Thread safety: Evaluate is const and may run on any number of threads concurrently with one
// writer calling SceneGraph::SetPose/SetTwist. Each edge value is read untorn (sequence lock);
// different edges of one path may come from different writer updates (there is no cross-edge
// snapshot). Topology changes (add/remove) need exclusive access.
#pragma once

#include <cstdint>
#include <vector>

#include "semgraph/core/scene_graph.h"

namespace semgraph::core {

/// Shared machinery of the compiled queries: the resolved edges and the frame-to-frame paths.
template <coord::Backend B>
class CompiledQuery {
 public:
  using PoseCoords = typename B::PoseCoords;

  /// True while every edge the query reads still exists (O(edges)).
  [[nodiscard]] bool is_valid() const noexcept;
  /// Number of pose edges read per evaluation (the path length).
  [[nodiscard]] std::size_t num_pose_edges() const noexcept { return edges_.size(); }

 protected:
  friend class SceneGraph<B>;
  struct EdgeRef {
    std::uint64_t expected_header;  // PoseValue<B>::ExpectedHeader(epoch of the edge when compiled)
    std::uint32_t child;            // frame whose parent edge is read
    [[nodiscard]] std::uint32_t epoch() const noexcept {
      return static_cast<std::uint32_t>(expected_header >> 32);
    }
  };
  // X_AF for a frame F below ancestor A: edges_[begin, end) from F upward.
  struct Chain {
    std::uint32_t begin = 0, end = 0;
  };
  // Basic pose X_BA (a wrt b in [b]) = X_CA * inverse(X_CB), C the common ancestor.
  struct Basic {
    Chain up_a, up_b;
  };

  CompiledQuery() = default;
  explicit CompiledQuery(const SceneGraph<B>* graph) : graph_(graph) {}

  /// Appends the basic-pose path between frames a and b (same tree) to edges_.
  Basic AddBasic(FrameIndex a, FrameIndex b);
  [[nodiscard]] bool EvalChain(Chain c, PoseCoords& X_AF, bool& identity) const noexcept;
  /// Reads a twist edge's screw twist if its epoch is unchanged.
  [[nodiscard]] bool LoadTwistEdge(std::uint32_t slot, std::uint32_t epoch, Eigen::Vector3d& v,
                                   Eigen::Vector3d& w) const noexcept;
  [[nodiscard]] bool EvalBasic(const Basic& basic, PoseCoords& X_BA) const noexcept;

  const SceneGraph<B>* graph_ = nullptr;
  std::vector<EdgeRef> edges_;
};

/// PoseCoord((e,[a])|C, (f,[b])|D, [r]).
template <coord::Backend B>
class CompiledPose : public CompiledQuery<B> {
 public:
  CompiledPose() = default;
  [[nodiscard]] const semantics::PoseSemantics& semantics() const noexcept { return semantics_; }
  /// Writes the pose (orientation operator and position, in [r]). kOk or kQueryInvalidated.
  [[nodiscard]] ErrorCode Evaluate(typename B::PoseCoords& X) const noexcept;

 private:
  friend class SceneGraph<B>;
  using Base = CompiledQuery<B>;
  semantics::PoseSemantics semantics_;
  typename Base::Basic ab_, fb_, ea_, br_;
  bool change_ref_point_ = false, change_point_ = false, change_frame_ = false;
};

/// PositionCoord(e|C, f|D, [r]).
template <coord::Backend B>
class CompiledPosition : public CompiledQuery<B> {
 public:
  CompiledPosition() = default;
  [[nodiscard]] const semantics::PositionSemantics& semantics() const noexcept { return semantics_; }
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& p) const noexcept;

 private:
  friend class SceneGraph<B>;
  using Base = CompiledQuery<B>;
  semantics::PositionSemantics semantics_;
  typename Base::Basic ef_, fr_;
  bool change_frame_ = false;
};

/// OrientationCoord([a]|C, [b]|D, [r]).
template <coord::Backend B>
class CompiledOrientation : public CompiledQuery<B> {
 public:
  CompiledOrientation() = default;
  [[nodiscard]] const semantics::OrientationSemantics& semantics() const noexcept {
    return semantics_;
  }
  [[nodiscard]] ErrorCode Evaluate(typename B::Rotation& M) const noexcept;

 private:
  friend class SceneGraph<B>;
  using Base = CompiledQuery<B>;
  semantics::OrientationSemantics semantics_;
  typename Base::Basic ab_, br_;
  bool change_frame_ = false;
};

/// TwistCoord(e|C, D, [r]); linear and angular velocity are its parts.
template <coord::Backend B>
class CompiledTwist : public CompiledQuery<B> {
 public:
  CompiledTwist() = default;
  [[nodiscard]] const semantics::TwistSemantics& semantics() const noexcept { return semantics_; }
  /// v: velocity of the point of C at e relative to D; w: angular velocity; both in [r].
  [[nodiscard]] ErrorCode Evaluate(Eigen::Vector3d& v, Eigen::Vector3d& w) const noexcept;
  [[nodiscard]] std::size_t num_twist_edges() const noexcept { return steps_.size(); }

 private:
  friend class SceneGraph<B>;
  using Base = CompiledQuery<B>;
  struct Step {
    std::uint32_t slot, epoch;  // twist edge
    bool invert;                // traversed against its direction
    bool move_point;            // head != e: v += p(h wrt e) x w
    bool change_frame;          // head != r
    typename Base::Basic eh;    // X_HE: e wrt h in [h]
    typename Base::Basic hr;    // X_RH: h wrt r in [r]
  };
  semantics::TwistSemantics semantics_;
  std::vector<Step> steps_;
};

extern template class CompiledQuery<coord::QuaternionBackend>;
extern template class CompiledQuery<coord::HomogeneousBackend>;
extern template class CompiledPose<coord::QuaternionBackend>;
extern template class CompiledPose<coord::HomogeneousBackend>;
extern template class CompiledPosition<coord::QuaternionBackend>;
extern template class CompiledPosition<coord::HomogeneousBackend>;
extern template class CompiledOrientation<coord::QuaternionBackend>;
extern template class CompiledOrientation<coord::HomogeneousBackend>;
extern template class CompiledTwist<coord::QuaternionBackend>;
extern template class CompiledTwist<coord::HomogeneousBackend>;

}  // namespace semgraph::core
