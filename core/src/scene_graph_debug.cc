// SceneGraph debug output and checks (scene_graph_debug.h): Dump (canonical text of names,
// nodes, edges and values, for tests and fuzzers comparing states), CheckInvariants (the
// topology's, from scratch, plus the values' bookkeeping); and three inspection members of the
// graph (twist_parent, twist_value, ApproximateBytesExcludingNames). Not on any production path.
#include "semgraph/core/scene_graph_debug.h"

#include <sstream>

#include "text.h"

namespace semgraph::core {

// The graph's only friend: the private state the debug functions read (the edge values, for
// their count), and nothing else.
struct internal::DebugAccess {
  template <coord::Backend B>
  static const EdgeValues<B>& values(const SceneGraph<B>& g) noexcept {
    return g.values_;
  }
};

template <coord::Backend B>
BodyIndex SceneGraph<B>::twist_parent(FrameIndex f) const noexcept {
  const TwistEdgeIndex e = topology_.twist_edge_of(f);
  return e.is_valid() ? topology_.twist_edge(e).tail : BodyIndex();
}

template <coord::Backend B>
std::optional<coord::Twist> SceneGraph<B>::twist_value(FrameIndex f) const noexcept {
  const TwistEdgeIndex e = topology_.twist_edge_of(f);
  if (!e.is_valid()) return std::nullopt;
  const TwistNumbers V = values_.V_DH[e.value()].Load();
  return coord::Twist{topology_.twist_edge(e).semantics, V.v_DHo_H, V.w_DH_H};
}

template <coord::Backend B>
std::string Dump(const SceneGraph<B>& g) {
  const topology::SceneTopology& t = g.topology();
  const EdgeValues<B>& values = internal::DebugAccess::values(g);
  const internal::JointTable& joints = g.joint_table();
  const semantics::NameTable& names = t.names();
  std::ostringstream out;
  out.precision(17);
  out << "representation " << B::kName << "\nnames " << names.size() << "\n";
  for (std::size_t i = 0; i < names.size(); ++i)
    out << "  name " << i << " " << names.name(NameId(i)) << "\n";
  out << "bodies " << t.num_bodies() << "\n";
  for (std::size_t i = 0; i < t.num_bodies(); ++i)
    out << "  body " << i << " " << g.body_name(BodyIndex(i)) << "\n";
  out << "frames " << t.num_frames() << "\n";
  for (std::uint32_t i = 0; i < t.num_frames(); ++i) {
    const FrameIndex f(i);
    out << "  frame " << i << " " << text::Frame(t, f);
    if (t.pose_parent(f).is_valid()) {
      const auto X = values.X_PF[i].Load();
      const Eigen::Quaterniond q = B::ToQuaternion(B::RotationOf(X));
      const Eigen::Vector3d p = B::TranslationOf(X);
      out << " parent " << t.pose_parent(f).value() << " p " << p.x() << " " << p.y() << " "
          << p.z() << " q " << q.w() << " " << q.x() << " " << q.y() << " " << q.z();
    }
    if (const std::optional<coord::Twist> tw = g.twist_value(f)) {
      out << " twist_parent " << g.body_name(g.twist_parent(f)) << " v " << tw->linear.transpose()
          << " w " << tw->angular.transpose();
    }
    if (const std::optional<coord::Acceleration> A = g.acceleration_value(f)) {
      out << " a " << A->linear.transpose() << " alpha " << A->angular.transpose();
    }
    out << " tree " << t.forest().Root(f).value() << "\n";
  }
  out << "joints " << joints.num_alive << "\n";
  for (std::uint32_t i = 0; i < joints.joints.size(); ++i) {
    const internal::JointRecord& j = joints.joints[i];
    out << "  joint " << i << " generation " << j.generation;
    if (j.alive) {
      out << " " << joints.name(j) << " " << ToString(j.type) << " " << t.frame_name(j.parent)
          << " -> " << t.frame_name(j.child) << " q " << j.q << " qdot " << j.qdot;
      if (j.has_qddot) out << " qddot " << j.qddot;
      if (j.is_mimic()) out << " mimic " << joints.name(joints[j.master]);
    }
    out << "\n";
  }
  const internal::WrenchStore& w = g.wrench_store();
  // Live wrenches in slot order; free slots and epochs are bookkeeping (a script that rebuilds
  // the graph, semgraph export, renumbers them), like removed joints' records.
  out << "wrenches " << w.num_live << "\n";
  for (std::size_t i = 0; i < w.slots.size(); ++i) {
    const internal::WrenchSlot& s = w.slots[i];
    if (!s.live) continue;
    const WrenchNumbers W = w.values[i].Load();
    out << "  wrench on " << g.body_name(s.on) << " by " << g.body_name(s.by) << " at "
        << t.frame_name(s.frame) << " f " << W.f_S.transpose() << " m " << W.m_So_S.transpose()
        << "\n";
  }
  return out.str();
}

template <coord::Backend B>
std::string CheckInvariants(const SceneGraph<B>& g) {
  const topology::SceneTopology& t = g.topology();
  const EdgeValues<B>& values = internal::DebugAccess::values(g);
  std::string out = t.CheckInvariants();
  if (values.X_PF.size() != t.num_frames()) out += "pose value count mismatch\n";
  if (values.V_DH.size() < t.num_twist_edge_slots()) out += "twist value count mismatch\n";
  if (values.A_DH.size() != values.V_DH.size() ||
      values.acceleration_on.size() != values.V_DH.size()) {
    out += "acceleration record count mismatch\n";
  }
  // An acceleration goes with the twist it was stored with: the edge's current one.
  for (std::uint32_t e = 0; e < t.num_twist_edge_slots() && e < values.A_DH.size(); ++e) {
    const TwistAndAcceleration r = values.A_DH[e].Load();
    if ((r.present != 0.0) != (values.acceleration_on[e] != 0)) {
      out += "acceleration flag mismatch on twist slot " + std::to_string(e) + "\n";
    }
    if (!values.acceleration_on[e]) continue;
    const TwistNumbers V = values.V_DH[e].Load();
    if (!t.twist_edge(TwistEdgeIndex(e)).alive || r.V.v_DHo_H != V.v_DHo_H ||
        r.V.w_DH_H != V.w_DH_H) {
      out += "stale acceleration on twist slot " + std::to_string(e) + "\n";
    }
  }
  // A joint's edge carries an acceleration exactly when its qddot was given, and that one.
  for (const internal::JointRecord& j : g.joint_table().joints) {
    if (!j.alive) continue;
    const std::uint32_t e = t.twist_edge_of(j.child).value();
    if (values.HasAcceleration(e) != j.has_qddot) {
      out += "joint " + std::string(g.joint_table().name(j)) + ": acceleration flag mismatch\n";
    } else if (j.has_qddot) {
      AccelerationNumbers A;
      j.AccelerationAt(j.qddot, A.a_DHo_H, A.alpha_DH_H);
      const TwistAndAcceleration r = values.A_DH[e].Load();
      if (r.A.a_DHo_H != A.a_DHo_H || r.A.alpha_DH_H != A.alpha_DH_H) {
        out += "joint " + std::string(g.joint_table().name(j)) + ": acceleration is not qddot's\n";
      }
    }
  }
  return out;
}

template <coord::Backend B>
std::size_t SceneGraph<B>::ApproximateBytesExcludingNames() const noexcept {
  return sizeof(*this) - sizeof(topology_) + topology_.ApproximateBytesExcludingNames() +
         values_.ApproximateBytes();
}

#define SEMGRAPH_INSTANTIATE_DEBUG(B)                                                         \
  template BodyIndex SceneGraph<B>::twist_parent(FrameIndex) const noexcept;                  \
  template std::optional<coord::Twist> SceneGraph<B>::twist_value(FrameIndex) const noexcept; \
  template std::string Dump(const SceneGraph<B>&);                                            \
  template std::string CheckInvariants(const SceneGraph<B>&);                                 \
  template std::size_t SceneGraph<B>::ApproximateBytesExcludingNames() const noexcept;
SEMGRAPH_INSTANTIATE_DEBUG(coord::QuaternionBackend)
SEMGRAPH_INSTANTIATE_DEBUG(coord::HomogeneousBackend)

}  // namespace semgraph::core
