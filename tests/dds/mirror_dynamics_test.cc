// Accelerations and wrenches through DDS (docs/distributed.md, docs/dynamics.md): a publisher's
// twist edges with accelerations, a joint's qddot and the stored wrenches reach a mirror over
// the loopback domain; the mirror's GetAcceleration / GetWrench answers equal the publisher's
// and values composed here by hand. A twist without an acceleration clears the mirror's, a
// removed wrench disappears, and hostile messages (NaN, a wrench naming bodies or a frame its
// structure does not declare) are rejected with a log line and change nothing. Stamped
// accelerations and stamped wrenches: timed queries (At) on the mirror equal the publisher's and
// the linear interpolation of two samples computed here; a late mirror gets the samples.
// The mirror's graph is read through queries (sequence locks) while values may stream in,
// never through writer-thread inspectors (joint_acceleration, acceleration_value).
#include <dds/dds.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "dds_isolation.h"
#include "mirror_test_support.h"
#include "scenes.h"
#include "semgraph/core/scene_graph_debug.h"
#include "semgraph/dds/mirror.h"
#include "semgraph/dds/publisher.h"
#include "semgraph_wire.h"

namespace semgraph::dds_test {
namespace {

using namespace std::chrono_literals;
using core::AccelerationInput;
using core::WrenchSpec;

// The answer's six numbers (linear/force first), or empty with *code set to the error's.
std::vector<double> Acc(const core::SceneGraph<>& g, const TwistSpec& spec,
                        base::ErrorCode* code = nullptr) {
  auto A = g.GetAcceleration(spec);
  if (code != nullptr) *code = A ? base::ErrorCode::kOk : A.error().code;
  if (!A) return {};
  return {A->linear.x(),  A->linear.y(),  A->linear.z(),
          A->angular.x(), A->angular.y(), A->angular.z()};
}
std::vector<double> Wrench(const core::SceneGraph<>& g, const WrenchSpec& spec,
                           base::ErrorCode* code = nullptr) {
  auto W = g.GetWrench(spec);
  if (code != nullptr) *code = W ? base::ErrorCode::kOk : W.error().code;
  if (!W) return {};
  return {W->force.x(), W->force.y(), W->force.z(), W->moment.x(), W->moment.y(), W->moment.z()};
}
std::vector<double> Six(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return {a.x(), a.y(), a.z(), b.x(), b.y(), b.z()};
}
void ExpectNear(const std::vector<double>& got, const std::vector<double>& want, double tol,
                const std::string& what) {
  ASSERT_EQ(got.size(), 6u) << what;
  ASSERT_EQ(want.size(), 6u) << what;
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(got[i], want[i], tol) << what << " [" << i << "]";
}

// The publisher's scene: W -> {a}|A -> {b}|B (poses and twist edges, both with accelerations),
// W -> {c}|C a twist without one, the revolute joint j1 w -> l1 (axis z), the wrenches on A by B
// (stored at a) and on B by W (at b).
const Eigen::Quaterniond kQ_wa = Rz(0.3);
const Eigen::Vector3d kP_wa{1, 0, 0};
struct Scene {
  core::SceneGraph<> g;
  core::TwistHandle twist_a, twist_b;
  core::WrenchHandle on_a_by_b;
  core::JointGroup joints;
};
void BuildScene(Scene& s) {
  core::SceneGraph<>& g = s.g;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("a", "A").RelativeTo("w", "W"), kQ_wa, kP_wa));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("b", "B").RelativeTo("a", "A"), Rx(0.2), {0.5, 0, 0}));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c", "C").RelativeTo("w", "W"), Rz(-0.1), {0, 1, 0}));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("a"), {0.5, 0, 0},
                         {0, 0, 0.2}, AccelerationInput{{1, 2, 3}, {0.1, 0.2, 0.3}}));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("b", "B").RelativeTo("A").ExpressedIn("b"), {0, 0.1, 0},
                         {0.3, 0, 0}, AccelerationInput{{-1, 0, 0.5}, {0, 0.4, 0}}));
  ASSERT_TRUE(
      g.AddTwist(TwistSpec::Of("c", "C").RelativeTo("W").ExpressedIn("c"), {0, 0, 1}, {0, 0, 0}));
  core::JointSpec j1;
  j1.name = "j1";
  j1.type = core::JointType::kRevolute;
  j1.parent = "w";
  j1.parent_body = "W";
  j1.child = "l1";
  j1.child_body = "L1";
  j1.p_origin = {0, 0, 1};
  j1.axis = {0, 0, 1};
  j1.lower = -2;
  j1.upper = 2;
  ASSERT_TRUE(g.AddJoint(j1));
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("A").By("B").At("a"), {1, 0, 0}, {0, 0, 2}));
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("B").By("W").At("b"), {0, 0, -9.81}, {0, 0, 0}));
  auto ta = g.FindTwistEdge("a", "W");
  auto tb = g.FindTwistEdge("b", "A");
  auto w = g.FindWrench("A", "B");
  const std::string_view names[] = {"j1"};
  auto group = g.MakeJointGroup(names);
  ASSERT_TRUE(ta && tb && w && group);
  s.twist_a = *ta;
  s.twist_b = *tb;
  s.on_a_by_b = *w;
  s.joints = std::move(*group);
}

const TwistSpec kA_a = TwistSpec::Of("a").RelativeTo("W").ExpressedIn("a");
const TwistSpec kA_w = TwistSpec::Of("a").RelativeTo("W").ExpressedIn("w");
const TwistSpec kB_w = TwistSpec::Of("b").RelativeTo("W").ExpressedIn("w");
const TwistSpec kC_c = TwistSpec::Of("c").RelativeTo("W").ExpressedIn("c");
const TwistSpec kL1 = TwistSpec::Of("l1").RelativeTo("W").ExpressedIn("l1");
const WrenchSpec kAB_a = WrenchSpec::On("A").By("B").At("a");
const WrenchSpec kAB_w = WrenchSpec::On("A").By("B").At("w");
const WrenchSpec kBA_b = WrenchSpec::On("B").By("A").At("b");
const WrenchSpec kBW_w = WrenchSpec::On("B").By("W").At("w");

