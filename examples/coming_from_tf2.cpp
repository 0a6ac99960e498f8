// coming_from_tf2: one small scene built and queried with ROS tf2 and with semgraph, side by
// side; prints both answers and exits non-zero if they disagree. Read it with
// docs/coming-from-tf2.md. The tf2 half is coming_from_tf2_tf2.cc (a C++17 file, see there);
// the scene's numbers are in coming_from_tf2.h.
//
// What it shows, call by call:
//   setTransform(parent, child)        AddPose(PoseSpec::Of(child, Child).RelativeTo(parent,
//   Parent)) lookupTransform(target, source)    GetPose(PoseSpec::Of(source).RelativeTo(target))
//   canTransform(target, source)       GetPose(...) has a value (or: error no_pose_path)
//   rotate by hand into a third frame  .ExpressedIn(frame)
//   difference two lookups (no twist)  AddTwist + GetTwist, with zero twists across fixed mounts
//   a second parent                    tf2 re-parents; semgraph refuses (multiple_pose_parents)
#include "coming_from_tf2.h"

#include <cmath>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "semgraph/core/scene_graph.h"

namespace cf = coming_from_tf2;
using semgraph::core::PoseSpec;
using semgraph::core::SceneGraph;
using semgraph::core::TwistSpec;

namespace {

Eigen::Quaterniond Eig(const cf::Quat& q) { return Eigen::Quaterniond(q.w, q.x, q.y, q.z); }
Eigen::Vector3d Eig(const cf::Vec3& v) { return Eigen::Vector3d(v.x, v.y, v.z); }
cf::Quat Plain(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }
cf::Vec3 Plain(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// The semgraph half: the same scene and the same questions.
cf::Answers AskSemgraph() {
  SceneGraph<> graph;  // quaternion + vector coordinates
  const auto add = [](const semgraph::core::BuildResult& r) {
    if (!r) throw std::runtime_error(r.error().message);
  };
  // Every frame lives on a body: tf2's "w -> b" is "frame b of body B relative to frame w of W".
  add(graph.AddPose(PoseSpec::Of("b", "B").RelativeTo("w", "W"), Eig(cf::kX_WB.q),
                    Eig(cf::kX_WB.p)));
  add(graph.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"), Eig(cf::kX_BC.q),
                    Eig(cf::kX_BC.p)));
  add(graph.AddPose(PoseSpec::Of("k", "K").RelativeTo("t", "T"), Eig(cf::kX_TK.q),
                    Eig(cf::kX_TK.p)));
  // The object at t1 (no time stamps yet: the graph holds the current value) and its twist,
  // as the camera measures it: the velocity of o relative to C and O's angular velocity, in [c].
  add(graph.AddPose(PoseSpec::Of("o", "O").RelativeTo("c", "C"), Eig(cf::kX_CO.q),
                    Eig(cf::kX_CO.p)));
  add(graph.AddTwist(TwistSpec::Of("o", "O").RelativeTo("C").ExpressedIn("c"), Eig(cf::kV_CO_C),
                     Eig(cf::kW_CO_C)));

  cf::Answers a{};
  const auto X_BO = graph.GetPose(PoseSpec::Of("o").RelativeTo("b"));  // lookupTransform("b", "o")
  const auto X_WC = graph.GetPose(PoseSpec::Of("c").RelativeTo("w"));
  // The same relation as X_BO, its numbers written in [w]: no hand-made rotation.
  const auto p_BoOo_W = graph.GetPosition(PoseSpec::Of("o").RelativeTo("b").ExpressedIn("w"));
  const auto R_BO_W = graph.GetOrientation(PoseSpec::Of("o").RelativeTo("b").ExpressedIn("w"));
  if (!X_BO || !X_WC || !p_BoOo_W || !R_BO_W) throw std::runtime_error("a pose query failed");
  a.X_BO = {Plain(X_BO->value.rotation), Plain(X_BO->value.translation)};
  a.X_WC = {Plain(X_WC->value.rotation), Plain(X_WC->value.translation)};
  a.p_BoOo_W = Plain(p_BoOo_W->value);
  a.R_BO_W = Plain(R_BO_W->value);

  a.can_w_o = graph.GetPose(PoseSpec::Of("o").RelativeTo("w")).has_value();
  const auto w_k = graph.GetPose(PoseSpec::Of("k").RelativeTo("w"));
  a.can_w_k = w_k.has_value();
  if (!w_k) {
    std::printf("semgraph, pose of k wrt w: %s\n",
                graph.Describe(w_k.error(), PoseSpec::Of("k").RelativeTo("w")).c_str());
  }

  // Velocities follow twist edges, not pose edges: the camera mount C-B and the parked base B-W
  // carry no motion, but a twist query across them needs that said, as zero twists.
  const TwistSpec V_WO_W = TwistSpec::Of("o", "O").RelativeTo("W").ExpressedIn("w");
  if (const auto before = graph.GetTwist(V_WO_W); !before) {
    std::printf("semgraph, twist of O wrt W before the zero twists: %s\n",
                graph.Describe(before.error(), V_WO_W).c_str());
  }
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  add(graph.AddTwist(TwistSpec::Of("c", "C").RelativeTo("B").ExpressedIn("c"), zero, zero));
  add(graph.AddTwist(TwistSpec::Of("b", "B").RelativeTo("W").ExpressedIn("b"), zero, zero));
  const auto V = graph.GetTwist(V_WO_W);
  if (!V) throw std::runtime_error(graph.Describe(V.error(), V_WO_W));
  a.v_WO_W = Plain(V->linear);
  a.w_WO_W = Plain(V->angular);

  const auto second = graph.AddPose(PoseSpec::Of("k", "K").RelativeTo("c", "C"), Eig(cf::kX_TK.q),
                                    Eig(cf::kX_TK.p));
  a.second_parent_accepted = second.has_value();
  if (!second) std::printf("semgraph, a second parent for k: %s\n", second.error().message.c_str());
  return a;
}

// ---- printing and comparing
int failures = 0;

void Row(const char* what, const double* tf2_value, const double* sg_value, int n,
         double tolerance) {
  double worst = 0.0;
  for (int i = 0; i < n; ++i) worst = std::fmax(worst, std::fabs(tf2_value[i] - sg_value[i]));
  const bool agree = worst <= tolerance;
  failures += agree ? 0 : 1;
  std::printf("%-36s tf2      [", what);
  for (int i = 0; i < n; ++i) std::printf("%s% .6f", i ? ", " : "", tf2_value[i]);
  std::printf("]\n%-36s semgraph [", "");
  for (int i = 0; i < n; ++i) std::printf("%s% .6f", i ? ", " : "", sg_value[i]);
  std::printf("]  %s (max diff %.1e)\n", agree ? "agree" : "DISAGREE", worst);
}
void Row(const char* what, const cf::Vec3& x, const cf::Vec3& y, double tolerance = 1e-9) {
  const double a[] = {x.x, x.y, x.z}, b[] = {y.x, y.y, y.z};
  Row(what, a, b, 3, tolerance);
}
void Row(const char* what, cf::Quat x, cf::Quat y) {
  // q and -q are one rotation: print both with w >= 0.
  if (x.w < 0) x = {-x.w, -x.x, -x.y, -x.z};
  if (y.w < 0) y = {-y.w, -y.x, -y.y, -y.z};
  const double a[] = {x.w, x.x, x.y, x.z}, b[] = {y.w, y.x, y.y, y.z};
  Row(what, a, b, 4, 1e-9);
}
void Row(const char* what, bool x, bool y) {
  failures += x == y ? 0 : 1;
  std::printf("%-36s tf2 %-5s  semgraph %-5s  %s\n", what, x ? "true" : "false",
              y ? "true" : "false", x == y ? "agree" : "DISAGREE");
}

}  // namespace

