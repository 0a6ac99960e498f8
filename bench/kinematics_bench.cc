// semgraph_kinematics_bench: joints and Jacobians vs KDL on the same URDF and joint states
// (models/urdf/arm6.urdf, arm7.urdf), one binary, one run.
//
//   semgraph_kinematics_bench [google-benchmark flags]       wall time of every kernel
//   semgraph_kinematics_bench --icount KERNEL MODEL ITERS    calls icount_KERNEL ITERS times,
//                                                            for callgrind (kinematics_icount.sh)
// Kernels (n = the model's joints; the end effector is the last link, tool0 / flange):
//   sg_update_pose         SetJointPositions(all n) + compiled pose of the EE wrt the base
//   sg_update_pose_object  SetJointPositions + compiled pose of the EE wrt a cup seen by a
//                          camera on the base (EE -> base -> camera -> cup)
//   sg_jacobian            compiled 6 x n Jacobian of the EE wrt the base, at the EE origin, in
//                          [base] (KDL's convention), into caller storage
//   sg_update_jacobian     SetJointPositions + the compiled Jacobian
//   kdl_fk                 KDL::ChainFkSolverPos_recursive::JntToCart (base -> EE)
//   kdl_jacobian           KDL::ChainJntToJacSolver::JntToJac
// Before timing, each model's answers are checked against KDL's (1e-9), so that the kernels
// compare equal work. Targets (docs/kinematics.md): update + compiled EE pose >= 5x faster than
// kdl_fk; compiled Jacobian >= 3x faster than kdl_jacobian.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "semgraph/models/urdf.h"
#include "support/kdl_from_urdf.h"

namespace {

using namespace semgraph;
using B = coord::QuaternionBackend;

constexpr int kStates = 64;  // joint states cycled through (the same for both libraries)

struct Fixture {
  std::string model_name, ee;
  urdf::ModelInterfaceSharedPtr urdf_model;
  KDL::Chain chain;
  std::unique_ptr<KDL::ChainFkSolverPos_recursive> kdl_fk;
  std::unique_ptr<KDL::ChainJntToJacSolver> kdl_jac;
  std::vector<KDL::JntArray> kdl_q;
  core::SceneGraph<B> graph;
  models::Robot robot;
  core::CompiledPose<B> ee_pose, ee_in_cup;
  core::CompiledJacobian<B> jacobian;
  std::vector<std::vector<double>> q;
  KDL::Frame F;
  KDL::Jacobian J_kdl;
  core::JacobianMatrix J;
  B::PoseCoords X;
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

[[noreturn]] void Die(const std::string& what) {
  std::fprintf(stderr, "semgraph_kinematics_bench: %s\n", what.c_str());
  std::exit(1);
}

Fixture& Get(const std::string& model) {
  static std::unique_ptr<Fixture> fixtures[2];
  const int k = model == "arm6" ? 0 : 1;
  if (fixtures[k]) return *fixtures[k];
  auto f = std::make_unique<Fixture>();
  f->model_name = model;
  f->ee = model == "arm6" ? "tool0" : "flange";
  const std::string xml = ReadFile(std::string(SEMGRAPH_ROBOT_MODELS) + "/" + model + ".urdf");
  f->urdf_model = urdf::parseURDF(xml);
  if (!f->urdf_model) Die("cannot parse " + model);
  const std::string root = f->urdf_model->getRoot()->name;
  KDL::Tree tree = semgraph::testing::KdlTree(*f->urdf_model);
  if (!tree.getChain(root, f->ee, f->chain)) Die("no KDL chain");
  f->kdl_fk = std::make_unique<KDL::ChainFkSolverPos_recursive>(f->chain);
  f->kdl_jac = std::make_unique<KDL::ChainJntToJacSolver>(f->chain);
  auto robot = models::LoadUrdfString(f->graph, xml);
  if (!robot) Die(robot.error().message);
  f->robot = *robot;
  // A camera on the base, a cup seen by it.
  if (!f->graph.AddPose(core::PoseSpec::Of("camera", "Camera").RelativeTo(root),
                        Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX())),
                        Eigen::Vector3d(0.6, 0.1, 1.1)) ||
      !f->graph.AddPose(core::PoseSpec::Of("cup", "Cup").RelativeTo("camera"),
                        Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ())),
                        Eigen::Vector3d(0.05, -0.1, 0.85))) {
    Die("camera / cup");
  }
  auto p = f->graph.CompilePose(core::PoseSpec::Of(f->ee).RelativeTo(root));
  auto pc = f->graph.CompilePose(core::PoseSpec::Of(f->ee).RelativeTo("cup"));
  auto jc = f->graph.CompileJacobian(core::TwistSpec::Of(f->ee).RelativeTo(root).ExpressedIn(root));
  if (!p || !pc || !jc) Die("compile");
  f->ee_pose = std::move(*p);
  f->ee_in_cup = std::move(*pc);
  f->jacobian = std::move(*jc);
  const std::size_t n = f->robot.joints.size();
  f->J.setZero(6, static_cast<Eigen::Index>(n));
  f->J_kdl.resize(static_cast<unsigned>(n));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int s = 0; s < kStates; ++s) {
    std::vector<double> q;
    KDL::JntArray kq(static_cast<unsigned>(n));
    for (std::size_t i = 0; i < n; ++i) {
      const urdf::JointConstSharedPtr j = f->urdf_model->getJoint(f->robot.joints[i]);
      q.push_back(j->limits->lower + (j->limits->upper - j->limits->lower) * unit(rng));
      kq(static_cast<unsigned>(i)) = q.back();  // chain order = the robot's order (serial arms)
    }
    f->q.push_back(q);
    f->kdl_q.push_back(kq);
  }
  // Same answers (chain joint order checked by name).
  std::size_t next = 0;
  for (const KDL::Segment& seg : f->chain.segments) {
    if (seg.getJoint().getType() == KDL::Joint::None) continue;
    if (seg.getJoint().getName() != f->robot.joints[next++]) Die("joint order differs");
  }
  for (int s = 0; s < kStates; ++s) {
    if (f->graph.SetJointPositions(f->robot.group, f->q[static_cast<std::size_t>(s)]) !=
        base::ErrorCode::kOk) {
      Die("set");
    }
    (void)f->ee_pose.Evaluate(f->X);
    f->kdl_fk->JntToCart(f->kdl_q[static_cast<std::size_t>(s)], f->F);
    (void)f->jacobian.Evaluate(f->J);
    f->kdl_jac->JntToJac(f->kdl_q[static_cast<std::size_t>(s)], f->J_kdl);
    const Eigen::Vector3d p_kdl(f->F.p.x(), f->F.p.y(), f->F.p.z());
    if ((f->X.translation - p_kdl).norm() > 1e-9) Die("FK differs from KDL's");
    if ((f->J - f->J_kdl.data).cwiseAbs().maxCoeff() > 1e-9) Die("Jacobian differs from KDL's");
  }
  fixtures[k] = std::move(f);
  return *fixtures[k];
}

}  // namespace