// The mirror's and the publisher's answers to every dynamics query of the scene are equal.
void ExpectSameDynamics(const dds::Mirror& mirror, const core::SceneGraph<>& g) {
  mirror.WithGraph([&](const core::SceneGraph<>& m) {
    for (const TwistSpec& spec : {kA_a, kA_w, kB_w, kC_c, kL1}) {
      base::ErrorCode cm = base::ErrorCode::kOk, cg = base::ErrorCode::kOk;
      const std::vector<double> am = Acc(m, spec, &cm), ag = Acc(g, spec, &cg);
      EXPECT_EQ(cm, cg) << spec.point;
      if (cm == base::ErrorCode::kOk && cg == base::ErrorCode::kOk)
        ExpectNear(am, ag, 1e-12, std::string("acceleration of ") + std::string(spec.point));
    }
    for (const WrenchSpec& spec : {kAB_a, kAB_w, kBA_b, kBW_w}) {
      base::ErrorCode cm = base::ErrorCode::kOk, cg = base::ErrorCode::kOk;
      const std::vector<double> wm = Wrench(m, spec, &cm), wg = Wrench(g, spec, &cg);
      EXPECT_EQ(cm, cg) << spec.on << " by " << spec.by;
      if (cm == base::ErrorCode::kOk && cg == base::ErrorCode::kOk)
        ExpectNear(wm, wg, 1e-12, std::string("wrench on ") + std::string(spec.on));
    }
  });
}

// Waits until the mirror applied `n` more values than `before`.
bool WaitValues(const dds::Mirror& mirror, std::uint64_t before, std::uint64_t n) {
  return mirror.WaitUntil([&] { return mirror.values_applied() >= before + n; }, 5s);
}

