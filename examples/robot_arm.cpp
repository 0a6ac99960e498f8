// A 1 kHz control loop for a 7-DOF arm (models/urdf/arm7.urdf): joint states in, the tool's
// pose and its Jacobian in the frame of an object seen by a camera out.
//
//   semgraph_robot_arm [CYCLES] [URDF]      (default: 1000 cycles, i.e. one second)
//
// Build time (allocates, may fail with a message): load the model, place the robot, the camera
// and the object, make the joint group and compile the queries. Run time (each cycle: no
// allocation, no lock, no exception): set the 7 joint positions and velocities, evaluate the
// compiled pose, Jacobian and twist. The loop checks J qdot against the twist query and exits 1
// when they disagree.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "semgraph/models/urdf.h"

namespace {

using namespace semgraph;
using B = coord::QuaternionBackend;

int Fail(const std::string& what) {
  std::fprintf(stderr, "robot_arm: %s\n", what.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  const int cycles = argc > 1 ? std::atoi(argv[1]) : 1000;
  const std::string urdf = argc > 2 ? argv[2] : std::string(SEMGRAPH_ROBOT_MODELS) + "/arm7.urdf";

  // ------------------------------------------------------------ build time
  core::SceneGraph<B> g;
  auto robot = models::LoadUrdfFile(g, urdf, "arm/");
  if (!robot) return Fail(robot.error().message);
  // The base on the table (fixed: a zero twist), a camera above the table, a cup it sees.
  const auto identity = Eigen::Quaterniond::Identity();
  for (const core::BuildResult& r :
       {g.AddPose(core::PoseSpec::Of("arm/link0").RelativeTo("table", "Table"), identity,
                  Eigen::Vector3d(0.5, 0, 0)),
        g.AddTwist(core::TwistSpec::Of("arm/link0").RelativeTo("Table").ExpressedIn("arm/link0"),
                   Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()),
        g.AddPose(core::PoseSpec::Of("camera", "Camera").RelativeTo("table"),
                  Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX())),
                  Eigen::Vector3d(1.1, 0.1, 1.0)),
        g.AddPose(core::PoseSpec::Of("cup", "Cup").RelativeTo("camera"),
                  Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ())),
                  Eigen::Vector3d(0.05, -0.1, 0.85))}) {
    if (!r) return Fail(r.error().message);
  }
  // The flange relative to the cup, in [cup]; its Jacobian and twist relative to the table, at
  // the flange's origin, in [cup].
  auto tool_in_cup = g.CompilePose(core::PoseSpec::Of("arm/flange").RelativeTo("cup"));
  const auto tool_twist_spec =
      core::TwistSpec::Of("arm/flange").RelativeTo("Table").ExpressedIn("cup");
  auto jacobian = g.CompileJacobian(tool_twist_spec);
  auto twist = g.CompileTwist(tool_twist_spec);
  if (!tool_in_cup || !jacobian || !twist) return Fail("a query did not compile");
  const core::JointGroup& joints = robot->group;  // arm/joint1 .. arm/joint7
  if (joints.size() != 7 || jacobian->num_columns() != 7) return Fail("expected 7 joints");

  // ------------------------------------------------------------ run time (1 kHz)
  Eigen::Matrix<double, 7, 1> q, qdot;
  Eigen::Matrix<double, 6, 7> J;
  B::PoseCoords X_cup_tool;
  Eigen::Vector3d v, w;
  double worst = 0;
  auto next = std::chrono::steady_clock::now();
  for (int k = 0; k < cycles; ++k) {
    const double t = 1e-3 * k;
    for (int i = 0; i < 7; ++i) {  // a smooth motion inside the limits, and its derivative
      const double a = 0.3 + 0.05 * i, f = 0.5 + 0.1 * i;
      q(i) = a * std::sin(f * t) + (i == 3 ? -1.5 : 0.0) + (i == 5 ? 1.5 : 0.0);
      qdot(i) = a * f * std::cos(f * t);
    }
    if (g.SetJointState(joints, {q.data(), 7}, {qdot.data(), 7}) != base::ErrorCode::kOk)
      return Fail("joint state");
    if (tool_in_cup->Evaluate(X_cup_tool) != base::ErrorCode::kOk ||
        jacobian->Evaluate(J) != base::ErrorCode::kOk ||
        twist->Evaluate(v, w) != base::ErrorCode::kOk) {
      return Fail("evaluation");
    }
    const Eigen::Matrix<double, 6, 1> Jqdot = J * qdot;
    worst = std::max({worst, (Jqdot.head<3>() - v).norm(), (Jqdot.tail<3>() - w).norm()});
    next += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(next);
  }
  std::printf("after %d cycles: flange in the cup's frame at [%.6f, %.6f, %.6f] m\n", cycles,
              X_cup_tool.translation.x(), X_cup_tool.translation.y(), X_cup_tool.translation.z());
  std::printf("J (6 x 7, at the flange wrt the table, in [cup]):\n");
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 7; ++c) std::printf(" %9.5f", J(r, c));
    std::printf("\n");
  }
  std::printf("worst |J qdot - twist| over the run: %.3g\n", worst);
  return worst <= 1e-12 ? 0 : Fail("J qdot differs from the twist");
}
