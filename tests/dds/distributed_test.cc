// Multi-process tests of distributed scenes (docs/distributed.md), on loopback only
// (CYCLONEDDS_URI = tests/dds/cyclonedds-loopback.xml, set by ctest). Each test has its own DDS
// domain (tests run in parallel), bounds its time, and kills its processes (child_process.h).
// Values are checked against products computed by hand (scenes.h), and mirrors against the
// publisher within 1e-12.
#include <gtest/gtest.h>

#include <map>

#include "child_process.h"
#include "dds_isolation.h"
#include "scenes.h"
#include "semgraph/core/scene_graph_debug.h"
#include "semgraph/dds/mirror.h"

namespace semgraph::dds_test {
namespace {

using namespace std::chrono_literals;

const std::string kNode = SEMGRAPH_DDS_TEST_NODE;

std::map<std::string, std::vector<double>> Parse(const std::vector<std::string>& lines) {
  std::map<std::string, std::vector<double>> out;
  for (const std::string& l : lines) {
    std::string name;
    std::vector<double> v = Numbers(l, &name);
    out[name] = v;
  }
  return out;
}

void ExpectNear(const std::vector<double>& a, const std::vector<double>& b,
                const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_NEAR(a[i], b[i], 1e-12) << what << " [" << i << "]";
}

std::vector<double> PoseNumbers(const Eigen::Isometry3d& X) {
  Eigen::Quaterniond q(X.linear());
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return {
      q.w(), q.x(), q.y(), q.z(), X.translation().x(), X.translation().y(), X.translation().z()};
}
std::vector<double> Canonical(std::vector<double> v) {  // q and -q are one rotation
  if (v.size() == 7 && v[0] < 0) {
    for (int i = 0; i < 4; ++i) v[i] = -v[i];
  }
  return v;
}

TEST(DistributedTest, TwoMirrorProcessesAnswerAsThePublisher) {
  const int kSteps = 1000;  // 1 s of 1 kHz joint updates, object at 30 Hz
  Child m1({kNode, "mirror", "11", "m1", "done", "1", "9000"});
  Child m2({kNode, "mirror", "11", "m2", "done", "1", "9000"});
  Child pub({kNode, "robot", "11", "arm", std::to_string(kSteps)});
  ASSERT_TRUE(pub.started() && m1.started() && m2.started());
  ASSERT_EQ(m1.Wait(10s), 0) << m1.Output();
  ASSERT_EQ(m2.Wait(10s), 0) << m2.Output();
  ASSERT_TRUE(pub.WaitForLine("READY", 5s)) << pub.Output();
  const auto p = Parse(LinesWith(pub.Output(), "P"));
  const auto steps = LinesWith(pub.Output(), "STEPS");
  ASSERT_EQ(steps.size(), 1u);
  int k = 0, j = 0;
  ASSERT_EQ(std::sscanf(steps[0].c_str(), "%d %d", &k, &j), 2);
  EXPECT_EQ(k, kSteps);
  // The publisher against the hand-made products.
  ExpectNear(Canonical(p.at("tool_in_w")), PoseNumbers(ExpectedToolInWorld(k)),
             "publisher tool_in_w");
  ExpectNear(Canonical(p.at("o_in_w")), PoseNumbers(ExpectedObjectInWorld(j)), "publisher o_in_w");
  ASSERT_EQ(p.at("twist_o_C_w").size(), 7u);
  for (Child* m : {&m1, &m2}) {
    const auto q = Parse(LinesWith(m->Output(), "Q"));
    ASSERT_EQ(q.size(), p.size());
    for (const auto& [name, value] : p) ExpectNear(q.at(name), value, "mirror " + name);
    EXPECT_TRUE(LinesWith(m->Output(), "R").empty()) << m->Output();
  }
}

TEST(DistributedTest, ConflictingRelationRefusedAlikeOnBothMirrors) {
  Child m1({kNode, "mirror", "12", "m1", "perception_done,gripper_done", "2", "9000"});
  Child a({kNode, "claim", "12", "perception", "c"});
  ASSERT_TRUE(a.WaitForLine("READY", 5s)) << a.Output();
  std::this_thread::sleep_for(100ms);  // perception's incarnation starts first
  Child b({kNode, "claim", "12", "gripper", "g"});
  Child m2({kNode, "mirror", "12", "m2", "perception_done,gripper_done", "2", "9000"});
  ASSERT_EQ(m1.Wait(10s), 0) << m1.Output();
  ASSERT_EQ(m2.Wait(10s), 0) << m2.Output();
  for (Child* m : {&m1, &m2}) {
    EXPECT_EQ(LinesWith(m->Output(), "R"),
              std::vector<std::string>{"gripper multiple_pose_parents"})
        << m->Output();
    const auto q = Parse(LinesWith(m->Output(), "Q"));
    // o stays where perception put it: X_wc X_co.
    const Eigen::Isometry3d X_wo = Iso(Rz(0.25), {1, 0, 1}) * Iso(Rx(0.5), {0.3, 0, 0});
    ExpectNear(Canonical(q.at("o_in_w")), PoseNumbers(X_wo), "o_in_w");
  }
  EXPECT_EQ(LinesWith(m1.Output(), "Q"), LinesWith(m2.Output(), "Q"));
}

bool HasReport(const dds::Mirror& m, const std::string& event, const std::string& owner) {
  for (const dds::Report& r : m.Reports()) {
    if (r.event == event && r.owner == owner) return true;
  }
  return false;
}

TEST(DistributedTest, KilledPublisherKeepsValuesAndRestartReconciles) {
  auto made = dds::Mirror::Create({"driver", 13, {}, {}, {}, {}});
  ASSERT_TRUE(made) << made.error();
  dds::Mirror& mirror = **made;
  Child pub({kNode, "robot", "13", "arm", "300"});
  ASSERT_TRUE(pub.WaitForLine("READY", 5s)) << pub.Output();
  auto has = [&](const char* frame) {
    bool found = false;
    mirror.WithGraph([&](const core::SceneGraph<>& g) { found = g.FindFrame(frame).is_valid(); });
    return found;
  };
  ASSERT_TRUE(mirror.WaitUntil([&] { return has("done") && mirror.CaughtUp(); }, 5s));
  const auto p = Parse(LinesWith(pub.Output(), "P"));
  std::optional<core::CompiledPose<coord::QuaternionBackend>> tool;
  mirror.WithGraph([&](const core::SceneGraph<>& g) {
    auto c = g.CompilePose(core::PoseSpec::Of("tool").RelativeTo("w"));
    if (c) tool.emplace(std::move(*c));
  });
  ASSERT_TRUE(tool.has_value());

  pub.Kill();  // kill -9 mid-life
  ASSERT_TRUE(mirror.WaitUntil([&] { return HasReport(mirror, "liveliness_lost", "arm"); }, 5s));
  // The last values stay.
  std::string answers;
  mirror.WithGraph([&](const core::SceneGraph<>& g) { answers = Answers(g); });
  const auto kept = Parse(LinesWith(answers, "Q"));
  for (const auto& [name, value] : p) ExpectNear(kept.at(name), value, "kept " + name);
  ASSERT_EQ(mirror.Owners().size(), 1u);
  EXPECT_FALSE(mirror.Owners()[0].alive);

  Child again({kNode, "robot_v2", "13", "arm"});
  ASSERT_TRUE(mirror.WaitUntil([&] { return has("restarted") && mirror.CaughtUp(); }, 5s))
      << again.Output();
  EXPECT_TRUE(HasReport(mirror, "alive", "arm"));
  mirror.WithGraph([&](const core::SceneGraph<>& g) {
    // No leftover: the object's pose and twist are gone; the new edge is there; nothing twice.
    EXPECT_FALSE(g.pose_parent(g.FindFrame("o")).is_valid());
    EXPECT_FALSE(g.twist_parent(g.FindFrame("o")).is_valid());
    EXPECT_EQ(g.num_pose_edges(), 6u);  // b, l1, l2, tool, c, probe
    EXPECT_EQ(g.num_twist_edges(), 0u);
    EXPECT_TRUE(CheckInvariants(g).empty());
    auto X = g.GetPose(core::PoseSpec::Of("probe").RelativeTo("w"));
    ASSERT_TRUE(X);
    const Eigen::Isometry3d X_wp = ExpectedToolInWorld(0) * Iso(Rz(0.5), {0, 0, 0.05});
    ExpectNear(Canonical({X->value.rotation.w(), X->value.rotation.x(), X->value.rotation.y(),
                          X->value.rotation.z(), X->value.translation.x(), X->value.translation.y(),
                          X->value.translation.z()}),
               PoseNumbers(X_wp), "probe_in_w");
  });
  // Kept edges kept their handles: the query compiled before the kill still evaluates, to the
  // restarted publisher's values.
  coord::QuaternionBackend::PoseCoords X_wt;
  ASSERT_EQ(tool->Evaluate(X_wt), base::ErrorCode::kOk);
  const Eigen::Vector3d p_expected = ExpectedToolInWorld(0).translation();
  EXPECT_NEAR((X_wt.translation - p_expected).norm(), 0.0, 1e-12);
  EXPECT_EQ(mirror.Owners().size(), 1u);
  EXPECT_TRUE(mirror.Owners()[0].alive);
}

// Covariances (docs/uncertainty.md) between processes: a publisher process sets a constant
// edge's calibration covariance (in the structure), a pose value with a covariance in the body
// convention, a value with one and then one without (exact again), and a batched twist with one
// in angular_linear order; this process's mirror holds each in the edge form, as computed here
// by hand: diag(R, R) S diag(R, R)^T for the body convention, the halves swapped for the order.
TEST(DistributedTest, CovariancesReachTheMirrorInTheEdgeForm) {
  auto made = dds::Mirror::Create({"driver", 28, {}, {}, {}, {}});
  ASSERT_TRUE(made) << made.error();
  dds::Mirror& mirror = **made;
  Child pub({kNode, "covariance", "28", "arm"});
  const core::Covariance6 S_cam = TestCovariance(1), S_obj = TestCovariance(2);
  const core::Covariance6 S_vel = TestCovariance(4);
  const Eigen::Matrix3d R = Rx(CovarianceObjectRoll()).toRotationMatrix();
  core::Covariance6 B = core::Covariance6::Zero();
  B.topLeftCorner<3, 3>() = R;
  B.bottomRightCorner<3, 3>() = R;
  const core::Covariance6 obj_expected = B * S_obj * B.transpose();
  core::Covariance6 vel_expected;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) vel_expected(i, j) = S_vel((i + 3) % 6, (j + 3) % 6);
  }
  const auto l1_in_b = core::PoseSpec::Of("l1").RelativeTo("b");
  const auto arrived = [&] {
    bool ok = false;
    mirror.WithGraph([&](const core::SceneGraph<>& g) {
      const auto o = g.GetPoseWithCovariance(core::PoseSpec::Of("o").RelativeTo("c"));
      const auto l1 = g.GetPose(l1_in_b);
      const auto v =
          g.GetTwistWithCovariance(core::TwistSpec::Of("o").RelativeTo("C").ExpressedIn("o"));
      ok = g.FindFrame("cam").is_valid() && o && !o->covariance.isZero(0.0) && l1 &&
           l1->value.rotation.angularDistance(Rz(0.2)) < 1e-12 && v && !v->covariance.isZero(0.0);
    });
    return ok;
  };
  ASSERT_TRUE(mirror.WaitUntil(arrived, 20s)) << pub.Output();
  mirror.WithGraph([&](const core::SceneGraph<>& g) {
    const auto cam = g.GetPoseWithCovariance(core::PoseSpec::Of("cam").RelativeTo("l2"));
    ASSERT_TRUE(cam);
    EXPECT_LT((cam->covariance - S_cam).cwiseAbs().maxCoeff(), 1e-18) << cam->covariance;
    const auto o = g.GetPoseWithCovariance(core::PoseSpec::Of("o").RelativeTo("c"));
    ASSERT_TRUE(o);
    EXPECT_LT((o->covariance - obj_expected).cwiseAbs().maxCoeff(), 1e-18) << o->covariance;
    EXPECT_NEAR((o->value.value.translation - ObjectPosition(1)).norm(), 0.0, 1e-15);
    // {l1}'s last value came without a covariance: exact, zero.
    const auto l1 = g.GetPoseWithCovariance(l1_in_b);
    ASSERT_TRUE(l1);
    EXPECT_TRUE(l1->covariance.isZero(0.0)) << l1->covariance;
    EXPECT_TRUE(g.pose_covariance(g.FindFrame("l1")).isZero(0.0));
    const auto v =
        g.GetTwistWithCovariance(core::TwistSpec::Of("o").RelativeTo("C").ExpressedIn("o"));
    ASSERT_TRUE(v);
    EXPECT_LT((v->covariance - vel_expected).cwiseAbs().maxCoeff(), 1e-18) << v->covariance;
    EXPECT_NEAR((v->value.linear - Eigen::Vector3d(0.02, 0, 0)).norm(), 0.0, 1e-15);
  });
  EXPECT_TRUE(mirror.Reports().empty() || mirror.Reports().back().event != "refused");
}

