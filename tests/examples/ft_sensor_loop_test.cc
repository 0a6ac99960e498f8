// The F/T-sensor example (examples/ft_sensor_loop.h) checked against values computed here:
// the arm's forward kinematics written out with explicit rotation matrices (not the example's
// Eigen::Isometry chain), the wrenches moved by hand (f unchanged, m_q = m_p + (p - q) x f,
// then rotated), and, when KDL is found, KDL's Frame * Wrench on a KDL::Frame chain. Also: the
// tool's weight stays vertical in the world as the arm moves (it is rewritten each tick), and
// the example's loop allocates nothing after setup (tests/support/alloc_counter.h).
#include "ft_sensor_loop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "support/alloc_counter.h"

#ifdef SEMGRAPH_TEST_WITH_KDL
#include <kdl/frames.hpp>
#endif

namespace semgraph::examples::ft_sensor {
namespace {

using Mat = Eigen::Matrix3d;
constexpr double kTol = 1e-10;

Mat RotZ(double a) {
  Mat R;
  R << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  return R;
}
Mat RotY(double a) {
  Mat R;
  R << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  return R;
}

// World rotation and position of a frame.
struct WorldPose {
  Mat R;
  Vec p;
  WorldPose Then(const Mat& R_local, const Vec& p_local) const {
    return {R * R_local, p + R * p_local};
  }
};

struct Frames {
  WorldPose base, ft, com, tcp;
};

// The arm's forward kinematics, frame by frame from the table in ft_sensor_loop.h.
Frames Fk(const Joints& q) {
  Frames F;
  F.base = WorldPose{RotZ(kBaseYaw), kBaseOrigin};
  const WorldPose flange = F.base.Then(RotZ(q.q1), kLink1Origin)
                               .Then(RotY(q.q2), kLink2Origin)
                               .Then(RotY(q.q3), kLink3Origin)
                               .Then(Mat::Identity(), kFlangeOrigin);
  F.ft = flange.Then(RotY(kFtPitch), kFtOrigin);
  F.com = F.ft.Then(Mat::Identity(), kComOrigin);
  F.tcp = F.ft.Then(RotZ(kTcpYaw), kTcpOrigin);
  return F;
}

// The contact on Tool by the environment, about {tcp}, in [world]: minus the sum of the reading
// (about {ft}, in [ft]) and the weight (at {tool_com}, in [world]), both moved to {tcp}.
ForceMoment ExpectedContactInWorld(const Frames& F, const ForceMoment& reading) {
  const Vec f_sensor = F.ft.R * reading.f;
  const Vec m_sensor = F.ft.R * reading.m + (F.ft.p - F.tcp.p).cross(f_sensor);
  const Vec f_weight(0, 0, -kToolMass * kGravity);
  const Vec m_weight = (F.com.p - F.tcp.p).cross(f_weight);
  return {-(f_sensor + f_weight), -(m_sensor + m_weight)};
}

ForceMoment Rotated(const Mat& R, const ForceMoment& w) { return {R * w.f, R * w.m}; }

void ExpectNear(const Vec& actual, const Vec& expected, const char* what) {
  EXPECT_LT((actual - expected).norm(), kTol)
      << what << ": " << actual.transpose() << " vs " << expected.transpose();
}

Joints RandomJoints(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  return {u(rng), u(rng), u(rng)};
}
Vec RandomVec(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Vec(u(rng), u(rng), u(rng));
}

class FtSensorLoopTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(loop.Setup(), ""); }
  FtSensorLoop loop;
  std::mt19937_64 rng{20261205};
};

TEST_F(FtSensorLoopTest, ContactAtTcpMatchesHandComputedWrenches) {
  for (int i = 0; i < 200; ++i) {
    const Joints q = RandomJoints(rng);
    const ForceMoment reading{RandomVec(rng, 20), RandomVec(rng, 3)};
    ContactAtTcp out;
    ASSERT_TRUE(loop.Tick(q, reading, out));
    const Frames F = Fk(q);
    const ForceMoment contact_W = ExpectedContactInWorld(F, reading);
    const ForceMoment in_tcp = Rotated(F.tcp.R.transpose(), contact_W);
    const ForceMoment in_base = Rotated(F.base.R.transpose(), contact_W);
    ExpectNear(out.in_tcp.f, in_tcp.f, "force in [tcp]");
    ExpectNear(out.in_tcp.m, in_tcp.m, "moment about tcp in [tcp]");
    ExpectNear(out.in_base.f, in_base.f, "force in [base]");
    ExpectNear(out.in_base.m, in_base.m, "moment about tcp in [base]");
  }
}

