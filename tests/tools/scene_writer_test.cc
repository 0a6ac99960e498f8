// Tests of WriteScene (tools/semgraph/scene_writer.cc, declared in semgraph/script/scene_script.h):
// a graph written as a scene script and run again gives the same graph - Dump() identical, so
// the same names, bodies and frames under the same ids, edges and values bit for bit - on
// every scene script of the repository (examples/ and the tool's test scripts) and on random
// scenes built through the C++ calls (both backends, names that need quoting, nodes created by
// poses, twists and joints, values converted from other forms, joint states, updates and
// removals). The text of a
// small scene is checked line by line, written by hand from docs/scene-script.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "semgraph/core/scene_graph_debug.h"
#include "semgraph/script/scene_script.h"

namespace semgraph::script {
namespace {

using core::PoseSpec;
using core::TwistSpec;

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The Dump with the joint table's indices, generations and removed records left out, and the
// live joints in name order.
std::string WithoutJointRecords(const std::string& dump) {
  std::string out;
  std::vector<std::string> joints;
  bool in_joints = false;
  for (const std::string& line : Lines(dump)) {
    if (line.rfind("joints ", 0) == 0) in_joints = true;
    if (in_joints && line.rfind("  joint ", 0) == 0) {
      const std::size_t at = line.find(' ', line.find("generation ") + 11);
      if (at != std::string::npos) joints.push_back(line.substr(at));
      continue;
    }
    out += line + "\n";
  }
  std::sort(joints.begin(), joints.end());
  for (const std::string& j : joints) out += "  joint" + j + "\n";
  return out;
}

// Writes `g`, runs the text on a fresh graph, and checks that every op succeeds and the graph
// is the same. Returns the text.
template <coord::Backend B>
std::string ExpectRoundTrip(const core::SceneGraph<B>& g) {
  const std::string text = WriteScene(g);
  core::SceneGraph<B> rebuilt;
  const SceneRun run = LoadScene(text, rebuilt);
  EXPECT_EQ(run.status, kExitOk) << run.error << "\n" << text;
  for (const OpResult& op : run.ops) EXPECT_TRUE(op.ok) << op.json << "\n" << text;
  if (g.joint_table().joints.size() == g.num_joints()) {
    EXPECT_EQ(Dump(rebuilt), Dump(g)) << text;
  } else {  // removed joints: the live ones come back renumbered (scene_script.h)
    EXPECT_EQ(WithoutJointRecords(Dump(rebuilt)), WithoutJointRecords(Dump(g))) << text;
  }
  EXPECT_EQ(CheckInvariants(rebuilt), "");
  // The script names its representation: running it on its own (RunScene, `semgraph run`)
  // picks the same backend.
  const SceneRun alone = RunScene(text);
  EXPECT_EQ(alone.status, kExitOk) << alone.error;
  return text;
}

// ------------------------------------------------------------------ the text

TEST(WriteScene, WritesNodesEdgesAndValuesInTheScriptFormat) {
  core::SceneGraph<> g;
  ASSERT_TRUE(g.AddBody("B"));
  ASSERT_TRUE(g.AddFrame("b", "B"));
  // The pose creates {c} and its body C: written as that pose, with its stored value.
  const Eigen::Quaterniond q_BC(0.5, 0.5, -0.5, 0.5);
  ASSERT_TRUE(
      g.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"), q_BC, Eigen::Vector3d(1, -0.25, 0.1)));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("c", "C").RelativeTo("B").ExpressedIn("c"),
                         Eigen::Vector3d(0, 0, -0.5), Eigen::Vector3d(1e-3, 0, 0)));
  const std::vector<std::string> lines = Lines(ExpectRoundTrip(g));
  ASSERT_EQ(lines.size(), 8u) << ::testing::PrintToString(lines);
  EXPECT_EQ(lines[0].rfind("# A scene written by semgraph", 0), 0u);
  EXPECT_NE(lines[0].find("2 bodies, 2 frames, 1 pose edges, 1 twist edges"), std::string::npos);
  EXPECT_EQ(lines[2], "representation: quaternion");
  EXPECT_EQ(lines[3], "ops:");
  EXPECT_EQ(lines[4], "  - {op: body, name: \"B\"}");
  EXPECT_EQ(lines[5], "  - {op: frame, name: \"b\", body: \"B\"}");
  EXPECT_EQ(
      lines[6],
      "  - {op: pose, of: \"c\", body: \"C\", wrt: \"b\", ref_body: \"B\", position: [1, -0.25, "
      "0.10000000000000001], rotation: {quaternion: [0.5, 0.5, -0.5, 0.5]}}");
  EXPECT_EQ(lines[7],
            "  - {op: twist, point: \"c\", body: \"C\", ref_body: \"B\", coord: \"c\", linear: [0, "
            "0, -0.5], "
            "angular: [0.001, 0, 0]}");
}

TEST(WriteScene, WritesWrenchesInTheirStoredForm) {
  core::SceneGraph<> g;
  const Eigen::Quaterniond q_BC(0.5, 0.5, -0.5, 0.5);
  ASSERT_TRUE(
      g.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"), q_BC, Eigen::Vector3d(1, -0.25, 0.1)));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("d", "D").RelativeTo("b", "B"), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d(0, 2, 0)));
  // Given about {b} in [b]: stored about C's frame {c} in [c] (converted), then written so.
  ASSERT_TRUE(g.AddWrench(core::WrenchSpec::On("C").By("B").At("b"), Eigen::Vector3d(1, 2, 3),
                          Eigen::Vector3d(0.5, 0, -1)));
  ASSERT_TRUE(g.AddWrench(core::WrenchSpec::On("D").By("C").At("d"), Eigen::Vector3d(0, 0, 4),
                          Eigen::Vector3d::Zero()));
  ASSERT_TRUE(g.AddWrench(core::WrenchSpec::On("B").By("D").At("b"), Eigen::Vector3d(1, 0, 0),
                          Eigen::Vector3d::Zero()));
  ASSERT_TRUE(g.RemoveWrench("C", "B"));  // a free slot: the rebuilt graph renumbers
  const std::vector<std::string> lines = Lines(ExpectRoundTrip(g));
  EXPECT_NE(lines[0].find("2 wrenches"), std::string::npos) << lines[0];
  EXPECT_EQ(lines[lines.size() - 2],
            "  - {op: wrench, on: \"D\", by: \"C\", point: \"d\", coord: \"d\", force: [0, 0, 4], "
            "moment: [0, 0, 0]}");
  EXPECT_EQ(lines.back(),
            "  - {op: wrench, on: \"B\", by: \"D\", point: \"b\", coord: \"b\", force: [1, 0, 0], "
            "moment: [0, 0, 0]}");
  // The converted value reads back bit for bit (the Dump of ExpectRoundTrip) and equals the
  // wrench as given.
  ASSERT_TRUE(g.AddWrench(core::WrenchSpec::On("C").By("B").At("b"), Eigen::Vector3d(1, 2, 3),
                          Eigen::Vector3d(0.5, 0, -1)));
  ExpectRoundTrip(g);
}

TEST(WriteScene, WritesAStampedWrenchAsItsNewestSample) {
  core::SceneGraph<> g;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d(1, 0, 0)));
  const auto spec = core::WrenchSpec::On("C").By("B").At("c");
  ASSERT_TRUE(g.AddWrench(spec, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::Zero(),
                          core::Stamp::Nanoseconds(2'000'000'000)));
  ASSERT_TRUE(g.AddWrench(spec, Eigen::Vector3d(5, 0, 0), Eigen::Vector3d::Zero(),
                          core::Stamp::Nanoseconds(1'000'000'000)));  // older: not the value
  const std::vector<std::string> lines = Lines(ExpectRoundTrip(g));
  EXPECT_EQ(lines.back(),
            "  - {op: wrench, on: \"C\", by: \"B\", point: \"c\", coord: \"c\", force: [1, 0, 0], "
            "moment: [0, 0, 0]}");
}

TEST(WriteScene, HomogeneousGraphsWriteTheStoredMatrix) {
  core::SceneGraph<coord::HomogeneousBackend> g;
  Eigen::Matrix3d R_BC;
  R_BC << 0, -1, 0, 1, 0, 0, 0, 0, 1;  // a quarter turn about z
  ASSERT_TRUE(
      g.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"), R_BC, Eigen::Vector3d(0, 0, 2)));
  const std::vector<std::string> lines = Lines(ExpectRoundTrip(g));
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[2], "representation: homogeneous");
  EXPECT_EQ(
      lines[4],
      "  - {op: pose, of: \"c\", body: \"C\", wrt: \"b\", ref_body: \"B\", position: [0, 0, 2], "
      "rotation: {matrix: [[0, -1, 0], [1, 0, 0], [0, 0, 1]]}}");
}

TEST(WriteScene, EmptyGraphAndBodiesOnly) {
  core::SceneGraph<> g;
  EXPECT_EQ(Lines(ExpectRoundTrip(g)).back(), "  []");
  ASSERT_TRUE(g.AddBody("lonely"));
  EXPECT_EQ(Lines(ExpectRoundTrip(g)).back(), "  - {op: body, name: \"lonely\"}");
}

// The pose that created {x}|X and {y}|Y was removed: nothing but an edge can intern a frame's
// name before its body's, so the writer adds one and removes it at once (a twist from the
// existing body A for {x}, then a pose under {x} for {y}), and the ids come out the same.
TEST(WriteScene, OrderOfNamesNeedsAnEdgeThatIsRemovedAgain) {
  core::SceneGraph<> g;
  ASSERT_TRUE(g.AddBody("A"));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("x", "X").RelativeTo("y", "Y"), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d(1, 2, 3)));
  ASSERT_TRUE(g.RemovePose("x", "y"));
  const std::string text = ExpectRoundTrip(g);
  EXPECT_NE(text.find("{op: remove, kind: twist, point: \"x\", ref_body: \"A\"}"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("{op: remove, kind: pose, of: \"y\", wrt: \"x\"}"), std::string::npos)
      << text;
  EXPECT_EQ(text.find("{op: frame"), std::string::npos) << text;
}

// A frame and a body may share a name, and names may be anything printable.
TEST(WriteScene, NamesThatNeedQuoting) {
  core::SceneGraph<> g;
  const std::vector<std::string> names = {"a \"quoted\" name",
                                          "back\\slash",
                                          "#hash: colon",
                                          "- dash",
                                          "null",
                                          "1",
                                          "true",
                                          " spaced ",
                                          "\xc3\xa9t\xc3\xa9",
                                          "[x]",
                                          "{y}",
                                          "&z",
                                          "*w",
                                          "!v",
                                          "u'v"};
  for (std::size_t i = 0; i + 1 < names.size(); ++i) {
    ASSERT_TRUE(g.AddPose(PoseSpec::Of(names[i + 1], names[i + 1]).RelativeTo(names[i], names[i]),
                          Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.5, 0, 0)))
        << names[i];
  }
  ExpectRoundTrip(g);
}

// ------------------------------------------------------------------ every script of the repository

TEST(WriteScene, RoundTripsEveryScriptOfTheRepository) {
  const std::filesystem::path root = SEMGRAPH_SOURCE_DIR;
  std::vector<std::filesystem::path> scripts;
  for (const auto& dir : {root / "examples", root / "tests" / "tools" / "scripts"}) {
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      if (entry.path().extension() == ".yaml") scripts.push_back(entry.path());
    }
  }
  ASSERT_GT(scripts.size(), 20u);
  int loaded = 0;
  for (const auto& path : scripts) {
    SCOPED_TRACE(path.string());
    const std::string text = ReadFile(path);
    core::SceneGraph<coord::QuaternionBackend> q;
    core::SceneGraph<coord::HomogeneousBackend> h;
    if (LoadScene(text, q).status == kExitMalformed) continue;  // malformed on purpose
    ASSERT_NE(LoadScene(text, h).status, kExitMalformed);
    ExpectRoundTrip(q);
    ExpectRoundTrip(h);
    loaded += q.num_frames() > 0 ? 1 : 0;
  }
  EXPECT_GE(loaded, 10);
}

// ------------------------------------------------------------------ random scenes

// Random ops over small pools of names (frames and bodies overlap, some names need quoting),
// most of them accepted: bodies, frames, poses creating their frames and bodies (edge form,
// other points, coordinate frames, matrices, near-unit quaternions), twists (screw twists and
// other coordinate frames), value updates and removals. Rejected ops change nothing.
template <coord::Backend B>
void BuildRandomScene(core::SceneGraph<B>& g, std::mt19937_64& rng, int num_ops) {
  static const std::vector<std::string> frames = {"f0", "f1", "f2", "f3",  "f4",   "f5",      "f6",
                                                  "f7", "f8", "B1", "a b", "q\"t", "\xc3\xa9"};
  static const std::vector<std::string> bodies = {"B0", "B1", "B2", "B3", "B4", "f8", "C d"};
  const auto pick = [&](const std::vector<std::string>& v) -> const std::string& {
    return v[std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng)];
  };
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto vec = [&] { return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)); };
  const auto quat = [&] {
    Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
    q.normalize();
    if (unit(rng) < 0.3) q.coeffs() *= 1.0 + 4e-7 * (unit(rng) - 0.5);  // off-unit, accepted
    return q;
  };
  const auto existing_frame = [&]() -> std::string {
    if (g.num_frames() == 0) return pick(frames);
    const std::uint32_t i =
        std::uniform_int_distribution<std::uint32_t>(0, g.num_frames() - 1)(rng);
    return std::string(g.frame_name(core::FrameIndex(i)));
  };
  for (int k = 0; k < num_ops; ++k) {
    const double u = unit(rng);
    const bool has_frames = g.num_frames() > 0;
    if (u < 0.06) {
      (void)g.AddBody(pick(bodies));
    } else if (u < 0.14) {
      (void)g.AddFrame(pick(frames), pick(bodies));
    } else if (u < 0.47) {  // an edge-form pose, naming bodies so that new frames can be made
      const PoseSpec spec =
          PoseSpec::Of(pick(frames), pick(bodies)).RelativeTo(pick(frames), pick(bodies));
      if (unit(rng) < 0.2) {
        (void)g.AddPose(spec, quat().toRotationMatrix(), vec());
      } else {
        (void)g.AddPose(spec, quat(), vec());
      }
    } else if (u < 0.53) {  // a joint (creating its frames, as a pose does), sometimes a mimic
      static const std::vector<std::string> joint_names = {"j0", "j1", "j2", "j3"};
      core::JointSpec j;
      j.name = pick(joint_names);
      j.type = static_cast<core::JointType>(std::uniform_int_distribution<int>(0, 3)(rng));
      j.parent = pick(frames);
      j.parent_body = pick(bodies);
      j.child = pick(frames);
      j.child_body = pick(bodies);
      j.q_origin = quat();
      j.p_origin = vec();
      j.axis = vec();
      j.lower = -1;
      j.upper = 1.5;
      if (unit(rng) < 0.3) {
        j.mimic = pick(joint_names);
        j.multiplier = normal(rng);
        j.offset = 0.1;
      }
      (void)g.AddJoint(j);
      const core::JointValue q[] = {{pick(joint_names), 0.5 * unit(rng)}};
      const core::JointValue qdot[] = {{pick(joint_names), normal(rng)}};
      (void)g.SetJoints(q, qdot);
    } else if (u < 0.58) {  // a pose given in another form: converted to the edge form once
      // A spec views its names: each one is kept in a string that outlives the add.
      const std::string ref = existing_frame();
      PoseSpec spec = PoseSpec::Of(pick(frames), pick(bodies)).RelativeTo(ref);
      std::string coord, ref_point;
      if (unit(rng) < 0.5) {
        coord = existing_frame();
        spec.ExpressedIn(coord);
      }
      if (unit(rng) < 0.3) {
        ref_point = existing_frame();
        spec.RelativeToPoint(ref_point);
      }
      (void)g.AddPose(spec, quat(), vec());
    } else if (!has_frames) {
      continue;
    } else if (u < 0.66) {  // an update of an existing edge
      const std::string of = existing_frame();
      const core::FrameIndex p = g.pose_parent(g.FindFrame(of));
      if (p.is_valid())
        (void)g.AddPose(PoseSpec::Of(of).RelativeTo(g.frame_name(p)), quat(), vec());
    } else if (u < 0.82) {
      TwistSpec spec = TwistSpec::Of(pick(frames), pick(bodies)).RelativeTo(pick(bodies));
      const std::string coord =
          unit(rng) < 0.5 ? std::string(spec.point) : existing_frame();  // the spec views it
      spec.ExpressedIn(coord);
      (void)g.AddTwist(spec, vec(), vec());
    } else if (u < 0.92) {
      const std::string of = existing_frame();
      const core::FrameIndex p = g.pose_parent(g.FindFrame(of));
      if (p.is_valid()) (void)g.RemovePose(of, g.frame_name(p));
    } else {
      const std::string of = existing_frame();
      const core::BodyIndex D = g.twist_parent(g.FindFrame(of));
      if (D.is_valid()) (void)g.RemoveTwist(of, g.body_name(D));
    }
  }
}

