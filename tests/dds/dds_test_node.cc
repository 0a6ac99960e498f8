// dds_test_node: the processes of the multi-process DDS tests (distributed_test.cc).
//
//   dds_test_node robot DOMAIN OWNER STEPS         publish the robot scene (scenes.h), stream
//       STEPS joint updates at 1 kHz (object at 30 Hz), then add the frame `done`, republish the
//       structure, print "P" answers and "READY", and stay until killed (at most 20 s).
//   dds_test_node robot_v2 DOMAIN OWNER            the robot's restarted incarnation without the
//       object (edges c->o and the twist gone) and with a new edge {probe} wrt {tool}.
//   dds_test_node claim DOMAIN OWNER PARENT         publish {PARENT} wrt {w} and {o}|O wrt {PARENT}
//       (a conflicting claim when two owners run it with different parents), stay at most 20 s.
//   dds_test_node joints DOMAIN OWNER MIRRORS        the 10 s joint scene (scenes.h), stamped:
//       once MIRRORS mirrors matched (Publisher::WaitForMirrors: the stream is longer than the
//       1024-sample history a late mirror gets) and 2 s more (their readers' side of the
//       match), 10,000 joint states (1 kHz of scene time) and
//       300 detections (30 Hz) as fast as the mirrors take them, then the frame `done`, "P"
//       answers at the compared stamps, "READY".
//   dds_test_node timed_mirror DOMAIN NAME LIMIT_MS  mirror the joint scene until `done`, caught
//       up and every sample applied; print refusals ("R"), samples received per joint
//       ("S name n"), the timed answers ("Q").
//   dds_test_node covariance DOMAIN OWNER         the robot with a calibrated camera {cam} wrt
//       {l2} (constant, covariance TestCovariance(1)); once a mirror matched: {o} wrt {c} set
//       with TestCovariance(2) in the body convention, {l1} wrt {b} set with TestCovariance(3)
//       and then without one (exact again), the twist of {o} in a batch with TestCovariance(4)
//       in angular_linear order; then "READY" (the mirror checks the covariances it got).
//   dds_test_node mirror DOMAIN NAME FRAME OWNERS LIMIT_MS   mirror until frame FRAME exists,
//   OWNERS
//       owners are known and the replica is caught up; then print refusals ("R owner code")
//       and answers ("Q ..."), and exit 0; exit 1 when LIMIT_MS passes first.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "scenes.h"
#include "semgraph/dds/mirror.h"
#include "semgraph/dds/publisher.h"