// With no reading, the contact is minus the weight: vertical in the world at every pose (a
// weight stored once in [tool_com] and not rewritten would turn with the tool).
TEST_F(FtSensorLoopTest, WeightStaysVerticalAsTheArmMoves) {
  for (int i = 0; i < 50; ++i) {
    const Joints q = RandomJoints(rng);
    ContactAtTcp out;
    ASSERT_TRUE(loop.Tick(q, ForceMoment{}, out));
    const Frames F = Fk(q);
    const Vec up_in_base = F.base.R.transpose() * Vec(0, 0, kToolMass * kGravity);
    ExpectNear(out.in_base.f, up_in_base, "minus the weight, in [base]");
    const Vec lever = F.com.p - F.tcp.p;  // m_tcp of the weight, negated
    ExpectNear(out.in_base.m, F.base.R.transpose() * -lever.cross(Vec(0, 0, -kToolMass * kGravity)),
               "minus the weight's moment about tcp, in [base]");
  }
}

#ifdef SEMGRAPH_TEST_WITH_KDL
KDL::Vector ToKdl(const Vec& v) { return KDL::Vector(v.x(), v.y(), v.z()); }
Vec FromKdl(const KDL::Vector& v) { return Vec(v.x(), v.y(), v.z()); }
KDL::Frame Offset(const KDL::Rotation& R, const Vec& p) { return KDL::Frame(R, ToKdl(p)); }

// KDL: the reading carried to the world origin with Frame * Wrench along a KDL::Frame chain, the
// weight from {tool_com} (world axes) likewise, summed, and carried back to {tcp} with
// Frame::Inverse() * Wrench, in [tcp] and in [base].
TEST_F(FtSensorLoopTest, ContactAtTcpMatchesKdlFrameTimesWrench) {
  for (int i = 0; i < 200; ++i) {
    const Joints q = RandomJoints(rng);
    const ForceMoment reading{RandomVec(rng, 20), RandomVec(rng, 3)};
    ContactAtTcp out;
    ASSERT_TRUE(loop.Tick(q, reading, out));
    const KDL::Frame X_W_base = Offset(KDL::Rotation::RotZ(kBaseYaw), kBaseOrigin);
    const KDL::Frame X_W_ft = X_W_base * Offset(KDL::Rotation::RotZ(q.q1), kLink1Origin) *
                              Offset(KDL::Rotation::RotY(q.q2), kLink2Origin) *
                              Offset(KDL::Rotation::RotY(q.q3), kLink3Origin) *
                              Offset(KDL::Rotation::Identity(), kFlangeOrigin) *
                              Offset(KDL::Rotation::RotY(kFtPitch), kFtOrigin);
    const KDL::Frame X_W_com = X_W_ft * Offset(KDL::Rotation::Identity(), kComOrigin);
    const KDL::Frame X_W_tcp = X_W_ft * Offset(KDL::Rotation::RotZ(kTcpYaw), kTcpOrigin);
    const KDL::Wrench sensor_W = X_W_ft * KDL::Wrench(ToKdl(reading.f), ToKdl(reading.m));
    const KDL::Wrench weight_W =
        KDL::Frame(X_W_com.p) *
        KDL::Wrench(KDL::Vector(0, 0, -kToolMass * kGravity), KDL::Vector::Zero());
    const KDL::Wrench contact_W = -(sensor_W + weight_W);  // about the world origin
    const KDL::Wrench in_tcp = X_W_tcp.Inverse() * contact_W;
    const KDL::Wrench in_base = KDL::Frame(X_W_base.M, X_W_tcp.p).Inverse() * contact_W;
    ExpectNear(out.in_tcp.f, FromKdl(in_tcp.force), "KDL force in [tcp]");
    ExpectNear(out.in_tcp.m, FromKdl(in_tcp.torque), "KDL moment in [tcp]");
    ExpectNear(out.in_base.f, FromKdl(in_base.force), "KDL force in [base]");
    ExpectNear(out.in_base.m, FromKdl(in_base.torque), "KDL moment in [base]");
  }
}
#endif

// The example's loop (the one the program runs): its simulated contact is recovered, and after
// setup (and a first tick) it allocates nothing.
TEST_F(FtSensorLoopTest, LoopRecoversTheContactAndAllocatesNothing) {
  constexpr int kTicks = 3000;
  std::vector<double> tick_ns(kTicks);
  (void)RunLoop(loop, 1, false, tick_ns);
  LoopSummary s;
  std::size_t allocations = 0;
  {
    semgraph::testing::CountAllocations counting;
    s = RunLoop(loop, kTicks, false, tick_ns);
    allocations = counting.count();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(s.ticks, kTicks);
  EXPECT_EQ(s.failed_ticks, 0);
  EXPECT_LT(s.worst_error, 1e-9);
  // The last tick's answer against this file's kinematics and the simulated contact.
  const double t = 1e-3 * (kTicks - 1);
  const Frames F = Fk(JointsAt(t));
  const ForceMoment truth_W = ContactInWorldAt(t);
  ExpectNear(s.last.in_base.f, F.base.R.transpose() * truth_W.f, "last force in [base]");
  ExpectNear(s.last.in_base.m, F.base.R.transpose() * truth_W.m, "last moment in [base]");
}

}  // namespace
}  // namespace semgraph::examples::ft_sensor