extern "C" {
__attribute__((noinline)) int icount_sg_update_pose(Fixture* f, int s) {
  if (f->graph.SetJointPositions(f->robot.group, f->q[static_cast<std::size_t>(s)]) !=
      base::ErrorCode::kOk)
    return 1;
  return static_cast<int>(f->ee_pose.Evaluate(f->X));
}
__attribute__((noinline)) int icount_sg_update_pose_object(Fixture* f, int s) {
  if (f->graph.SetJointPositions(f->robot.group, f->q[static_cast<std::size_t>(s)]) !=
      base::ErrorCode::kOk)
    return 1;
  return static_cast<int>(f->ee_in_cup.Evaluate(f->X));
}
__attribute__((noinline)) int icount_sg_jacobian(Fixture* f, int) {
  return static_cast<int>(f->jacobian.Evaluate(f->J));
}
__attribute__((noinline)) int icount_sg_update_jacobian(Fixture* f, int s) {
  if (f->graph.SetJointPositions(f->robot.group, f->q[static_cast<std::size_t>(s)]) !=
      base::ErrorCode::kOk)
    return 1;
  return static_cast<int>(f->jacobian.Evaluate(f->J));
}
__attribute__((noinline)) int icount_kdl_fk(Fixture* f, int s) {
  return f->kdl_fk->JntToCart(f->kdl_q[static_cast<std::size_t>(s)], f->F);
}
__attribute__((noinline)) int icount_kdl_jacobian(Fixture* f, int s) {
  return f->kdl_jac->JntToJac(f->kdl_q[static_cast<std::size_t>(s)], f->J_kdl);
}
}

namespace {

using Kernel = int (*)(Fixture*, int);
struct Named {
  const char* name;
  Kernel kernel;
};
constexpr Named kKernels[] = {{"sg_update_pose", icount_sg_update_pose},
                              {"sg_update_pose_object", icount_sg_update_pose_object},
                              {"sg_jacobian", icount_sg_jacobian},
                              {"sg_update_jacobian", icount_sg_update_jacobian},
                              {"kdl_fk", icount_kdl_fk},
                              {"kdl_jacobian", icount_kdl_jacobian}};

void Run(benchmark::State& state, Kernel kernel, const char* model) {
  Fixture& f = Get(model);
  int s = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(kernel(&f, s));
    benchmark::ClobberMemory();
    s = (s + 1) % kStates;
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::strcmp(argv[1], "--icount") == 0) {
    if (argc != 5) Die("usage: --icount KERNEL MODEL ITERS");
    Fixture& f = Get(argv[3]);
    const int iters = std::atoi(argv[4]);
    for (const Named& k : kKernels) {
      if (std::strcmp(k.name, argv[2]) != 0) continue;
      int bad = 0;
      for (int i = 0; i < iters; ++i) bad |= k.kernel(&f, i % kStates);
      return bad;
    }
    Die(std::string("unknown kernel ") + argv[2]);
  }
  for (const char* model : {"arm6", "arm7"}) {
    for (const Named& k : kKernels) {
      benchmark::RegisterBenchmark((std::string(k.name) + "/" + model).c_str(), Run, k.kernel,
                                   model);
    }
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