namespace {

using namespace semgraph;
using namespace std::chrono_literals;

void StayAlive() {
  std::fflush(stdout);
  std::this_thread::sleep_for(20s);  // the driver kills it long before
}

int Robot(std::uint32_t domain, const std::string& owner, int steps) {
  core::SceneGraph<> g;
  if (!dds_test::BuildRobot(g)) return 3;
  auto pub = dds::Publisher::Create(g, {owner, domain});
  if (!pub) {
    std::fprintf(stderr, "%s\n", pub.error().c_str());
    return 3;
  }
  if (!(*pub)->PublishStructure()) return 3;
  auto j1 = g.FindPoseEdge("l1", "b");
  auto j2 = g.FindPoseEdge("l2", "l1");
  auto obj = g.FindPoseEdge("o", "c");
  auto vel = g.FindTwistEdge("o", "C");
  if (!j1 || !j2 || !obj || !vel) return 3;
  std::this_thread::sleep_for(300ms);  // let the mirrors match
  auto next = std::chrono::steady_clock::now();
  int j = 0;
  for (int k = 1; k <= steps; ++k) {
    next += 1ms;
    std::this_thread::sleep_until(next);
    (void)(*pub)->SetPose(*j1, dds_test::Rz(dds_test::Theta1(k)), {0, 0, 0.5});
    (void)(*pub)->SetPose(*j2, dds_test::Ry(dds_test::Theta2(k)), {0.4, 0, 0});
    if (k % 33 == 0) {
      ++j;
      (void)(*pub)->SetPose(*obj, dds_test::Rx(dds_test::ObjectRoll(j)),
                            dds_test::ObjectPosition(j));
      (void)(*pub)->SetTwist(*vel, {0.01 * j, 0, 0}, {0, 0, 0.1});
    }
  }
  if (!g.AddFrame("done", "W") || !(*pub)->PublishStructure()) return 3;
  std::printf("STEPS %d %d\n", steps, j);
  std::string answers = dds_test::Answers(g);
  for (std::size_t i = 0; i < answers.size(); ++i) {
    if (answers[i] == 'Q' && (i == 0 || answers[i - 1] == '\n')) answers[i] = 'P';
  }
  std::fputs(answers.c_str(), stdout);
  std::puts("READY");
  StayAlive();
  return 0;
}

int Covariances(std::uint32_t domain, const std::string& owner) {
  core::SceneGraph<> g;
  if (!dds_test::BuildRobot(g)) return 3;
  const core::Covariance6 S_cam = dds_test::TestCovariance(1), S_obj = dds_test::TestCovariance(2);
  const core::Covariance6 S_l1 = dds_test::TestCovariance(3), S_vel = dds_test::TestCovariance(4);
  const core::CovarianceInput calibration{&S_cam};
  if (!g.AddPose(core::PoseSpec::Of("cam", "L2").RelativeTo("l2", "L2"),
                 Eigen::Quaterniond::Identity(), dds_test::kP_L2Cam, calibration)) {
    return 3;
  }
  auto pub = dds::Publisher::Create(g, {owner, domain});
  if (!pub || !(*pub)->PublishStructure()) return 3;
  auto j1 = g.FindPoseEdge("l1", "b");
  auto obj = g.FindPoseEdge("o", "c");
  auto vel = g.FindTwistEdge("o", "C");
  if (!j1 || !obj || !vel || !(*pub)->WaitForMirrors(1, 20s)) return 3;
  using core::CovarianceOrder;
  using core::PoseCovarianceConvention;
  const core::CovarianceInput body{&S_obj, CovarianceOrder::kLinearAngular,
                                   PoseCovarianceConvention::kBody};
  const core::CovarianceInput swapped{&S_vel, CovarianceOrder::kAngularLinear,
                                      PoseCovarianceConvention::kCoordinates};
  bool ok = (*pub)->SetPose(*obj, dds_test::Rx(dds_test::CovarianceObjectRoll()),
                            dds_test::ObjectPosition(1), body) == base::ErrorCode::kOk;
  ok &= (*pub)->SetPose(*j1, dds_test::Rz(0.1), {0, 0, 0.5}, core::CovarianceInput{&S_l1}) ==
        base::ErrorCode::kOk;
  ok &= (*pub)->SetPose(*j1, dds_test::Rz(0.2), {0, 0, 0.5}) == base::ErrorCode::kOk;
  (*pub)->BeginBatch();
  ok &= (*pub)->SetTwist(*vel, {0.02, 0, 0}, {0, 0, 0.2}, swapped) == base::ErrorCode::kOk;
  (*pub)->Flush();
  if (!ok) return 4;
  std::puts("READY");
  StayAlive();
  return 0;
}

// The dynamics scene (scenes.h): the robot with the object's acceleration and a wrench on O by
// C, their values set once the mirror matched; then stays alive.
int Dynamics(std::uint32_t domain, const std::string& owner) {
  core::SceneGraph<> g;
  if (!dds_test::BuildRobot(g)) return 3;
  if (!g.AddWrench(core::WrenchSpec::On("O").By("C").At("o"), {1, 0, 0}, {0, 0, 0})) return 3;
  auto pub = dds::Publisher::Create(g, {owner, domain});
  if (!pub || !(*pub)->PublishStructure()) return 3;
  auto vel = g.FindTwistEdge("o", "C");
  auto wrench = g.FindWrench("O", "C");
  if (!vel || !wrench || !(*pub)->WaitForMirrors(1, 20s)) return 3;
  bool ok = (*pub)->SetTwist(*vel, {0.01, 0, 0}, {0, 0, 0.1},
                             core::AccelerationInput{dds_test::kA_o, dds_test::kAlpha_o}) ==
            base::ErrorCode::kOk;
  ok &= (*pub)->SetWrench(*wrench, dds_test::kF_o, dds_test::kM_o) == base::ErrorCode::kOk;
  if (!ok) return 4;
  std::puts("READY");
  StayAlive();
  return 0;
}

int Joints(std::uint32_t domain, const std::string& owner, std::uint32_t mirrors) {
  auto made = core::SceneGraph<>::Create(dds_test::TenSecondTime());
  if (!made) return 3;
  core::SceneGraph<>& g = *made;
  if (!dds_test::BuildJointRobot(g)) return 3;
  auto pub = dds::Publisher::Create(g, {owner, domain});
  if (!pub || !(*pub)->PublishStructure()) return 3;
  const std::string_view names[] = {"j1", "j2", "j3"};
  auto group = g.MakeJointGroup(names);
  auto obj = g.FindPoseEdge("o", "c");
  auto vel = g.FindTwistEdge("o", "C");
  if (!group || !obj || !vel) return 3;
  if (auto matched = (*pub)->WaitForMirrors(mirrors, 30s); !matched) {
    std::fprintf(stderr, "%s\n", matched.error().c_str());
    return 3;
  }
  // The writers' side of the match is not the mirrors' readers' side: a sample written before a
  // mirror's reader has matched its writer reaches it only through the transient-local history
  // (the newest 1,024 per edge); one mirror in three or four got 8,900-9,200 of the 10,000 joint
  // samples without this wait, on an idle machine.
  std::this_thread::sleep_for(2s);
  int j = 0;
  for (int k = 1; k <= dds_test::kJointSteps; ++k) {
    const double q[] = {dds_test::Q1(k), dds_test::Q2(k), dds_test::Q3(k)};
    const double qdot[] = {dds_test::Q1dot(k), dds_test::Q2dot(k), dds_test::Q3dot(k)};
    if ((*pub)->SetJointState(*group, q, qdot, core::Stamp::Nanoseconds(dds_test::JointStamp(k))) !=
        base::ErrorCode::kOk) {
      return 4;
    }
    while (j < dds_test::kDetections &&
           dds_test::DetectionStamp(j + 1) <= dds_test::JointStamp(k)) {
      ++j;
      const core::Stamp s = core::Stamp::Nanoseconds(dds_test::DetectionStamp(j));
      if ((*pub)->SetPose(*obj, dds_test::Rx(dds_test::DetectedRoll(j)),
                          dds_test::DetectedPosition(j), s) != base::ErrorCode::kOk ||
          (*pub)->SetTwist(*vel, {0.01 * j, 0, 0}, {0, 0, 0.1}, s) != base::ErrorCode::kOk) {
        return 4;
      }
    }
    // As fast as the mirrors take them: a short pause every 50 steps keeps each edge's writer
    // history (1024 samples) ahead of the acknowledgements on a loaded machine.
    if (k % 50 == 0) std::this_thread::sleep_for(1ms);
  }
  if (!g.AddFrame("done", "W") || !(*pub)->PublishStructure()) return 3;
  std::printf("STEPS %d %d %llu\n", dds_test::kJointSteps, j,
              static_cast<unsigned long long>((*pub)->write_failures()));
  std::string answers = dds_test::TimedAnswers(g);
  for (std::size_t i = 0; i < answers.size(); ++i) {
    if (answers[i] == 'Q' && (i == 0 || answers[i - 1] == '\n')) answers[i] = 'P';
  }
  std::fputs(answers.c_str(), stdout);
  std::puts("READY");
  StayAlive();
  return 0;
}

// Every stamped sample of the joint scene applied (j1, j2, j3: kJointSteps each; o's pose and
// twist: kDetections each). CaughtUp is about each edge's latest value, which comes on the values
// topic; the samples come on their own topic and may still be in flight then (seen on a loaded
// 2-core machine: 9,774 of 10,000). A lost sample still fails: the wait then times out.
bool AllSamplesApplied(const dds::Mirror& mirror) {
  int complete = 0;
  for (const dds::EdgeState& e : mirror.Edges()) {
    const bool joint = e.joint && (e.head == "j1" || e.head == "j2" || e.head == "j3");
    const bool detection = !e.joint && e.head == "o";
    if (!joint && !detection) continue;
    if (e.received <
        static_cast<std::uint64_t>(joint ? dds_test::kJointSteps : dds_test::kDetections)) {
      return false;
    }
    ++complete;
  }
  return complete == 5;
}

int TimedMirror(std::uint32_t domain, const std::string& name, int limit_ms) {
  auto m = dds::Mirror::Create({name, domain, {}, {}, {}, {}});
  if (!m) return 3;
  dds::Mirror& mirror = **m;
  const bool done = mirror.WaitUntil(
      [&] {
        bool has = false;
        mirror.WithGraph(
            [&](const core::SceneGraph<>& g) { has = g.FindFrame("done").is_valid(); });
        return has && mirror.Owners().size() == 1 && mirror.CaughtUp() && AllSamplesApplied(mirror);
      },
      std::chrono::milliseconds(limit_ms));
  if (!done) {
    std::puts("TIMEOUT");
    return 1;
  }
  for (const dds::Report& r : mirror.Refusals())
    std::printf("R %s %s\n", r.owner.c_str(), r.code.c_str());
  for (const dds::EdgeState& e : mirror.Edges()) {
    std::printf("S %s%s %llu\n",
                e.joint   ? "joint_"
                : e.twist ? "twist_"
                          : "pose_",
                e.head.c_str(), static_cast<unsigned long long>(e.received));
  }
  std::printf("DROPPED %llu REJECTED %llu\n",
              static_cast<unsigned long long>(mirror.samples_dropped()),
              static_cast<unsigned long long>(mirror.messages_rejected()));
  std::string answers;
  mirror.WithGraph([&](const core::SceneGraph<>& g) { answers = dds_test::TimedAnswers(g); });
  std::fputs(answers.c_str(), stdout);
  std::puts("DONE");
  std::fflush(stdout);
  return 0;
}

int RobotV2(std::uint32_t domain, const std::string& owner) {
  core::SceneGraph<> g;
  if (!dds_test::BuildRobot(g)) return 3;
  if (!g.RemoveTwist("o", "C") || !g.RemovePose("o", "c")) return 3;
  if (!g.AddPose(core::PoseSpec::Of("probe", "P").RelativeTo("tool", "L2"), dds_test::Rz(0.5),
                 {0, 0, 0.05}))
    return 3;
  if (!g.AddFrame("restarted", "W")) return 3;
  auto pub = dds::Publisher::Create(g, {owner, domain});
  if (!pub || !(*pub)->PublishStructure()) return 3;
  std::puts("READY");
  StayAlive();
  return 0;
}

int Claim(std::uint32_t domain, const std::string& owner, const std::string& parent) {
  core::SceneGraph<> g;
  const std::string body = parent == "c" ? "C" : "G";
  const Eigen::Vector3d p_parent =
      parent == "c" ? Eigen::Vector3d(1, 0, 1) : Eigen::Vector3d(0, 2, 0);
  if (!g.AddPose(core::PoseSpec::Of(parent, body).RelativeTo("w", "W"), dds_test::Rz(0.25),
                 p_parent) ||
      !g.AddPose(core::PoseSpec::Of("o", "O").RelativeTo(parent, body), dds_test::Rx(0.5),
                 {0.3, 0, 0}) ||
      !g.AddFrame(owner + "_done", "W")) {
    return 3;
  }
  auto pub = dds::Publisher::Create(g, {owner, domain});
  if (!pub || !(*pub)->PublishStructure()) return 3;
  std::puts("READY");
  StayAlive();
  return 0;
}

int MirrorMain(std::uint32_t domain, const std::string& name, const std::string& frame,
               std::size_t owners, int limit_ms) {
  auto m = dds::Mirror::Create({name, domain, {}, {}, {}, {}});
  if (!m) {
    std::fprintf(stderr, "%s\n", m.error().c_str());
    return 3;
  }
  dds::Mirror& mirror = **m;
  const bool done = mirror.WaitUntil(
      [&] {
        bool has = false;
        mirror.WithGraph([&](const core::SceneGraph<>& g) {
          has = true;
          for (std::size_t a = 0, b; a <= frame.size(); a = b + 1) {
            b = frame.find(',', a);
            if (b == std::string::npos) b = frame.size();
            has = has && g.FindFrame(frame.substr(a, b - a)).is_valid();
          }
        });
        return has && mirror.Owners().size() == owners && mirror.CaughtUp();
      },
      std::chrono::milliseconds(limit_ms));
  if (!done) {
    std::puts("TIMEOUT");
    return 1;
  }
  for (const dds::Report& r : mirror.Refusals())
    std::printf("R %s %s\n", r.owner.c_str(), r.code.c_str());
  std::string answers;
  mirror.WithGraph([&](const core::SceneGraph<>& g) { answers = dds_test::Answers(g); });
  std::fputs(answers.c_str(), stdout);
  std::puts("DONE");
  std::fflush(stdout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (argc < 4) return 2;
  const auto domain = static_cast<std::uint32_t>(std::atoi(argv[2]));
  if (mode == "robot" && argc == 5) return Robot(domain, argv[3], std::atoi(argv[4]));
  if (mode == "robot_v2" && argc == 4) return RobotV2(domain, argv[3]);
  if (mode == "covariance" && argc == 4) return Covariances(domain, argv[3]);
  if (mode == "dynamics" && argc == 4) return Dynamics(domain, argv[3]);
  if (mode == "joints" && argc == 5) {
    return Joints(domain, argv[3], static_cast<std::uint32_t>(std::atoi(argv[4])));
  }
  if (mode == "timed_mirror" && argc == 5) return TimedMirror(domain, argv[3], std::atoi(argv[4]));
  if (mode == "claim" && argc == 5) return Claim(domain, argv[3], argv[4]);
  if (mode == "mirror" && argc == 7) {
    return MirrorMain(domain, argv[3], argv[4], static_cast<std::size_t>(std::atoi(argv[5])),
                      std::atoi(argv[6]));
  }
  return 2;
}
