// DOT export. Contract: dot_writer.h.
#include "semgraph/dot_writer.h"

#include <cstdint>
#include <vector>

namespace semgraph::script {

namespace {

std::string FrameId(core::FrameIndex f) { return "frame_" + std::to_string(f.value()); }
std::string BodyId(core::BodyIndex b) { return "body_" + std::to_string(b.value()); }

}  // namespace

std::string DotLabel(std::string_view text) {
  // In a quoted DOT string only \" is an escape, but labels also give \n, \l, \N ... a meaning,
  // so a backslash is doubled to stay literal.
  std::string s = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') s += '\\';
    s += c;
  }
  return s + "\"";
}

template <coord::Backend B>
std::string WriteDot(const core::SceneGraph<B>& graph) {
  // Frames grouped by body, in index order.
  std::vector<std::vector<core::FrameIndex>> frames_of(graph.num_bodies());
  for (std::uint32_t i = 0; i < graph.num_frames(); ++i) {
    const core::FrameIndex f(i);
    frames_of[graph.body_of(f).value()].push_back(f);
  }
  std::string dot = "digraph semgraph {\n";
  dot += "  graph [compound=true, fontname=\"Helvetica\"];\n";
  dot += "  node [fontname=\"Helvetica\", shape=ellipse];\n";
  dot += "  edge [fontname=\"Helvetica\"];\n";
  for (std::uint32_t i = 0; i < graph.num_bodies(); ++i) {
    const core::BodyIndex b(i);
    dot += "  subgraph cluster_" + std::to_string(i) + " {\n";
    dot += "    label=" + DotLabel(graph.body_name(b)) + ";\n";
    dot += "    style=rounded;\n";
    dot += "    " + BodyId(b) + " [shape=box, style=filled, fillcolor=gray90, fontsize=10, " +
           "height=0.25, label=" + DotLabel(graph.body_name(b)) + "];\n";
    for (const core::FrameIndex f : frames_of[i]) {
      dot += "    " + FrameId(f) +
             " [label=" + DotLabel("{" + std::string(graph.frame_name(f)) + "}") + "];\n";
    }
    dot += "  }\n";
  }
  // A joint's two edges are drawn bold and labelled with its type and name.
  const auto joint_label = [&](core::FrameIndex head) -> std::string {
    const core::internal::JointRecord* j = graph.joint_table().OfChild(head);
    if (!j) return {};
    return "label=" +
           DotLabel(std::string(core::ToString(j->type)) + " " +
                    std::string(graph.joint_table().name(*j))) +
           ", penwidth=2";
  };
  graph.topology().ForEachPoseEdge([&](core::FrameIndex tail, core::FrameIndex head) {
    const std::string joint = joint_label(head);
    dot += "  " + FrameId(tail) + " -> " + FrameId(head) +
           (joint.empty() ? "" : " [" + joint + "]") + ";\n";
  });
  graph.topology().ForEachTwistEdge([&](core::BodyIndex tail, core::FrameIndex head) {
    const std::string joint = joint_label(head);
    dot += "  " + BodyId(tail) + " -> " + FrameId(head) + " [style=dashed" +
           (joint.empty() ? "" : ", " + joint) + "];\n";
  });
  dot += "}\n";
  return dot;
}

template std::string WriteDot<coord::QuaternionBackend>(
    const core::SceneGraph<coord::QuaternionBackend>&);
template std::string WriteDot<coord::HomogeneousBackend>(
    const core::SceneGraph<coord::HomogeneousBackend>&);

}  // namespace semgraph::script
