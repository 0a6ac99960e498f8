// spray_painting: the paper's example scene (De Laet et al., IROS 2013, §V), built with the
// semgraph scene graph and queried the way the robot program would: where is the paint point
// relative to the spray gun, and how fast is it moving relative to the gun?
//
// Legend: B robot base {b}, E end effector {e}, O2 spray gun {o2}, O1 cylinder {o1} with the
// paint point {f1}, C camera {c}. X_AB is the pose of B in A; V_AB_E the twist of B relative
// to A expressed in E. The same scene, as a scene script: examples/spray_painting.yaml.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "semgraph/core/scene_graph.h"
#include "semgraph/semantics/describe.h"
#include "spray_painting_scene.h"

namespace sg = semgraph::core;
namespace scene = semgraph::examples::spray_painting;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

void Must(const sg::BuildResult& result) {
  if (!result) {
    std::fprintf(stderr, "unexpected rejection: %s\n", result.error().message.c_str());
    std::exit(1);
  }
}

std::string Vec(const Vector3d& v) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "[%8.4f %8.4f %8.4f]", v.x(), v.y(), v.z());
  return buf;
}

std::string Quat(Quaterniond q) {
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  char buf[112];
  std::snprintf(buf, sizeof(buf), "[w %7.4f  x %7.4f  y %7.4f  z %7.4f]", q.w(), q.x(), q.y(),
                q.z());
  return buf;
}

// Returns a copy: the result is a temporary that dies at the end of the caller's statement.
template <class T>
T Need(const sg::QueryResult<T>& r, const sg::SceneGraph<>& graph) {
  if (!r) {
    std::fprintf(stderr, "%s\n", graph.Describe(r.error()).c_str());
    std::exit(1);
  }
  return *r;
}

}  // namespace

int main() {
  sg::SceneGraph<> graph;  // quaternion + vector coordinates (the default backend)

  std::printf("== Building the scene of the paper's Fig. 8\n");
  for (const scene::EdgePose& e : scene::kPoses) {
    Must(graph.AddPose(sg::PoseSpec::Of(e.of, e.of_body).RelativeTo(e.wrt, e.wrt_body), e.q_PF,
                       e.p_PoFo_P));
    std::printf("  pose  {%s}|%s wrt {%s}|%s\n", e.of, e.of_body, e.wrt, e.wrt_body);
  }
  // The camera is fixed to the base: zero twist, given in [b]; stored as the screw twist at c.
  Must(graph.AddTwist(sg::TwistSpec::Of("c", "C").RelativeTo("B").ExpressedIn("b"),
                      Vector3d::Zero(), Vector3d::Zero()));
  // The camera measures the object's twist in its own axes [c]: not a screw twist of {o1}, so
  // the graph converts it once, with the pose of [c] wrt [o1] (paper §V).
  Must(graph.AddTwist(sg::TwistSpec::Of("o1", "O1").RelativeTo("C").ExpressedIn("c"),
                      scene::kV_CO1_c, scene::kW_CO1_c));
  Must(graph.AddTwist(sg::TwistSpec::Of("o2", "O2").RelativeTo("E").ExpressedIn("o2"),
                      Vector3d::Zero(), Vector3d::Zero()));
  Must(graph.AddTwist(sg::TwistSpec::Of("e", "E").RelativeTo("B").ExpressedIn("e"), scene::kV_BE_e,
                      scene::kW_BE_e));
  std::printf("  twists: %zu twist edges, %zu pose edges, %zu frames on %zu bodies\n",
              graph.num_twist_edges(), graph.num_pose_edges(), graph.num_frames(),
              graph.num_bodies());

  const auto& names = graph.names();
  std::printf("\n== Listing 2 and more\n");
  {
    const auto X = Need(graph.GetPose(sg::PoseSpec::Of("f1", "O1").RelativeTo("o2", "O2")), graph);
    std::printf("%s\n  position %s\n  rotation %s\n",
                semgraph::semantics::Describe(X.semantics, names).c_str(),
                Vec(X.value.translation).c_str(), Quat(X.value.rotation).c_str());
  }
  {
    const auto V = Need(
        graph.GetTwist(sg::TwistSpec::Of("f1", "O1").RelativeTo("O2").ExpressedIn("o2")), graph);
    std::printf(
        "%s   (the paint point's velocity relative to the gun, in the gun frame)\n  v %s\n  w %s\n",
        semgraph::semantics::Describe(V.semantics, names).c_str(), Vec(V.linear).c_str(),
        Vec(V.angular).c_str());
  }
  {
    const auto X = Need(graph.GetPose(sg::PoseSpec::Of("f1", "O1").RelativeTo("b", "B")), graph);
    std::printf("%s   (the paint point in the robot base)\n  position %s\n  rotation %s\n",
                semgraph::semantics::Describe(X.semantics, names).c_str(),
                Vec(X.value.translation).c_str(), Quat(X.value.rotation).c_str());
  }
  {
    auto spec = sg::PoseSpec::Of("f1", "O1").RelativeTo("o2", "O2").ExpressedIn("c");
    const auto p = Need(graph.GetPosition(spec), graph);
    std::printf("%s   (where the gun must point, seen by the camera)\n  p %s\n",
                semgraph::semantics::Describe(p.semantics, names).c_str(), Vec(p.value).c_str());
  }
  {
    const auto v = Need(
        graph.GetLinearVelocity(sg::TwistSpec::Of("o2", "O1").RelativeTo("O2").ExpressedIn("b")),
        graph);
    std::printf(
        "%s   (the object's point under the gun nozzle, relative to the gun, in [b])\n  v %s\n",
        semgraph::semantics::Describe(v.semantics, names).c_str(), Vec(v.value).c_str());
  }
  {
    const auto w =
        Need(graph.GetAngularVelocity(sg::TwistSpec::Of("", "O1").RelativeTo("B").ExpressedIn("b")),
             graph);
    std::printf("%s   (how fast the cylinder turns, seen from the robot base)\n  w %s\n",
                semgraph::semantics::Describe(w.semantics, names).c_str(), Vec(w.value).c_str());
  }

  std::printf("\n== What the graph refuses, and why\n");
  // A second pose parent for the object (Fig. 4, case 2a): rejected, naming the existing edge.
  auto r1 = graph.AddPose(sg::PoseSpec::Of("o1", "O1").RelativeTo("e", "E"),
                          Quaterniond::Identity(), Vector3d::Zero());
  std::printf("  %s\n", r1 ? "accepted?!" : r1.error().message.c_str());
  // Changing a constant pose (both frames on O1): rejected, the stored value stays.
  auto r2 = graph.AddPose(sg::PoseSpec::Of("f1", "O1").RelativeTo("o1", "O1"),
                          scene::Rpy(0, 0, 0.5), Vector3d::Zero());
  std::printf("  %s\n", r2 ? "accepted?!" : r2.error().message.c_str());
  auto r3 = graph.AddTwist(sg::TwistSpec::Of("f1", "O1").RelativeTo("B").ExpressedIn("f1"),
                           Vector3d::Zero(), Vector3d::Zero());
  std::printf("  %s\n", r3 ? "accepted?!" : r3.error().message.c_str());
  auto q = graph.GetPose(sg::PoseSpec::Of("f1", "O1").RelativeTo("o2", "E"));
  // Describe names the code itself: "query failed (frame_body_mismatch): ...".
  std::printf("  query PoseCoord({f1}|O1, {o2}|E, [o2]): %s\n", graph.Describe(q.error()).c_str());
  return 0;
}