template <class B>
class WriteSceneRandom : public ::testing::Test {};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(WriteSceneRandom, Backends);

TYPED_TEST(WriteSceneRandom, RebuildsTheSameGraph) {
  std::size_t frames = 0, pose_edges = 0, twist_edges = 0, removals = 0, joints = 0;
  for (std::uint64_t seed = 0; seed < 300; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    core::SceneGraph<TypeParam> g;
    BuildRandomScene(g, rng, 10 + static_cast<int>(seed % 60));
    ASSERT_EQ(CheckInvariants(g), "");
    const std::string text = ExpectRoundTrip(g);
    if (::testing::Test::HasFailure()) return;
    frames += g.num_frames();
    pose_edges += g.num_pose_edges();
    twist_edges += g.num_twist_edges();
    joints += g.num_joints();
    for (std::size_t at = text.find("op: remove"); at != std::string::npos;
         at = text.find("op: remove", at + 1)) {
      ++removals;
    }
  }
  // The scenes are not trivial: many frames and edges, and the order of names needed edges
  // that were removed again.
  EXPECT_GT(frames, 1500u);
  EXPECT_GT(pose_edges, 600u);
  EXPECT_GT(twist_edges, 150u);
  EXPECT_GT(removals, 20u);
  EXPECT_GT(joints, 50u);
}

