// Forward kinematics and Jacobians of URDF robots loaded by semgraph::models, cross-checked
// against KDL (liborocos-kdl) on the same URDF (the KDL tree built from the urdfdom model,
// tests/support/kdl_from_urdf.h) at 1,000 random joint states per model:
//   - the pose of every link relative to the root link, within 1e-9;
//   - the Jacobian of every link wrt the root body, at the link origin in [root] (KDL's
//     ChainJntToJacSolver convention), at the root origin in [root] (Pinocchio's WORLD), and
//     at the link origin in [link] (LOCAL), converted from KDL's, within 1e-9; mimic joints
//     merged into their master's column (KDL has a column per joint);
//   - one-shot and compiled Jacobians agree; J qdot equals the twist query;
//   - the twist query equals the finite-difference derivative of the pose query under
//     q(t) = q + t qdot, to O(h^2) (the error ratio for h and h/2 is about 4).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/treefksolverpos_recursive.hpp>
#include <map>
#include <random>
#include <sstream>

#include "semgraph/models/urdf.h"
#include "support/kdl_from_urdf.h"

namespace semgraph::models {
namespace {

using core::ErrorCode;
using core::PoseSpec;
using core::TwistSpec;
using Graph = core::SceneGraph<>;

constexpr int kStates = 1000;
constexpr double kTol = 1e-9;

std::string ReadModel(const std::string& file) {
  std::ifstream in(std::string(SEMGRAPH_ROBOT_MODELS) + "/" + file);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Eigen::Matrix3d ToEigen(const KDL::Rotation& R) {
  Eigen::Matrix3d out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out(i, j) = R(i, j);
  return out;
}
Eigen::Vector3d ToEigen(const KDL::Vector& v) { return {v.x(), v.y(), v.z()}; }

struct Counts {
  int poses = 0, jacobians = 0, twists = 0;
};

class CrossCheck : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    xml_ = ReadModel(GetParam());
    model_ = urdf::parseURDF(xml_);
    ASSERT_TRUE(model_);
    tree_ = testing::KdlTree(*model_);
    auto robot = LoadUrdfString(g_, xml_);
    ASSERT_TRUE(robot) << robot.error().message;
    robot_ = *robot;
  }
  // Uniform in the limits (continuous: [-pi, pi]); velocities in [-1, 1].
  void RandomState(std::mt19937& rng, std::vector<double>& q, std::vector<double>& qdot) const {
    q.clear();
    qdot.clear();
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (const std::string& name : robot_.joints) {
      const urdf::JointConstSharedPtr j = model_->getJoint(name);
      double lo = -M_PI, hi = M_PI;
      if (j->type != urdf::Joint::CONTINUOUS) {
        lo = j->limits->lower;
        hi = j->limits->upper;
      }
      q.push_back(lo + (hi - lo) * unit(rng));
      qdot.push_back(-1 + 2 * unit(rng));
    }
  }
  std::map<std::string, double> ByName(const std::vector<double>& v) const {
    std::map<std::string, double> out;
    for (std::size_t i = 0; i < v.size(); ++i) out[robot_.joints[i]] = v[i];
    return out;
  }
  // KDL's Jacobian of `tip` (ref point: tip origin, in [root]) with columns merged as ours.
  Eigen::MatrixXd KdlJacobian(const std::string& tip, const KDL::JntArray& q_tree,
                              const std::vector<core::JointHandle>& columns) {
    KDL::Chain chain;
    EXPECT_TRUE(tree_.getChain(robot_.root, tip, chain));
    KDL::JntArray q(chain.getNrOfJoints());
    std::vector<std::string> names;
    for (const KDL::Segment& s : chain.segments) {
      if (s.getJoint().getType() == KDL::Joint::None) continue;
      q(names.size()) = q_tree(tree_.getSegment(s.getName())->second.q_nr);
      names.push_back(s.getJoint().getName());
    }
    KDL::Jacobian J(chain.getNrOfJoints());
    KDL::ChainJntToJacSolver solver(chain);
    EXPECT_EQ(solver.JntToJac(q, J), 0);
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(6, static_cast<Eigen::Index>(columns.size()));
    for (std::size_t k = 0; k < names.size(); ++k) {
      const urdf::JointConstSharedPtr j = model_->getJoint(names[k]);
      const std::string master = j->mimic ? j->mimic->joint_name : j->name;
      const double scale = j->mimic ? j->mimic->multiplier : 1.0;
      std::size_t col = columns.size();
      for (std::size_t c = 0; c < columns.size(); ++c) {
        if (g_.joint_name(columns[c]) == master) col = c;
      }
      EXPECT_LT(col, columns.size()) << "no column for " << master;
      if (col == columns.size()) continue;
      out.col(static_cast<Eigen::Index>(col)) += scale * J.data.col(static_cast<Eigen::Index>(k));
    }
    return out;
  }