TEST(MirrorDynamicsTest, AccelerationsAndWrenchesReachMirrors) {
  constexpr std::uint32_t kDomain = 31;
  auto mirror = dds::Mirror::Create({"m", kDomain, {}, {}, {}, {}});
  ASSERT_TRUE(mirror) << mirror.error();
  Scene s;
  BuildScene(s);
  if (HasFatalFailure()) return;
  core::SceneGraph<>& g = s.g;
  auto pub = dds::Publisher::Create(g, {"arm", kDomain});
  ASSERT_TRUE(pub) << pub.error();
  ASSERT_TRUE((*pub)->PublishStructure());
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->CaughtUp(); }, 5s));
  // The structure: edges with their accelerations (one without), the wrenches at their frames.
  ExpectSameDynamics(**mirror, g);
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
    EXPECT_EQ(m.num_wrenches(), 2u);
    // By hand: the edge form as given, then rotated into [w] (a's origin: no transport terms).
    ExpectNear(Acc(m, kA_a), {1, 2, 3, 0.1, 0.2, 0.3}, 1e-15, "edge form");
    ExpectNear(Acc(m, kA_w),
               Six(kQ_wa * Eigen::Vector3d(1, 2, 3), kQ_wa * Eigen::Vector3d(0.1, 0.2, 0.3)), 1e-14,
               "in [w]");
    base::ErrorCode code = base::ErrorCode::kOk;
    EXPECT_TRUE(Acc(m, kC_c, &code).empty());
    EXPECT_EQ(code, base::ErrorCode::kNoAcceleration);
    // A joint never given qddot: no acceleration on its edge.
    EXPECT_TRUE(Acc(m, kL1, &code).empty());
    EXPECT_EQ(code, base::ErrorCode::kNoAcceleration);
    // The wrench on A by B moved to w in [w] by hand: f_w = R_wa f, m_w = R_wa m + p_WoAo x f_w.
    const Eigen::Vector3d f_w = kQ_wa * Eigen::Vector3d(1, 0, 0);
    ExpectNear(Wrench(m, kAB_w), Six(f_w, kQ_wa * Eigen::Vector3d(0, 0, 2) + kP_wa.cross(f_w)),
               1e-14, "wrench in [w]");
  });

  // Values: a twist with an acceleration, a joint state with qddot, a wrench.
  std::uint64_t before = (*mirror)->values_applied();
  ASSERT_EQ((*pub)->SetTwist(s.twist_a, {0.1, 0, 0}, {0, 0, 0.5},
                             AccelerationInput{{0, -1, 0}, {0, 0, 2}}),
            base::ErrorCode::kOk);
  const double q[] = {0.4}, qdot[] = {-0.1}, qddot[] = {0.7};
  ASSERT_EQ((*pub)->SetJointState(s.joints, q, qdot, qddot), base::ErrorCode::kOk);
  ASSERT_EQ((*pub)->SetWrench(s.on_a_by_b, {0, 3, 0}, {1, 0, 0}), base::ErrorCode::kOk);
  ASSERT_TRUE(WaitValues(**mirror, before, 3));
  ExpectSameDynamics(**mirror, g);
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
    ExpectNear(Acc(m, kA_a), {0, -1, 0, 0, 0, 2}, 0, "new edge form");
    // j1's edge: revolute about z through the child's origin: (0, u qddot).
    ExpectNear(Acc(m, kL1), {0, 0, 0, 0, 0, 0.7}, 1e-15, "joint qddot");
    ExpectNear(Wrench(m, kAB_a), {0, 3, 0, 1, 0, 0}, 0, "stored wrench");
  });

  // A twist without an acceleration clears it, on the mirror as on the publisher; a position-
  // only joint state keeps qddot (as the graph does).
  before = (*mirror)->values_applied();
  ASSERT_EQ((*pub)->SetTwist(s.twist_a, {0.2, 0, 0}, {0, 0, 0.1}), base::ErrorCode::kOk);
  const double q2[] = {0.5};
  ASSERT_EQ((*pub)->SetJointPositions(s.joints, q2), base::ErrorCode::kOk);
  ASSERT_TRUE(WaitValues(**mirror, before, 2));
  ExpectSameDynamics(**mirror, g);
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
    base::ErrorCode code = base::ErrorCode::kOk;
    EXPECT_TRUE(Acc(m, kA_w, &code).empty());
    EXPECT_EQ(code, base::ErrorCode::kNoAcceleration);
    EXPECT_TRUE(Acc(m, kA_a, &code).empty());
    EXPECT_EQ(code, base::ErrorCode::kNoAcceleration);
    ExpectNear(Acc(m, kL1), {0, 0, 0, 0, 0, 0.7}, 1e-15, "qddot kept");
  });
  // SetAcceleration alone brings it back.
  before = (*mirror)->values_applied();
  ASSERT_EQ((*pub)->SetAcceleration(s.twist_a, {4, 0, 0}, {0, 0, -1}), base::ErrorCode::kOk);
  ASSERT_TRUE(WaitValues(**mirror, before, 1));
  ExpectSameDynamics(**mirror, g);

  // A batch carries them as single values do.
  before = (*mirror)->values_applied();
  (*pub)->BeginBatch();
  ASSERT_EQ((*pub)->SetTwist(s.twist_b, {0, 0.2, 0}, {0.1, 0, 0},
                             AccelerationInput{{0, 0, 1}, {0.5, 0, 0}}),
            base::ErrorCode::kOk);
  ASSERT_EQ((*pub)->SetWrench(s.on_a_by_b, {-2, 0, 0}, {0, 0.5, 0}), base::ErrorCode::kOk);
  ASSERT_EQ((*pub)->SetTwist(s.twist_a, {0.3, 0, 0}, {0, 0, 0}), base::ErrorCode::kOk);
  (*pub)->Flush();
  ASSERT_TRUE(WaitValues(**mirror, before, 3));
  ExpectSameDynamics(**mirror, g);
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
    ExpectNear(Wrench(m, kAB_a), {-2, 0, 0, 0, 0.5, 0}, 0, "batched wrench");
    base::ErrorCode code = base::ErrorCode::kOk;
    EXPECT_TRUE(Acc(m, kA_a, &code).empty());
    EXPECT_EQ(code, base::ErrorCode::kNoAcceleration);
  });

  // A late mirror gets all of it from the structure (accelerations, qddot, wrench values).
  ASSERT_TRUE((*pub)->PublishStructure());
  auto late = dds::Mirror::Create({"late", kDomain, {}, {}, {}, {}});
  ASSERT_TRUE(late) << late.error();
  ASSERT_TRUE((*late)->WaitUntil([&] { return (*late)->CaughtUp(); }, 5s));
  ExpectSameDynamics(**late, g);

  // A wrench removed on the publisher disappears from the mirrors (its reaction query too).
  ASSERT_TRUE(g.RemoveWrench("A", "B"));
  const std::uint64_t generation = (*mirror)->structure_generation();
  ASSERT_TRUE((*pub)->PublishStructure());
  ASSERT_TRUE((*mirror)->WaitUntil(
      [&] { return (*mirror)->structure_generation() > generation && (*mirror)->CaughtUp(); }, 5s));
  ExpectSameDynamics(**mirror, g);
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
    EXPECT_EQ(m.num_wrenches(), 1u);
    base::ErrorCode code = base::ErrorCode::kOk;
    EXPECT_TRUE(Wrench(m, kAB_a, &code).empty());
    EXPECT_EQ(code, base::ErrorCode::kNoWrench);
    EXPECT_TRUE(Wrench(m, kBA_b, &code).empty());
    EXPECT_EQ(code, base::ErrorCode::kNoWrench);
    ExpectNear(Wrench(m, WrenchSpec::On("B").By("W").At("b")), {0, 0, -9.81, 0, 0, 0}, 0,
               "the other wrench stays");
  });
  // Added again (a new slot value on the publisher): it comes back with its value.
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("A").By("B").At("a"), {0, 0, 5}, {0, 0, 0}));
  ASSERT_TRUE((*pub)->PublishStructure());
  ASSERT_TRUE((*mirror)->WaitUntil(
      [&] {
        bool back = false;
        (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { back = m.num_wrenches() == 2; });
        return back && (*mirror)->CaughtUp();
      },
      5s));
  ExpectSameDynamics(**mirror, g);
  EXPECT_EQ((*mirror)->messages_rejected(), 0u);
  EXPECT_EQ((*pub)->write_failures(), 0u);
}

