// Uses the installed semgraph: interns two names and composes two pose semantics (semantics),
// then builds a small scene graph and queries it (core), checking the numbers against a pose
// composed by hand. Returns 0 on success.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "semgraph/core/scene_graph.h"
#include "semgraph/semantics/describe.h"
#include "semgraph/semantics/names.h"
#include "semgraph/semantics/operations.h"
#include "semgraph/semantics/relations.h"

namespace {

int Semantics() {
  namespace sem = semgraph::semantics;
  sem::NameTable names;
  auto base = names.Intern("base");
  auto tool = names.Intern("tool");
  if (!base || !tool) return 1;

  // Each body carries a frame of the same name: {base}|base and {tool}|tool.
  const sem::Frame b(*base), t(*tool);
  const sem::Body B(*base), T(*tool);
  const auto tool_wrt_base = sem::PoseSemantics::OfFrame(t, T, b, B, b.axes());
  const auto base_wrt_tool = sem::PoseSemantics::OfFrame(b, B, t, T, t.axes());

  auto composed = sem::Compose(tool_wrt_base, base_wrt_tool);
  if (!composed) {
    std::printf("unexpected: %s\n", sem::Describe(composed.error(), names).c_str());
    return 1;
  }
  if (!(composed->result == sem::PoseSemantics::OfFrame(t, T, t, T, t.axes()))) return 1;
  if (sem::Compose(tool_wrt_base, tool_wrt_base)) return 1;  // must be rejected

  std::printf("semgraph consumer: %s\n", sem::Describe(composed->result, names).c_str());
  return 0;
}

// {e}|E wrt {b}|B is X_BE (a quarter turn about z, 1 m along x); {t}|T wrt {e}|E is X_ET (0.5 m
// along the end effector's x). Then p_BoTo_B = p_BoEo_B + R_BE p_EoTo_E = (1, 0.5, 0).
int Graph() {
  using semgraph::core::PoseSpec;
  semgraph::core::SceneGraph<> g;
  const Eigen::Quaterniond q_BE(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  if (!g.AddPose(PoseSpec::Of("e", "E").RelativeTo("b", "B"), q_BE, Eigen::Vector3d(1, 0, 0)))
    return 1;
  if (!g.AddPose(PoseSpec::Of("t", "T").RelativeTo("e", "E"), Eigen::Quaterniond::Identity(),
                 Eigen::Vector3d(0.5, 0, 0))) {
    return 1;
  }
  const auto X = g.GetPose(PoseSpec::Of("t").RelativeTo("b"));
  if (!X) return 1;
  const Eigen::Vector3d p = X->value.translation;
  if ((p - Eigen::Vector3d(1, 0.5, 0)).norm() > 1e-12) return 1;
  // The compiled query gives the same answer in the same type; Eigen isometries in and out.
  // (Inline members of the explicitly instantiated templates: the pkg-config build of this
  // file is at -O0, where they are not inlined.)
  const auto compiled = g.CompilePose(PoseSpec::Of("t").RelativeTo("b"));
  if (!compiled) return 1;
  const auto Y = compiled->Evaluate();
  if (!Y || !(Y->semantics == X->semantics)) return 1;
  const Eigen::Isometry3d T_BT = Y->ToIsometry();
  if ((T_BT.translation() - p).norm() > 1e-12 || g.num_frames() != 3) return 1;
  if (!g.AddPose(PoseSpec::Of("k", "K").RelativeTo("t"), T_BT)) return 1;
  // An unknown frame is a query error, described with its code.
  const auto missing = g.GetPose(PoseSpec::Of("nowhere").RelativeTo("b"));
  if (missing || missing.error().code != semgraph::base::ErrorCode::kUnknownFrame) return 1;
  if (g.Describe(missing.error()).rfind("query failed (unknown_frame): ", 0) != 0) return 1;
  std::printf("semgraph consumer: p_BoTo_B = [%g, %g, %g]\n", p.x(), p.y(), p.z());
  return 0;
}

}  // namespace

int main() { return Semantics() != 0 || Graph() != 0 ? 1 : 0; }