int main() {
  try {
    const cf::Answers tf2 = cf::AskTf2();
    const cf::Answers sg = AskSemgraph();
    std::printf("\n");
    Row("pose of o in b: rotation", tf2.X_BO.q, sg.X_BO.q);
    Row("pose of o in b: position", tf2.X_BO.p, sg.X_BO.p);
    Row("pose of c in w: rotation", tf2.X_WC.q, sg.X_WC.q);
    Row("pose of c in w: position", tf2.X_WC.p, sg.X_WC.p);
    Row("position of o wrt b, in [w]", tf2.p_BoOo_W, sg.p_BoOo_W);
    Row("orientation of o wrt b, in [w]", tf2.R_BO_W, sg.R_BO_W);
    Row("canTransform(w, o)", tf2.can_w_o, sg.can_w_o);
    Row("canTransform(w, k)", tf2.can_w_k, sg.can_w_k);
    // tf2's velocity is a difference quotient of two samples of an exactly linear motion (and
    // a rotation about a fixed axis): exact up to rounding divided by dt.
    Row("velocity of o wrt W, in [w]", tf2.v_WO_W, sg.v_WO_W, 1e-9);
    Row("angular velocity of O wrt W, in [w]", tf2.w_WO_W, sg.w_WO_W, 1e-9);
    std::printf("%-36s tf2 %-5s  semgraph %-5s  (different on purpose: P1)\n",
                "second parent for k accepted", tf2.second_parent_accepted ? "yes" : "no",
                sg.second_parent_accepted ? "yes" : "no");
    if (!tf2.second_parent_accepted || sg.second_parent_accepted) ++failures;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "coming_from_tf2: %s\n", e.what());
    return 2;
  }
  std::printf("\n%s\n", failures == 0 ? "tf2 and semgraph agree." : "tf2 and semgraph DISAGREE.");
  return failures == 0 ? 0 : 1;
}