  std::string xml_;
  urdf::ModelInterfaceSharedPtr model_;
  KDL::Tree tree_;
  Graph g_;
  Robot robot_;
};

TEST_P(CrossCheck, PosesAndJacobiansOfEveryLinkEqualKdls) {
  std::mt19937 rng(20261122);
  KDL::TreeFkSolverPos_recursive fk(tree_);
  const std::string& root = robot_.root;
  // Compiled Jacobians (LOCAL_WORLD_ALIGNED-like: at the link origin, in [root]) per link.
  std::vector<core::CompiledJacobian<coord::QuaternionBackend>> compiled;
  for (const std::string& link : robot_.links) {
    auto c = g_.CompileJacobian(TwistSpec::Of(link).RelativeTo(root).ExpressedIn(root));
    ASSERT_TRUE(c);
    compiled.push_back(std::move(*c));
  }
  Counts n;
  std::vector<double> q, qdot;
  for (int s = 0; s < kStates; ++s) {
    RandomState(rng, q, qdot);
    ASSERT_EQ(g_.SetJointState(robot_.group, q, qdot), ErrorCode::kOk);
    const KDL::JntArray q_kdl = testing::KdlPositions(*model_, tree_, ByName(q));
    for (std::size_t li = 0; li < robot_.links.size(); ++li) {
      const std::string& link = robot_.links[li];
      // Pose.
      KDL::Frame F;
      ASSERT_GE(fk.JntToCart(q_kdl, F, link), 0);
      auto X = g_.GetPose(PoseSpec::Of(link).RelativeTo(root));
      ASSERT_TRUE(X);
      const Eigen::Matrix3d R = X->value.rotation.toRotationMatrix();
      ASSERT_LE((R - ToEigen(F.M)).cwiseAbs().maxCoeff(), kTol) << link << " state " << s;
      ASSERT_LE((X->value.translation - ToEigen(F.p)).cwiseAbs().maxCoeff(), kTol)
          << link << " state " << s;
      ++n.poses;
      if (link == root) continue;
      // Jacobian at the link origin in [root].
      auto J = g_.GetJacobian(TwistSpec::Of(link).RelativeTo(root).ExpressedIn(root));
      ASSERT_TRUE(J);
      const Eigen::MatrixXd J_kdl = KdlJacobian(link, q_kdl, J->joints);
      if (J->J.cols() == 0) {  // only fixed joints between the root and this link
        KDL::Chain chain;
        ASSERT_TRUE(tree_.getChain(root, link, chain));
        ASSERT_EQ(chain.getNrOfJoints(), 0u) << link;
        continue;
      }
      ASSERT_LE((J->J - J_kdl).cwiseAbs().maxCoeff(), kTol) << link << " state " << s << "\n"
                                                            << J->J << "\n"
                                                            << J_kdl;
      core::JacobianMatrix Jc(6, static_cast<Eigen::Index>(compiled[li].num_columns()));
      ASSERT_EQ(compiled[li].Evaluate(Jc), ErrorCode::kOk);
      ASSERT_EQ(compiled[li].joints(), J->joints);
      ASSERT_LE((Jc - J->J).cwiseAbs().maxCoeff(), 1e-13) << link;  // composed in another order
      // At the root origin (the point of the link coinciding with it), in [root]: KDL's
      // Jacobian with its reference point moved by -p (v' = v + w x (0 - p)).
      auto J_world = g_.GetJacobian(TwistSpec::Of(root, link).RelativeTo(root).ExpressedIn(root));
      ASSERT_TRUE(J_world);
      Eigen::MatrixXd J_kdl_world = J_kdl;
      for (Eigen::Index c = 0; c < J_kdl.cols(); ++c) {
        const Eigen::Vector3d w = J_kdl.col(c).tail<3>();
        J_kdl_world.col(c).head<3>() += w.cross(-ToEigen(F.p));
      }
      ASSERT_LE((J_world->J - J_kdl_world).cwiseAbs().maxCoeff(), kTol) << link;
      // At the link origin in [link]: KDL's rotated by R^T.
      auto J_local = g_.GetJacobian(TwistSpec::Of(link).RelativeTo(root).ExpressedIn(link));
      ASSERT_TRUE(J_local);
      Eigen::MatrixXd J_kdl_local = J_kdl;
      J_kdl_local.topRows<3>() = R.transpose() * J_kdl.topRows<3>();
      J_kdl_local.bottomRows<3>() = R.transpose() * J_kdl.bottomRows<3>();
      ASSERT_LE((J_local->J - J_kdl_local).cwiseAbs().maxCoeff(), kTol) << link;
      n.jacobians += 3;
      // J qdot equals the twist query.
      auto V = g_.GetTwist(TwistSpec::Of(link).RelativeTo(root).ExpressedIn(root));
      ASSERT_TRUE(V);
      Eigen::VectorXd qdot_cols(J->joints.size());
      for (std::size_t c = 0; c < J->joints.size(); ++c)
        qdot_cols(c) = g_.joint_velocity(J->joints[c]);
      const Eigen::Matrix<double, 6, 1> Jq = J->J * qdot_cols;
      ASSERT_LE((Jq.head<3>() - V->linear).cwiseAbs().maxCoeff(), kTol) << link;
      ASSERT_LE((Jq.tail<3>() - V->angular).cwiseAbs().maxCoeff(), kTol) << link;
      ++n.twists;
    }
  }
  RecordProperty("poses", n.poses);
  RecordProperty("jacobians", n.jacobians);
  std::printf(
      "[ cross-check ] %s: %d states, %d link poses, %d Jacobians, %d twists vs KDL within %g\n",
      GetParam(), kStates, n.poses, n.jacobians, n.twists, kTol);
}

// The finite-difference velocity of link's origin and its angular velocity, central, step h,
// under q(t) = q + t qdot.
void FiniteDifference(Graph& g, const Robot& robot, const std::vector<double>& q,
                      const std::vector<double>& qdot, const std::string& link, double h,
                      Eigen::Vector3d& v, Eigen::Vector3d& w) {
  std::vector<double> qa(q.size()), qb(q.size());
  for (std::size_t i = 0; i < q.size(); ++i) {
    qa[i] = q[i] + h * qdot[i];
    qb[i] = q[i] - h * qdot[i];
  }
  // The limits are checked on the set joints: stay inside (the state is drawn inside with margin).
  ASSERT_EQ(g.SetJointPositions(robot.group, qa), ErrorCode::kOk);
  auto Xa = g.GetPose(PoseSpec::Of(link).RelativeTo(robot.root));
  ASSERT_EQ(g.SetJointPositions(robot.group, qb), ErrorCode::kOk);
  auto Xb = g.GetPose(PoseSpec::Of(link).RelativeTo(robot.root));
  ASSERT_TRUE(Xa && Xb);
  v = (Xa->value.translation - Xb->value.translation) / (2 * h);
  const Eigen::AngleAxisd dR(Xa->value.rotation * Xb->value.rotation.inverse());
  w = dR.axis() * dR.angle() / (2 * h);
  ASSERT_EQ(g.SetJointPositions(robot.group, q), ErrorCode::kOk);
}

TEST_P(CrossCheck, TwistQueryIsTheDerivativeOfThePoseQuery) {
  std::mt19937 rng(7);
  std::vector<double> q, qdot;
  int checked = 0;
  double worst_ratio_dev = 0;
  for (int s = 0; s < 40; ++s) {
    RandomState(rng, q, qdot);
    // Keep q(t) inside the limits for |t| <= 0.02.
    for (std::size_t i = 0; i < q.size(); ++i) {
      const urdf::JointConstSharedPtr j = model_->getJoint(robot_.joints[i]);
      if (j->type == urdf::Joint::CONTINUOUS) continue;
      const double width = j->limits->upper - j->limits->lower;
      if (width < 0.1) {  // a narrow range (the fingers): the middle, and a slower velocity
        q[i] = 0.5 * (j->limits->lower + j->limits->upper);
        qdot[i] *= 0.9 * std::min(1.0, width / 0.04);
      } else {
        q[i] = std::clamp(q[i], j->limits->lower + 0.03, j->limits->upper - 0.03);
      }
    }
    ASSERT_EQ(g_.SetJointState(robot_.group, q, qdot), ErrorCode::kOk);
    for (const std::string& link : robot_.links) {
      if (link == robot_.root) continue;
      auto V = g_.GetTwist(TwistSpec::Of(link).RelativeTo(robot_.root).ExpressedIn(robot_.root));
      ASSERT_TRUE(V);
      Eigen::Vector3d v1, w1, v2, w2, v3, w3;
      FiniteDifference(g_, robot_, q, qdot, link, 1e-4, v1, w1);
      EXPECT_LE((v1 - V->linear).norm(), 1e-7) << link;
      EXPECT_LE((w1 - V->angular).norm(), 1e-7) << link;
      // O(h^2): halving h quarters the error (checked where the error is far above rounding).
      FiniteDifference(g_, robot_, q, qdot, link, 2e-2, v2, w2);
      FiniteDifference(g_, robot_, q, qdot, link, 1e-2, v3, w3);
      const double e2 = (v2 - V->linear).norm() + (w2 - V->angular).norm();
      const double e3 = (v3 - V->linear).norm() + (w3 - V->angular).norm();
      if (e2 > 1e-6) {
        const double ratio = e2 / e3;
        EXPECT_GT(ratio, 3.5) << link;
        EXPECT_LT(ratio, 4.5) << link;
        worst_ratio_dev = std::max(worst_ratio_dev, std::abs(ratio - 4));
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 20);
  std::printf("[ finite-diff ] %s: %d error ratios, worst |ratio - 4| = %.3f\n", GetParam(),
              checked, worst_ratio_dev);
}

INSTANTIATE_TEST_SUITE_P(Models, CrossCheck,
                         ::testing::Values("arm6.urdf", "arm7.urdf", "mobile_manipulator.urdf"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string n = info.param;
                           return n.substr(0, n.find('.'));
                         });

}  // namespace
}  // namespace semgraph::models
