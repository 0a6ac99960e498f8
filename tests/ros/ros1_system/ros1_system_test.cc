// A real ROS 1 system's bag (record_ros1_system.sh: roscore, Debian's robot_state_publisher
// with models/urdf/arm6.urdf, a rospy publisher of sinusoidal joint states, rosbag record):
//  - semgraph, loading it with the same URDF, finds every recorded /tf sample equal to its own
//    forward kinematics at the sample's stamp (no model_mismatch; all transforms covered);
//  - tf2's BufferCore fed the bag's transforms answers lookupTransform like semgraph's
//    linear-interpolation queries on a graph holding only the bag's tf, within 1e-9, at 1,000
//    random times and frame pairs.
// Skips when the recording step was skipped (ROS 1 tools absent) or tf2 is not installed.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "semgraph/models/urdf.h"
#include "semgraph/ros/bag_loader.h"
#include "semgraph/ros/bag_reader.h"
#include "semgraph/ros/messages.h"
#if SEMGRAPH_HAVE_TF2
#include "core/tf2_time_peer.h"
#endif

namespace semgraph::ros {
namespace {

using core::PoseSpec;
using Graph = core::SceneGraph<>;

const std::string kBag = SEMGRAPH_ROS1_SYSTEM_BAG;
const std::string kUrdf = SEMGRAPH_ROS1_SYSTEM_URDF;

/// One transform as recorded (frame names as on the wire).
struct Recorded {
  std::string parent, child;
  std::int64_t stamp_ns = 0;
  bool is_static = false;
  Eigen::Isometry3d X_PC = Eigen::Isometry3d::Identity();
};

/// Every /tf and /tf_static transform of the bag, read with semgraph's ROS 1 reader.
std::vector<Recorded> ReadTransforms(const std::string& path) {
  std::vector<Recorded> out;
  auto reader = OpenBag(path);
  EXPECT_TRUE(reader) << Describe(reader.error());
  if (!reader) return out;
  BagRecord r;
  for (;;) {
    auto more = (*reader)->Next(r);
    EXPECT_TRUE(more) << Describe(more.error());
    if (!more || !*more) break;
    if (r.kind != MessageKind::kTfMessage) continue;
    TFMessage tf;
    auto ok = DecodeRos1(r.data, tf);
    EXPECT_TRUE(ok) << Describe(ok.error());
    for (const TransformStamped& t : tf.transforms) {
      const auto& v = t.transform.translation;
      const auto& q = t.transform.rotation;
      Recorded rec{t.header.frame_id, t.child_frame_id, ToNanoseconds(t.header.stamp),
                   r.topic == "/tf_static"};
      rec.X_PC.linear() = Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized().toRotationMatrix();
      rec.X_PC.translation() = Eigen::Vector3d(v.x, v.y, v.z);
      out.push_back(rec);
    }
  }
  return out;
}

Graph LinearGraph() {
  core::TimeOptions time;
  time.window = core::Duration::Seconds(1'000'000);
  time.interpolation = core::Interpolation::kLinear;
  time.sample_capacity = 4096;  // a few seconds at 50 Hz
  return std::move(*Graph::Create(time));
}

double Distance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff();
}

void SkipWithoutBag() {
  if (!std::filesystem::exists(kBag)) {
    GTEST_SKIP() << kBag << " not recorded (ROS 1 tools absent: scripts/setup.sh --ros)";
  }
}

TEST(Ros1System, EveryRecordedTfSampleEqualsSemgraphsForwardKinematics) {
  SkipWithoutBag();
  if (::testing::Test::IsSkipped()) return;
  Graph graph = LinearGraph();
  auto robot = models::LoadUrdfFile(graph, kUrdf);
  ASSERT_TRUE(robot) << robot.error().message;
  auto report = LoadBag(graph, kBag, {}, &*robot);
  ASSERT_TRUE(report) << Describe(report.error());
  for (const FindingGroup& g : report->findings.groups()) {
    ADD_FAILURE() << g.code.name() << " " << g.parent << " -> " << g.child << " x" << g.count
                  << ": " << g.message;
  }
  const std::vector<Recorded> recorded = ReadTransforms(kBag);
  std::size_t dynamic = 0;
  for (const Recorded& t : recorded) dynamic += t.is_static ? 0 : 1;
  ASSERT_GE(dynamic, 6u * 20) << "robot_state_publisher published too little";
  EXPECT_GT(report->counts.joint_states, 0u);
  EXPECT_EQ(report->counts.transforms, recorded.size());
  EXPECT_EQ(report->counts.covered, recorded.size());  // every joint of arm6 is in the URDF
  EXPECT_EQ(report->counts.mismatched, 0u);
  EXPECT_EQ(report->counts.applied, 0u);
  // The same, sample by sample, tighter than the lift's 1e-6: semgraph's pose of each child
  // link wrt its parent at the sample's stamp (the joint state of that stamp, from the bag) is
  // robot_state_publisher's (KDL's) to rounding.
  for (const Recorded& t : recorded) {
    const PoseSpec spec = PoseSpec::Of(t.child).RelativeTo(t.parent);
    const auto X = t.is_static
                       ? graph.GetPose(spec, core::Latest())
                       : graph.GetPose(spec, core::At(core::Stamp::Nanoseconds(t.stamp_ns)));
    ASSERT_TRUE(X) << graph.Describe(X.error(), spec);
    EXPECT_LT(Distance(X->value.ToIsometry(), t.X_PC), 1e-9)
        << t.parent << " -> " << t.child << " at " << t.stamp_ns;
  }
}

#if SEMGRAPH_HAVE_TF2
semgraph_test::tf2time::Pose7 ToPose7(const Eigen::Isometry3d& X) {
  const Eigen::Quaterniond q(X.linear());
  const Eigen::Vector3d& p = X.translation();
  return {q.w(), q.x(), q.y(), q.z(), p.x(), p.y(), p.z()};
}

Eigen::Isometry3d FromPose7(const semgraph_test::tf2time::Pose7& x) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::Quaterniond(x.qw, x.qx, x.qy, x.qz).normalized().toRotationMatrix();
  X.translation() = Eigen::Vector3d(x.x, x.y, x.z);
  return X;
}
#endif