// Hostile values (a NaN acceleration with a twist, a NaN wrench, an acceleration with a pose
// value, a stamped sample for an unstamped twist edge or wrench, a NaN qddot) and hostile
// structures (a wrench naming a body or a storage frame not of its `on` body, a NaN wrench, a NaN
// acceleration on a twist element) are rejected with a log line and change nothing; another owner's
// reaction of a mirrored wrench is refused duplicate_wrench.
TEST(MirrorDynamicsTest, HostileAccelerationsAndWrenchesAreRejected) {
  constexpr std::uint32_t kDomain = 32;
  std::mutex log_mutex;
  std::string logs;
  auto mirror = dds::Mirror::Create(LoggingOptions(kDomain, log_mutex, logs));
  ASSERT_TRUE(mirror) << mirror.error();
  Scene s;
  BuildScene(s);
  if (HasFatalFailure()) return;
  core::SceneGraph<>& g = s.g;
  auto pub = dds::Publisher::Create(g, {"arm", kDomain});
  ASSERT_TRUE(pub && (*pub)->PublishStructure());
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->CaughtUp(); }, 5s));
  const double q[] = {0.4}, qdot[] = {-0.1}, qddot[] = {0.7};
  ASSERT_EQ((*pub)->SetJointState(s.joints, q, qdot, qddot), base::ErrorCode::kOk);
  ASSERT_TRUE(WaitValues(**mirror, 0, 1));
  std::string before;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { before = core::Dump(m); });
  ExpectSameDynamics(**mirror, g);

  RawWriter values(kDomain, &semgraph_wire_Value_desc, "semgraph_values");
  RawWriter samples(kDomain, &semgraph_wire_Value_desc, "semgraph_samples");
  const double nan = std::nan("");
  auto value = [&](std::uint8_t kind, std::uint32_t edge, std::uint64_t seq) {
    semgraph_wire_Value v{};
    v.source = (*pub)->source();
    v.edge = edge;
    v.kind = kind;
    v.seq = seq;
    v.time_ns = 1000;
    return v;
  };
  const std::uint32_t a = g.FindFrame("a").value(), c = g.FindFrame("c").value();
  const std::uint32_t wrench = s.on_a_by_b.slot, j1 = g.FindJoint("j1")->index.value();
  // A new twist whose acceleration is NaN: neither is set.
  semgraph_wire_Value v1 = value(semgraph_wire_VALUE_TWIST, a, 100);
  v1.numbers[0] = 9;
  v1.has_acceleration = true;
  v1.acceleration[4] = nan;
  semgraph_wire_Value v2 = value(semgraph_wire_VALUE_WRENCH, wrench, 100);  // NaN force
  v2.numbers[0] = 1;
  v2.numbers[2] = nan;
  semgraph_wire_Value v3 = value(semgraph_wire_VALUE_POSE, c, 100);  // a pose with one
  v3.numbers[0] = 1;
  v3.has_acceleration = true;
  semgraph_wire_Value v4 = value(semgraph_wire_VALUE_JOINT, j1, 100);  // NaN qddot
  v4.numbers[0] = 0.1;
  v4.has_acceleration = true;
  v4.acceleration[0] = nan;
  semgraph_wire_Value s1 = value(semgraph_wire_VALUE_TWIST, c, 101);  // stamped, with one
  s1.has_acceleration = true;
  semgraph_wire_Value s2 = value(semgraph_wire_VALUE_WRENCH, wrench, 101);  // stamped wrench
  for (const semgraph_wire_Value* v : {&v1, &v2, &v3, &v4})
    ASSERT_EQ(dds_write(values.writer, v), DDS_RETCODE_OK);
  for (const semgraph_wire_Value* v : {&s1, &s2})
    ASSERT_EQ(dds_write(samples.writer, v), DDS_RETCODE_OK);

  // Hostile structures of owner "evil".
  RawWriter structures(kDomain, &semgraph_wire_Structure_desc, "semgraph_structure");
  char owner[] = "evil", X[] = "X", Y[] = "Y", Z[] = "Z", x[] = "x", w[] = "w", W[] = "W",
       empty[] = "";
  auto element = [&](std::uint8_t kind, char* head, char* head_body, char* tail, char* tail_body,
                     std::uint32_t id) {
    semgraph_wire_Element e{};
    e.kind = kind;
    e.edge = id;
    e.head = head;
    e.head_body = head_body;
    e.tail = tail;
    e.tail_body = tail_body;
    return e;
  };
  std::uint64_t revision = 0;
  auto structure = [&](std::vector<semgraph_wire_Element> elements) {
    semgraph_wire_Structure st{};
    st.owner = owner;
    st.source = 79;
    st.revision = ++revision;
    st.elements._length = st.elements._maximum = static_cast<std::uint32_t>(elements.size());
    st.elements._buffer = elements.data();
    ASSERT_EQ(dds_write(structures.writer, &st), DDS_RETCODE_OK);
    std::this_thread::sleep_for(20ms);  // keep-last 1: let each one arrive
  };
  const semgraph_wire_Element body_x =
      element(semgraph_wire_ELEMENT_BODY, X, empty, empty, empty, 0);
  const semgraph_wire_Element body_y =
      element(semgraph_wire_ELEMENT_BODY, Y, empty, empty, empty, 0);
  const semgraph_wire_Element frame_x = element(semgraph_wire_ELEMENT_FRAME, x, X, empty, empty, 0);
  // On X by Z: Z is not declared.
  structure({body_x, frame_x, element(semgraph_wire_ELEMENT_WRENCH, x, X, empty, Z, 1)});
  // On Y by X at x: x is a frame of X.
  structure({body_x, body_y, frame_x, element(semgraph_wire_ELEMENT_WRENCH, x, Y, empty, X, 1)});
  semgraph_wire_Element nan_wrench = element(semgraph_wire_ELEMENT_WRENCH, x, X, empty, Y, 1);
  nan_wrench.numbers[3] = nan;
  structure({body_x, body_y, frame_x, nan_wrench});
  semgraph_wire_Element twist = element(semgraph_wire_ELEMENT_TWIST, x, X, W, empty, 2);
  twist.has_acceleration = true;
  twist.acceleration[0] = nan;
  structure({body_x, frame_x, twist});
  (void)w;

  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->messages_rejected() >= 10; }, 5s))
      << (*mirror)->messages_rejected();
  std::string after;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { after = core::Dump(m); });
  EXPECT_EQ(before, after);
  EXPECT_EQ((*mirror)->Owners().size(), 1u);
  ExpectSameDynamics(**mirror, g);
  {
    std::lock_guard<std::mutex> lock(log_mutex);
    for (const char* line :
         {"value into 'a': invalid_number", "value into 'A': invalid_number",
          "value into 'c': an acceleration with a value that is neither a twist nor a joint state",
          "value into 'j1': invalid_number",
          "sample: a stamped sample for the unstamped edge into 'c' (stamp_mismatch)",
          "sample: a stamped sample for the unstamped wrench on 'A' (stamp_mismatch)",
          "wrench on 'X' by 'Z': a body the structure does not declare (unknown_body)",
          "wrench on 'Y' by 'X': storage frame 'x' is a frame of 'X', not of 'Y'",
          "element 3 (wrench 'x'): a number is not finite (invalid_number)",
          "element 2 (twist 'x'): an acceleration number is not finite (invalid_number)"}) {
      EXPECT_NE(logs.find(line), std::string::npos) << line << "\n" << logs;
    }
  }

  // Another owner's wrench on B by A (the reaction of arm's): refused, nothing changes.
  core::SceneGraph<> g2;
  ASSERT_TRUE(g2.AddBody("A"));
  ASSERT_TRUE(g2.AddBody("B"));
  ASSERT_TRUE(g2.AddFrame("a", "A"));
  ASSERT_TRUE(g2.AddFrame("b", "B"));
  ASSERT_TRUE(g2.AddWrench(WrenchSpec::On("B").By("A").At("b"), {7, 7, 7}, {0, 0, 0}));
  auto other = dds::Publisher::Create(g2, {"other", kDomain});
  ASSERT_TRUE(other && (*other)->PublishStructure());
  ASSERT_TRUE((*mirror)->WaitUntil(
      [&] {
        for (const dds::Report& r : (*mirror)->Refusals())
          if (r.owner == "other" && r.code == "duplicate_wrench") return true;
        return false;
      },
      5s));
  ExpectSameDynamics(**mirror, g);
}