// Accelerations and wrenches from another process: the mirror's answers in [c] equal the edge
// values rotated and moved by hand (the object's pose X_co = (Rx(roll(0)), p(0))).
TEST(DistributedTest, AccelerationsAndWrenchesReachAnotherProcess) {
  auto made = dds::Mirror::Create({"driver", 33, {}, {}, {}, {}});
  ASSERT_TRUE(made) << made.error();
  dds::Mirror& mirror = **made;
  Child pub({kNode, "dynamics", "33", "arm"});
  const auto arrived = [&] {
    bool ok = false;
    mirror.WithGraph([&](const core::SceneGraph<>& g) {
      const auto w = g.GetWrench(core::WrenchSpec::On("O").By("C").At("o"));
      // Queries only (sequence locks): the receive thread may be writing meanwhile.
      ok = g.FindFrame("o").is_valid() &&
           g.GetAcceleration(core::TwistSpec::Of("o").RelativeTo("C").ExpressedIn("o")) && w &&
           w->force == kF_o;
    });
    return ok;
  };
  ASSERT_TRUE(mirror.WaitUntil(arrived, 20s)) << pub.Output();
  const Eigen::Quaterniond q_co = Rx(ObjectRoll(0));
  const Eigen::Vector3d p_co = ObjectPosition(0);
  mirror.WithGraph([&](const core::SceneGraph<>& g) {
    const auto A = g.GetAcceleration(core::TwistSpec::Of("o").RelativeTo("C").ExpressedIn("c"));
    ASSERT_TRUE(A);
    EXPECT_LT((A->linear - q_co * kA_o).norm(), 1e-15);
    EXPECT_LT((A->angular - q_co * kAlpha_o).norm(), 1e-15);
    // On O by C about c's origin in [c]: f_c = R_co f, m_c = R_co m + p_co x f_c; its reaction
    // (on C by O) is the negation.
    const Eigen::Vector3d f_c = q_co * kF_o, m_c = q_co * kM_o + p_co.cross(f_c);
    const auto W = g.GetWrench(core::WrenchSpec::On("O").By("C").At("c"));
    ASSERT_TRUE(W);
    EXPECT_LT((W->force - f_c).norm(), 1e-15);
    EXPECT_LT((W->moment - m_c).norm(), 1e-15);
    const auto R = g.GetWrench(core::WrenchSpec::On("C").By("O").At("c"));
    ASSERT_TRUE(R);
    EXPECT_LT((R->force + f_c).norm(), 1e-15);
    EXPECT_LT((R->moment + m_c).norm(), 1e-15);
  });
  EXPECT_EQ(mirror.messages_rejected(), 0u);
}