TEST(Ros1System, Tf2AnswersLikeSemgraphsLinearInterpolationOnTheBagsTf) {
  SkipWithoutBag();
  if (::testing::Test::IsSkipped()) return;
#if !SEMGRAPH_HAVE_TF2
  GTEST_SKIP() << "tf2 (libtf2-dev) not installed: scripts/setup.sh --bench";
#else
  // semgraph: only the bag's tf (no URDF), linear interpolation.
  Graph graph = LinearGraph();
  BagLoadOptions options;
  options.topics = {"/tf", "/tf_static"};
  auto report = LoadBag(graph, kBag, options);
  ASSERT_TRUE(report) << Describe(report.error());
  ASSERT_TRUE(report->findings.empty()) << report->findings.groups()[0].message;
  // tf2: the same transforms, in the bag's order.
  semgraph_test::tf2time::Buffer tf2;
  std::set<std::string> frame_set;
  std::int64_t first = INT64_MAX, last = INT64_MIN;
  for (const Recorded& t : ReadTransforms(kBag)) {
    ASSERT_TRUE(tf2.Set(t.parent, t.child, ToPose7(t.X_PC), t.stamp_ns, t.is_static));
    frame_set.insert(t.parent);
    frame_set.insert(t.child);
    if (t.is_static) continue;
    first = std::min(first, t.stamp_ns);
    last = std::max(last, t.stamp_ns);
  }
  const std::vector<std::string> frames(frame_set.begin(), frame_set.end());
  ASSERT_EQ(frames.size(), 8u);  // arm6: base_link .. wrist_3_link, tool0
  ASSERT_LT(first, last);
  std::mt19937_64 rng(20);
  std::uniform_int_distribution<std::int64_t> time(first, last);
  std::uniform_int_distribution<std::size_t> frame(0, frames.size() - 1);
  double worst = 0;
  for (int i = 0; i < 1000; ++i) {
    const std::int64_t t = time(rng);
    const std::string& of = frames[frame(rng)];
    const std::string& relative_to = frames[frame(rng)];
    semgraph_test::tf2time::Pose7 x;
    ASSERT_TRUE(tf2.Lookup(relative_to, of, t, x)) << of << " in " << relative_to << " at " << t;
    const PoseSpec spec = PoseSpec::Of(of).RelativeTo(relative_to);
    const auto X = graph.GetPose(spec, core::At(core::Stamp::Nanoseconds(t)));
    ASSERT_TRUE(X) << graph.Describe(X.error(), spec);
    const double d = Distance(X->value.ToIsometry(), FromPose7(x));
    worst = std::max(worst, d);
    EXPECT_LT(d, 1e-9) << of << " wrt " << relative_to << " at " << t;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.3e", worst);
  RecordProperty("worst_difference", text);
#endif
}

}  // namespace
}  // namespace semgraph::ros