// The stamped scene: W -> {a}|A (timeless pose) with a stamped twist edge whose samples carry
// accelerations (t0, t1; t2 given by a stamped SetAcceleration after its twist; t3 without one),
// {b}|B on A (timeless pose), the stamped wrench on A by B stored at a (samples t0, t1, t2) and
// the timeless wrench on B by W at b; the revolute joint j1 w -> l1 (axis z), stamped with qddot
// by the publisher (kQddot at t0, t1, t2).
constexpr std::int64_t kT0 = 1'000'000'000, kDt = 100'000'000;  // 1 s, 100 ms
core::Stamp T(std::int64_t k) { return core::Stamp::Nanoseconds(kT0 + k * kDt); }
const Eigen::Vector3d kV[4] = {{0.5, 0, 0}, {0.6, 0.1, 0}, {0.7, 0, 0.2}, {0.8, 0, 0}};
const Eigen::Vector3d kW{0, 0, 0.2};
const Eigen::Vector3d kAcc[3] = {{1, 2, 3}, {3, -2, 1}, {0, 4, -1}};
const Eigen::Vector3d kAlpha[3] = {{0.1, 0.2, 0.3}, {0.5, 0, -0.3}, {0, 0, 1}};
const Eigen::Vector3d kF[3] = {{1, 0, 0}, {3, -4, 2}, {0, 0, 6}};
const Eigen::Vector3d kM[3] = {{0, 0, 2}, {1, 1, 0}, {0, -2, 0}};
const double kQddot[3] = {0.7, -0.3, 1.1};

struct StampedScene {
  core::SceneGraph<> g;
  core::TwistHandle twist;
  core::WrenchHandle wrench;
  explicit StampedScene(core::SceneGraph<>&& made) : g(std::move(made)) {}
};
std::unique_ptr<StampedScene> BuildStampedScene() {
  core::TimeOptions time;
  time.window = core::Duration::Seconds(10);
  time.sample_capacity = 64;
  auto made = core::SceneGraph<>::Create(time);
  if (!made) return nullptr;
  auto s = std::make_unique<StampedScene>(std::move(*made));
  core::SceneGraph<>& g = s->g;
  if (!g.AddPose(PoseSpec::Of("a", "A").RelativeTo("w", "W"), kQ_wa, kP_wa) ||
      !g.AddPose(PoseSpec::Of("b", "B").RelativeTo("a", "A"), Rx(0.2), {0.5, 0, 0}) ||
      !g.AddTwist(kA_a, kV[0], kW, T(0), AccelerationInput{kAcc[0], kAlpha[0]}) ||
      !g.AddWrench(kAB_a, kF[0], kM[0], T(0)) ||
      !g.AddWrench(WrenchSpec::On("B").By("W").At("b"), {0, 0, -9.81}, {0, 0, 0})) {
    return nullptr;
  }
  core::JointSpec j1;
  j1.name = "j1";
  j1.type = core::JointType::kRevolute;
  j1.parent = "w";
  j1.parent_body = "W";
  j1.child = "l1";
  j1.child_body = "L1";
  j1.axis = {0, 0, 1};
  j1.lower = -2;
  j1.upper = 2;
  if (!g.AddJoint(j1)) return nullptr;
  auto t = g.FindTwistEdge("a", "W");
  auto w = g.FindWrench("A", "B");
  if (!t || !w) return nullptr;
  s->twist = *t;
  s->wrench = *w;
  return s;
}

// The timed answer's six numbers, or empty with *code set to the error's.
std::vector<double> AccAt(const core::SceneGraph<>& g, const TwistSpec& spec, core::Stamp t,
                          base::ErrorCode* code) {
  auto A = g.GetAcceleration(spec, core::At(t));
  *code = A ? base::ErrorCode::kOk : A.error().code;
  if (!A) return {};
  return Six(A->value.linear, A->value.angular);
}
std::vector<double> WrenchAt(const core::SceneGraph<>& g, const WrenchSpec& spec, core::Stamp t,
                             base::ErrorCode* code) {
  auto W = g.GetWrench(spec, core::At(t));
  *code = W ? base::ErrorCode::kOk : W.error().code;
  if (!W) return {};
  return Six(W->value.force, W->value.moment);
}