TEST(DistributedTest, LateMirrorCatchesUp) {
  Child pub({kNode, "robot", "14", "arm", "200"});
  ASSERT_TRUE(pub.WaitForLine("READY", 5s)) << pub.Output();
  Child late({kNode, "mirror", "14", "late", "done", "1", "5000"});
  ASSERT_EQ(late.Wait(7s), 0) << late.Output();
  const auto p = Parse(LinesWith(pub.Output(), "P"));
  const auto q = Parse(LinesWith(late.Output(), "Q"));
  ASSERT_EQ(q.size(), p.size());
  for (const auto& [name, value] : p) ExpectNear(q.at(name), value, "late " + name);
}

// The issue's scene: one publisher of a 10 s scene (stamps over 10 s, fed as fast as the mirrors
// take them) with 1 kHz joint states (three joints, a mimic, a fixed camera joint) and 30 Hz
// object detections; two mirror processes whose answers at given stamps (on samples, between
// them) equal the publisher's within 1e-12, and the publisher's equal products made by hand.
TEST(DistributedTest, TenSecondJointSceneMirrorsAnswerAsThePublisherAtStamps) {
  Child m1({kNode, "timed_mirror", "15", "m1", "40000"});
  Child m2({kNode, "timed_mirror", "15", "m2", "40000"});
  Child pub({kNode, "joints", "15", "arm", "2"});  // streams once both mirrors matched
  ASSERT_TRUE(pub.started() && m1.started() && m2.started());
  ASSERT_EQ(m1.Wait(45s), 0) << m1.Output().substr(0, 2000);
  ASSERT_EQ(m2.Wait(10s), 0) << m2.Output().substr(0, 2000);
  ASSERT_TRUE(pub.WaitForLine("READY", 10s)) << pub.Output().substr(0, 2000);
  const auto steps = LinesWith(pub.Output(), "STEPS");
  ASSERT_EQ(steps.size(), 1u);
  int k = 0, j = 0;
  unsigned long long failures = 1;
  ASSERT_EQ(std::sscanf(steps[0].c_str(), "%d %d %llu", &k, &j, &failures), 3);
  EXPECT_EQ(k, kJointSteps);
  EXPECT_EQ(j, kDetections);
  EXPECT_EQ(failures, 0u);
  const std::vector<std::string> p_lines = LinesWith(pub.Output(), "P");
  ASSERT_EQ(p_lines.size(), CompareStamps().size() * 6);
  const auto p = Parse(p_lines);
  // The publisher against products made by hand, on joint samples and detections.
  for (int i = 0; i <= 40; ++i) {
    const std::string at = "@" + std::to_string(JointStamp(250 * i));
    ExpectNear(Canonical(p.at("tool_in_w" + at)), PoseNumbers(ExpectedJointTool(250 * i)),
               "publisher tool" + at);
    ExpectNear(Canonical(p.at("finger_in_w" + at)), PoseNumbers(ExpectedFinger(250 * i)),
               "publisher finger" + at);
  }
  for (int d = 7; d <= kDetections; d += 29) {
    const std::string at = "@" + std::to_string(DetectionStamp(d));
    const Eigen::Isometry3d X_wo =
        Iso(kQ_WB, kP_WB) * Iso(kQ_BC, kP_BC) * Iso(Rx(DetectedRoll(d)), DetectedPosition(d));
    ExpectNear(Canonical(p.at("o_in_w" + at)), PoseNumbers(X_wo), "publisher o" + at);
  }
  for (Child* m : {&m1, &m2}) {
    const std::string out = m->Output();
    EXPECT_TRUE(LinesWith(out, "R").empty()) << out.substr(0, 2000);
    const auto received = Parse(LinesWith(out, "S"));
    for (const char* joint : {"joint_j1", "joint_j2", "joint_j3"}) {
      ASSERT_TRUE(received.count(joint)) << joint;
      EXPECT_EQ(received.at(joint), std::vector<double>{double(kJointSteps)}) << joint;
    }
    EXPECT_EQ(received.at("pose_o"), std::vector<double>{double(kDetections)});
    EXPECT_EQ(received.at("twist_o"), std::vector<double>{double(kDetections)});
    const std::vector<std::string> q_lines = LinesWith(out, "Q");
    ASSERT_EQ(q_lines.size(), p_lines.size());
    const auto q = Parse(q_lines);
    for (std::size_t i = 0; i < p_lines.size(); ++i) {
      std::string name;
      const std::vector<double> pv = Numbers(p_lines[i], &name);
      ASSERT_TRUE(q.count(name)) << name;
      if (pv.empty()) {
        EXPECT_EQ(q_lines[i], p_lines[i]);  // the same error
      } else {
        ExpectNear(q.at(name), pv, "mirror " + name);
      }
    }
  }
}

}  // namespace
}  // namespace semgraph::dds_test