// ------------------------------------------------------------------ covariances

// A scene with covariances on pose and twist edges (tests/tools/scripts/covariance_chain.yaml,
// given in both orders and both conventions) is written with them, in edge form and the default
// order, and comes back with every edge's covariance and every answer's covariance identical.
TEST(WriteScene, RoundTripsCovariances) {
  const std::filesystem::path script = std::filesystem::path(SEMGRAPH_SOURCE_DIR) / "tests" /
                                       "tools" / "scripts" / "covariance_chain.yaml";
  core::SceneGraph<coord::QuaternionBackend> g;
  ASSERT_EQ(LoadScene(ReadFile(script), g).status, kExitOk);
  const std::string text = ExpectRoundTrip(g);
  EXPECT_NE(text.find(", covariance: [["), std::string::npos) << text;
  core::SceneGraph<coord::QuaternionBackend> rebuilt;
  ASSERT_EQ(LoadScene(text, rebuilt).status, kExitOk);
  int nonzero = 0;
  for (std::uint32_t i = 0; i < g.num_frames(); ++i) {
    const core::FrameIndex f(i);
    EXPECT_EQ(rebuilt.pose_covariance(f), g.pose_covariance(f)) << g.frame_name(f);
    EXPECT_EQ(rebuilt.twist_covariance(f), g.twist_covariance(f)) << g.frame_name(f);
    nonzero += g.pose_covariance(f).isZero(0.0) ? 0 : 1;
    nonzero += g.twist_covariance(f).isZero(0.0) ? 0 : 1;
    for (std::uint32_t j = 0; j < g.num_frames(); ++j) {
      const std::string of(g.frame_name(f)), wrt(g.frame_name(core::FrameIndex(j)));
      const PoseSpec spec = PoseSpec::Of(of).RelativeTo(wrt);
      const auto before = g.GetPoseWithCovariance(spec);
      const auto after = rebuilt.GetPoseWithCovariance(spec);
      ASSERT_EQ(before.has_value(), after.has_value()) << of << " wrt " << wrt;
      if (!before) continue;
      EXPECT_EQ(after->covariance, before->covariance) << of << " wrt " << wrt;
    }
  }
  EXPECT_EQ(nonzero, 4);  // a, b, c pose edges and the twist edge at a
  const TwistSpec twist = TwistSpec::Of("a").RelativeTo("W").ExpressedIn("w");
  EXPECT_EQ(rebuilt.GetTwistWithCovariance(twist)->covariance,
            g.GetTwistWithCovariance(twist)->covariance);
}

}  // namespace
}  // namespace semgraph::script