// The stamps the timed queries are asked at: on the samples from t_first, between them.
std::vector<core::Stamp> QueryStamps(std::int64_t first) {
  std::vector<core::Stamp> out;
  for (std::int64_t k = first; k <= 3; ++k) {
    out.push_back(T(k));
    if (k < 3) out.push_back(core::Stamp::Nanoseconds(kT0 + k * kDt + kDt / 3));
  }
  return out;
}

// Whether every timed acceleration and wrench answer of the mirror equals the publisher's
// (same code; same numbers to 1e-12) at the samples from t_first on and between them; `expect`:
// report each difference as a test failure.
bool SameTimedDynamics(const dds::Mirror& mirror, const core::SceneGraph<>& g, bool expect,
                       std::int64_t first) {
  bool same = true;
  mirror.WithGraph([&](const core::SceneGraph<>& m) {
    auto compare = [&](const std::vector<double>& x, base::ErrorCode cx,
                       const std::vector<double>& y, base::ErrorCode cy, const std::string& what) {
      bool ok = cx == cy;
      for (std::size_t i = 0; ok && i < x.size(); ++i) ok = std::abs(x[i] - y[i]) <= 1e-12;
      if (!ok && expect)
        ADD_FAILURE() << what << ": " << base::ToString(cx) << " vs " << base::ToString(cy);
      same = same && ok;
    };
    for (const core::Stamp t : QueryStamps(first)) {
      const std::string at = " at " + std::to_string(t.nanoseconds());
      for (const TwistSpec& spec : {kA_a, kA_w, kL1}) {
        base::ErrorCode cm, cg;
        const auto am = AccAt(m, spec, t, &cm), ag = AccAt(g, spec, t, &cg);
        compare(am, cm, ag, cg, "acceleration of " + std::string(spec.coordinate_frame) + at);
      }
      for (const WrenchSpec& spec : {kAB_a, kAB_w, kBA_b, kBW_w}) {
        base::ErrorCode cm, cg;
        const auto wm = WrenchAt(m, spec, t, &cm), wg = WrenchAt(g, spec, t, &cg);
        compare(wm, cm, wg, cg, "wrench on " + std::string(spec.on) + at);
      }
    }
  });
  return same;
}

// The publisher's stamped values after the structure: the twist sample t1 with its
// acceleration, t2 set then given its acceleration (SetAcceleration at t2, in a batch with the
// wrench sample t2: the sample goes out again with it), t3 without one; wrench samples t1, t2;
// joint states with qddot at t0 (its first stamped state, by name: a structure change), t1
// (the real-time stamped SetJointState with qddot) and t2 (the real-time stamped SetJointState
// without qddot, then SetJointAccelerations at the same stamp: the sample replaced).
void SendStampedValues(dds::Publisher& pub, const StampedScene& s) {
  const core::JointValue q0[] = {{"j1", 0.0}}, qdot0[] = {{"j1", 0.5}},
                         qddot0[] = {{"j1", kQddot[0]}};
  ASSERT_TRUE(pub.SetJoints(q0, qdot0, qddot0, T(0)));
  const std::string_view names[] = {"j1"};
  const auto group = s.g.MakeJointGroup(names);
  ASSERT_TRUE(group);
  const double q1[] = {0.1}, q2[] = {0.2}, qdot[] = {0.5}, qddot1[] = {kQddot[1]},
               qddot2[] = {kQddot[2]};
  ASSERT_EQ(pub.SetJointState(*group, q1, qdot, qddot1, T(1)), base::ErrorCode::kOk);
  ASSERT_EQ(pub.SetJointState(*group, q2, qdot, T(2)), base::ErrorCode::kOk);
  ASSERT_EQ(pub.SetJointAccelerations(*group, qddot2, T(2)), base::ErrorCode::kOk);
  ASSERT_EQ(pub.SetTwist(s.twist, kV[1], kW, T(1), AccelerationInput{kAcc[1], kAlpha[1]}),
            base::ErrorCode::kOk);
  ASSERT_EQ(pub.SetTwist(s.twist, kV[2], kW, T(2)), base::ErrorCode::kOk);
  ASSERT_EQ(pub.SetWrench(s.wrench, kF[1], kM[1], T(1)), base::ErrorCode::kOk);
  // One control cycle as a batch: the acceleration of the t2 sample and the wrench sample t2.
  pub.BeginBatch();
  ASSERT_EQ(pub.SetAcceleration(s.twist, kAcc[2], kAlpha[2], T(2)), base::ErrorCode::kOk);
  ASSERT_EQ(pub.SetWrench(s.wrench, kF[2], kM[2], T(2)), base::ErrorCode::kOk);
  pub.Flush();
  ASSERT_EQ(pub.SetTwist(s.twist, kV[3], kW, T(3)), base::ErrorCode::kOk);
  // A stamped value for the timeless pair, and the reverse: refused by the publisher's graph.
  auto timeless = s.g.FindWrench("B", "W");
  ASSERT_TRUE(timeless);
  EXPECT_EQ(pub.SetWrench(*timeless, kF[1], kM[1], T(1)), base::ErrorCode::kStampMismatch);
  EXPECT_EQ(pub.SetWrench(s.wrench, kF[1], kM[1]), base::ErrorCode::kStampMismatch);
}

// Stamped accelerations and stamped wrenches reach a mirror (docs/distributed.md): the twist
// samples carry their accelerations, the wrench samples travel on the sample topic, and the
// structure announces the stamped pair with its newest sample. The mirror's timed answers equal
// the publisher's at and between the samples, and the linear interpolation computed here by
// hand; between t2 and t3 (t3 carries none) both answer no_acceleration. A mirror started after
// all of it gets the samples from the publisher's writers (transient-local).
TEST(MirrorDynamicsTest, StampedAccelerationsAndWrenchesReachMirrors) {
  constexpr std::uint32_t kDomain = 33;
  auto mirror = dds::Mirror::Create({"m", kDomain, {}, {}, {}, {}});
  ASSERT_TRUE(mirror) << mirror.error();
  auto s = BuildStampedScene();
  ASSERT_TRUE(s);
  auto pub = dds::Publisher::Create(s->g, {"arm", kDomain});
  ASSERT_TRUE(pub && (*pub)->PublishStructure());
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->CaughtUp(); }, 5s));
  // The structure alone: the newest samples (t0) with the twist's acceleration.
  EXPECT_TRUE(SameTimedDynamics(**mirror, s->g, true, 0));
  const std::uint64_t before = (*mirror)->values_applied();
  SendStampedValues(**pub, *s);
  if (HasFatalFailure()) return;
  // (The joint's samples wait on the mirror for the structure that makes it stamped: they are
  // applied with it, not counted as values; wait for the answers instead.) From t1 on: the
  // joint's first stamped state (t0) travels in a structure only, which the batch's republish
  // may supersede before this mirror took it (docs/distributed.md, "Time").
  ASSERT_TRUE(
      (*mirror)->WaitUntil([&] { return SameTimedDynamics(**mirror, s->g, false, 1); }, 5s));
  EXPECT_GE((*mirror)->values_applied(), before + 6);
  EXPECT_EQ((*mirror)->messages_rejected(), 0u);
  EXPECT_EQ((*pub)->write_failures(), 0u);
  EXPECT_TRUE(SameTimedDynamics(**mirror, s->g, true, 1));

  // By hand: halfway between t1 and t2 the edge-form acceleration (kA_a is the edge form) and
  // the stored wrench (at its storage frame a) are the means of the two samples; halfway between
  // t0 and t1 likewise.
  const core::Stamp mid12 = core::Stamp::Nanoseconds(kT0 + kDt + kDt / 2);
  const core::Stamp mid01 = core::Stamp::Nanoseconds(kT0 + kDt / 2);
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) {
    base::ErrorCode code;
    ExpectNear(AccAt(m, kA_a, mid12, &code),
               Six(0.5 * (kAcc[1] + kAcc[2]), 0.5 * (kAlpha[1] + kAlpha[2])), 1e-12,
               "acceleration halfway t1-t2");
    EXPECT_EQ(code, base::ErrorCode::kOk);
    ExpectNear(AccAt(m, kA_a, T(2), &code), Six(kAcc[2], kAlpha[2]), 1e-12, "acceleration at t2");
    ExpectNear(WrenchAt(m, kAB_a, mid01, &code), Six(0.5 * (kF[0] + kF[1]), 0.5 * (kM[0] + kM[1])),
               1e-12, "wrench halfway t0-t1");
    ExpectNear(WrenchAt(m, kAB_a, T(2), &code), Six(kF[2], kM[2]), 1e-12, "wrench at t2");
    // The joint's edge: (0, u qddot) at l1 in [l1] (a revolute joint), interpolated.
    ExpectNear(AccAt(m, kL1, mid12, &code), {0, 0, 0, 0, 0, 0.5 * (kQddot[1] + kQddot[2])}, 1e-12,
               "joint acceleration halfway t1-t2");
    EXPECT_EQ(code, base::ErrorCode::kOk);
    // t3 carries no acceleration: none between t2 and t3, nor at t3.
    for (const core::Stamp t : {core::Stamp::Nanoseconds(kT0 + 2 * kDt + kDt / 2), T(3)}) {
      AccAt(m, kA_a, t, &code);
      EXPECT_EQ(code, base::ErrorCode::kNoAcceleration) << t.nanoseconds();
    }
  });

  // A late mirror: the structure (newest samples) and the samples from the writers' histories,
  // so every sample but the adds' (t0: those travel in the first structure only).
  auto late = dds::Mirror::Create({"late", kDomain, {}, {}, {}, {}});
  ASSERT_TRUE(late) << late.error();
  ASSERT_TRUE((*late)->WaitUntil(
      [&] { return (*late)->CaughtUp() && SameTimedDynamics(**late, s->g, false, 1); }, 5s));
  EXPECT_TRUE(SameTimedDynamics(**late, s->g, true, 1));
  EXPECT_EQ((*late)->messages_rejected(), 0u);
}

// Hostile stamped dynamics, each rejected with a log line, the mirror's dump unchanged: a
// stamped twist sample with a NaN acceleration, a stamped wrench sample with a NaN moment, a
// stamped wrench sample for the timeless pair and an unstamped value for the stamped one
// (stamp_mismatch), a wrench sample with an acceleration, a stamped joint state with a NaN qddot;
// structures with a stamped wrench whose
// stamp is out of range or whose `by` body is not declared.
TEST(MirrorDynamicsTest, HostileStampedDynamicsAreRejected) {
  constexpr std::uint32_t kDomain = 34;
  std::mutex log_mutex;
  std::string logs;
  dds::MirrorOptions options;
  options.name = "m";
  options.domain = kDomain;
  options.log = [&](const std::string& line) {
    std::lock_guard<std::mutex> lock(log_mutex);
    logs += line + "\n";
  };
  auto mirror = dds::Mirror::Create(options);
  ASSERT_TRUE(mirror) << mirror.error();
  auto s = BuildStampedScene();
  ASSERT_TRUE(s);
  auto pub = dds::Publisher::Create(s->g, {"arm", kDomain});
  ASSERT_TRUE(pub && (*pub)->PublishStructure());
  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->CaughtUp(); }, 5s));
  const std::uint64_t applied = (*mirror)->values_applied();
  SendStampedValues(**pub, *s);
  if (HasFatalFailure()) return;
  ASSERT_TRUE(
      (*mirror)->WaitUntil([&] { return SameTimedDynamics(**mirror, s->g, false, 1); }, 5s));
  EXPECT_GE((*mirror)->values_applied(), applied + 6);
  std::string before;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { before = core::Dump(m); });

  RawWriter values(kDomain, &semgraph_wire_Value_desc, "semgraph_values");
  RawWriter samples(kDomain, &semgraph_wire_Value_desc, "semgraph_samples");
  const double nan = std::nan("");
  auto value = [&](std::uint8_t kind, std::uint32_t edge, std::int64_t time_ns) {
    semgraph_wire_Value v{};
    v.source = (*pub)->source();
    v.edge = edge;
    v.kind = kind;
    v.seq = 100;
    v.time_ns = time_ns;
    return v;
  };
  const std::uint32_t a = s->g.FindFrame("a").value(), stamped = s->wrench.slot;
  const std::uint32_t timeless = s->g.FindWrench("B", "W")->slot;
  semgraph_wire_Value s1 = value(semgraph_wire_VALUE_TWIST, a, kT0 + 4 * kDt);  // NaN alpha
  s1.numbers[0] = 9;
  s1.has_acceleration = true;
  s1.acceleration[5] = nan;
  semgraph_wire_Value s2 = value(semgraph_wire_VALUE_WRENCH, stamped, kT0 + 4 * kDt);  // NaN m
  s2.numbers[4] = nan;
  semgraph_wire_Value s3 = value(semgraph_wire_VALUE_WRENCH, timeless, kT0 + 4 * kDt);
  semgraph_wire_Value s4 = value(semgraph_wire_VALUE_WRENCH, stamped, kT0 + 5 * kDt);
  s4.has_acceleration = true;  // a wrench with an acceleration
  semgraph_wire_Value v1 = value(semgraph_wire_VALUE_WRENCH, stamped, 0);  // unstamped
  v1.numbers[0] = 5;
  semgraph_wire_Value s5 =
      value(semgraph_wire_VALUE_JOINT, s->g.FindJoint("j1")->index.value(), kT0 + 4 * kDt);
  s5.numbers[0] = 0.1;
  s5.has_acceleration = true;
  s5.acceleration[0] = nan;  // a NaN qddot with a stamped joint state
  for (const semgraph_wire_Value* v : {&s1, &s2, &s3, &s4, &s5})
    ASSERT_EQ(dds_write(samples.writer, v), DDS_RETCODE_OK);
  ASSERT_EQ(dds_write(values.writer, &v1), DDS_RETCODE_OK);

  // Hostile structures of owner "evil": stamped wrenches with a stamp out of range, and naming
  // a body the structure does not declare.
  RawWriter structures(kDomain, &semgraph_wire_Structure_desc, "semgraph_structure");
  char owner[] = "evil", X[] = "X", Y[] = "Y", Z[] = "Z", x[] = "x", empty[] = "";
  std::uint64_t revision = 0;
  auto structure = [&](std::vector<semgraph_wire_Element> elements) {
    semgraph_wire_Structure st{};
    st.owner = owner;
    st.source = 80;
    st.revision = ++revision;
    st.elements._length = st.elements._maximum = static_cast<std::uint32_t>(elements.size());
    st.elements._buffer = elements.data();
    ASSERT_EQ(dds_write(structures.writer, &st), DDS_RETCODE_OK);
    std::this_thread::sleep_for(20ms);  // keep-last 1: let each one arrive
  };
  auto element = [&](std::uint8_t kind, char* head, char* head_body, char* tail_body) {
    semgraph_wire_Element e{};
    e.kind = kind;
    e.head = head;
    e.head_body = head_body;
    e.tail = empty;
    e.tail_body = tail_body;
    return e;
  };
  const semgraph_wire_Element body_x = element(semgraph_wire_ELEMENT_BODY, X, empty, empty);
  const semgraph_wire_Element body_y = element(semgraph_wire_ELEMENT_BODY, Y, empty, empty);
  const semgraph_wire_Element frame_x = element(semgraph_wire_ELEMENT_FRAME, x, X, empty);
  semgraph_wire_Element far = element(semgraph_wire_ELEMENT_WRENCH, x, X, Y);
  far.stamped = true;
  far.time_ns = std::numeric_limits<std::int64_t>::max();
  structure({body_x, body_y, frame_x, far});
  semgraph_wire_Element unknown = element(semgraph_wire_ELEMENT_WRENCH, x, X, Z);
  unknown.stamped = true;
  unknown.time_ns = kT0;
  structure({body_x, frame_x, unknown});

  ASSERT_TRUE((*mirror)->WaitUntil([&] { return (*mirror)->messages_rejected() >= 8; }, 5s))
      << (*mirror)->messages_rejected();
  std::string after;
  (*mirror)->WithGraph([&](const core::SceneGraph<>& m) { after = core::Dump(m); });
  EXPECT_EQ(before, after);
  EXPECT_EQ((*mirror)->Owners().size(), 1u);
  EXPECT_TRUE(SameTimedDynamics(**mirror, s->g, true, 1));
  std::lock_guard<std::mutex> lock(log_mutex);
  for (const char* line :
       {"sample into 'a': invalid_number", "sample into 'A': invalid_number",
        "sample: a stamped sample for the unstamped wrench on 'B' (stamp_mismatch)",
        "value: an unstamped value for the stamped wrench on 'A' (stamp_mismatch)",
        "sample into 'A': an acceleration with a value that is neither a twist nor a joint state",
        "sample into 'j1': invalid_number: acceleration of joint 0 of the group",
        "element 3 (wrench 'x'): the stamp is out of range (invalid_number)",
        "wrench on 'X' by 'Z': a body the structure does not declare (unknown_body)"}) {
    EXPECT_NE(logs.find(line), std::string::npos) << line << "\n" << logs;
  }
}

}  // namespace
}  // namespace semgraph::dds_test
