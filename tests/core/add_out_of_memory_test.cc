// All or nothing under allocation failure (core/src/add.cc, topology/src/scene_topology.cc): every
// build operation that changes the graph, failed at each of its allocations in turn, leaves the
// graph exactly as it was, and the graph keeps working.
//
// For each operation and each n = 1, 2, ...: a fresh scene is built; the n-th allocation of the
// operation is made to fail (support/alloc_counter.h, FailAt: operator new throws std::bad_alloc);
// the operation must let std::bad_alloc through, and afterwards
//   - Dump() (names, ids, nodes, edges, every stored value) equals the one before,
//   - CheckInvariants() (every invariant, recounted from scratch) is empty,
//   - the answers of every pose query between every two frames and of every twist query of
//     every frame wrt every body (codes and numbers) equal the ones before,
//   - running the operation again, without failure, gives the result, Dump and answers of the
//     operation run on an untouched scene.
// n stops at the first value the operation no longer reaches: n - 1 is the number of its
// allocation points. Each operation runs at several fill levels of the scene, so that every
// container is met full. The counts are printed (operations x fill levels x allocation points).
// Operations: AddBody, AddFrame, AddPose (new leaf, constant leaf, linking two trees or a single
// frame, a new root, two new frames, a value update, the non-edge form, stamped, repaired by the
// inverse and by re-rooting, rejections), AddTwist (new edge, new frame and bodies, converted,
// update, stamped, rejected), RemovePose (splits, leaves, rejected), RemoveTwist, AddJoint (new
// frames, linking two trees, a mimic, rejected) and the removal of a joint (RemovePose of its
// edge).
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <iostream>
#include <new>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/alloc_counter.h"

namespace semgraph::core {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;
using semgraph::testing::AllocationCounter;

Quaterniond Rotation(double angle) {
  return Quaterniond(Eigen::AngleAxisd(angle, Vector3d(1, 2, 3).normalized()));
}

JointSpec Joint(std::string_view name, JointType type, std::string_view parent,
                std::string_view parent_body, std::string_view child, std::string_view child_body) {
  JointSpec j;
  j.name = name;
  j.type = type;
  j.parent = parent;
  j.parent_body = parent_body;
  j.child = child;
  j.child_body = child_body;
  j.q_origin = Rotation(0.4);
  j.p_origin = Vector3d(0.1, 0.2, -0.3);
  j.axis = Vector3d(0, 0, 1);
  j.lower = -2;
  j.upper = 2;
  return j;
}

// Two pose trees with twist graphs, a single frame, a body without frames, and a removed pose
// edge and twist edge (so that free records and free twist slots exist):
//   tree 1: {w}|W <- {a}|A <- {a2}|A (constant), {a} <- {b}|B <- {c}|C;
//           twists W -> {a}, A -> {b}, B -> {c}
//   tree 2: {p}|P <- {q}|Q <- {r}|R; twists P -> {q}, Q -> {r}
//   single: {s}|S; body T; {u}|U (was under {r}, removed), twist T -> {u} removed.
//   before all that, `fill` filler pairs {f_i}|F_i <- {g_i}|G_i with a twist G_i -> {f_i}: the
//   same operation then runs with every container at another fill level, so that each one is
//   met when it is full and must grow (vectors double, hash tables rehash, name blocks run out).
template <class B>
void BuildScene(SceneGraph<B>& g, int fill) {
  for (int i = 0; i < fill; ++i) {
    const std::string f = "f" + std::to_string(i), gi = "g" + std::to_string(i);
    ASSERT_TRUE(
        g.AddPose(PoseSpec::Of(f, "F" + std::to_string(i)).RelativeTo(gi, "G" + std::to_string(i)),
                  Quaterniond::Identity(), Vector3d(i, 0, 0)));
    ASSERT_TRUE(g.AddTwist(TwistSpec::Of(f).RelativeTo("G" + std::to_string(i)).ExpressedIn(f),
                           Vector3d::Zero(), Vector3d::Zero()));
  }
  auto pose = [&](const char* of, const char* of_body, const char* wrt, const char* wrt_body,
                  double k) {
    ASSERT_TRUE(g.AddPose(PoseSpec::Of(of, of_body).RelativeTo(wrt, wrt_body), Rotation(0.1 * k),
                          Vector3d(0.5 * k, -0.25, 0.125 * k)));
  };
  auto twist = [&](const char* point, const char* body, const char* wrt, double k) {
    ASSERT_TRUE(g.AddTwist(TwistSpec::Of(point, body).RelativeTo(wrt).ExpressedIn(point),
                           Vector3d(k, 0.5, -k), Vector3d(0.1, -0.2 * k, 0.3)));
  };
  pose("a", "A", "w", "W", 1);
  pose("a2", "A", "a", "A", 2);
  pose("b", "B", "a", "A", 3);
  pose("c", "C", "b", "B", 4);
  twist("a", "A", "W", 1);
  twist("b", "B", "A", 2);
  twist("c", "C", "B", 3);
  pose("q", "Q", "p", "P", 5);
  pose("r", "R", "q", "Q", 6);
  twist("q", "Q", "P", 4);
  twist("r", "R", "Q", 5);
  ASSERT_TRUE(g.AddBody("S"));
  ASSERT_TRUE(g.AddFrame("s", "S"));
  ASSERT_TRUE(g.AddBody("T"));
  pose("u", "U", "r", "R", 7);
  twist("u", "U", "T", 6);
  ASSERT_TRUE(g.RemoveTwist("u", "T"));
  ASSERT_TRUE(g.RemovePose("u", "r"));
  // tree 3, two joints: {jw}|JW <-(j1, revolute) {ja}|JA <-(j2, prismatic) {jb}|JB, and j3 =
  // a mimic of j1 from {jb} to {jc}|JC.
  ASSERT_TRUE(g.AddJoint(Joint("j1", JointType::kRevolute, "jw", "JW", "ja", "JA")));
  ASSERT_TRUE(g.AddJoint(Joint("j2", JointType::kPrismatic, "ja", "JA", "jb", "JB")));
  JointSpec j3 = Joint("j3", JointType::kRevolute, "jb", "JB", "jc", "JC");
  j3.mimic = "j1";
  j3.multiplier = -0.5;
  ASSERT_TRUE(g.AddJoint(j3));
  const JointValue q[] = {{"j1", 0.3}, {"j2", 0.2}};
  ASSERT_TRUE(g.SetJoints(q, {}));
}

// Every pose query between the scene's frames (and the frames operations create) and every
// twist query of each frame wrt each body: code and numbers (compared exactly: the same graph
// gives bit-identical answers).
template <class B>
std::vector<double> Answers(const SceneGraph<B>& g) {
  static const char* const kFrames[] = {"w", "a",  "a2", "b",  "c",  "p",   "q", "r",
                                        "s", "u",  "n",  "l",  "c2", "top", "x", "y",
                                        "d", "jw", "ja", "jb", "jc", "kp",  "kc"};
  static const char* const kBodies[] = {"W",  "A",  "B",  "C",  "P",   "Q", "R", "S",
                                        "T",  "U",  "N",  "L",  "Top", "X", "Y", "D",
                                        "JW", "JA", "JB", "JC", "KP",  "KC"};
  std::vector<double> out;
  out.reserve(8192);
  for (const char* of : kFrames) {
    for (const char* wrt : kFrames) {
      const auto X = g.GetPose(PoseSpec::Of(of).RelativeTo(wrt));
      out.push_back(static_cast<double>(X ? ErrorCode::kOk : X.error().code));
      if (!X) continue;
      const Vector3d p = B::TranslationOf(X->value);
      const Eigen::Vector4d q = B::ToQuaternion(B::RotationOf(X->value)).coeffs();
      out.insert(out.end(), {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()});
    }
    for (const char* body : kBodies) {
      const auto V = g.GetTwist(TwistSpec::Of(of).RelativeTo(body).ExpressedIn(of));
      out.push_back(static_cast<double>(V ? ErrorCode::kOk : V.error().code));
      if (!V) continue;
      out.insert(out.end(), {V->linear.x(), V->linear.y(), V->linear.z(), V->angular.x(),
                             V->angular.y(), V->angular.z()});
    }
  }
  return out;
}

template <class B>
struct Operation {
  const char* name;
  std::function<BuildResult(SceneGraph<B>&)> run;
  ErrorCode expected;  // kOk, or the rejection's code
};

// A repairing add's result as a plain one (its report is checked by tests/core/repair_test.cc).
BuildResult Plain(const Expected<RepairReport, BuildError>& r) {
  if (r) return Ok{};
  return base::Unexpected{r.error()};
}

template <class B>
std::vector<Operation<B>> Operations() {
  const Quaterniond q = Rotation(0.7);
  const Vector3d p(0.3, -0.6, 0.9), v(1, -2, 3), w(-0.5, 0.25, 0.125);
  using G = SceneGraph<B>;
  return {
      {"AddBody", [](G& g) { return g.AddBody("N"); }, ErrorCode::kOk},
      {"AddFrame", [](G& g) { return g.AddFrame("n", "S"); }, ErrorCode::kOk},
      {"AddPose leaf, new body",
       [=](G& g) { return g.AddPose(PoseSpec::Of("l", "L").RelativeTo("c"), q, p); },
       ErrorCode::kOk},
      {"AddPose leaf, constant",
       [=](G& g) { return g.AddPose(PoseSpec::Of("c2", "C").RelativeTo("c"), q, p); },
       ErrorCode::kOk},
      {"AddPose link two trees",
       [=](G& g) { return g.AddPose(PoseSpec::Of("p").RelativeTo("c"), q, p); }, ErrorCode::kOk},
      {"AddPose link a single frame",
       [=](G& g) { return g.AddPose(PoseSpec::Of("s").RelativeTo("c"), q, p); }, ErrorCode::kOk},
      {"AddPose new root above a tree",
       [=](G& g) { return g.AddPose(PoseSpec::Of("w").RelativeTo("top", "Top"), q, p); },
       ErrorCode::kOk},
      {"AddPose two new frames",
       [=](G& g) { return g.AddPose(PoseSpec::Of("x", "X").RelativeTo("y", "Y"), q, p); },
       ErrorCode::kOk},
      {"AddPose update", [=](G& g) { return g.AddPose(PoseSpec::Of("b").RelativeTo("a"), q, p); },
       ErrorCode::kOk},
      {"AddPose non-edge form (link)",
       [=](G& g) { return g.AddPose(PoseSpec::Of("p").RelativeTo("c").ExpressedIn("b"), q, p); },
       // The homogeneous representation holds poses in edge form only.
       std::is_same_v<B, coord::HomogeneousBackend> ? ErrorCode::kRepresentationConstraint
                                                    : ErrorCode::kOk},
      {"AddPose rejected, new names (P1)",
       [=](G& g) { return g.AddPose(PoseSpec::Of("c").RelativeTo("y", "Y"), q, p); },
       ErrorCode::kMultiplePoseParents},
      {"AddPose rejected (P2)",
       [=](G& g) { return g.AddPose(PoseSpec::Of("w").RelativeTo("c"), q, p); },
       ErrorCode::kPoseCycle},
      {"AddTwist single frame",
       [=](G& g) { return g.AddTwist(TwistSpec::Of("s").RelativeTo("W").ExpressedIn("s"), v, w); },
       ErrorCode::kOk},
      {"AddTwist new frame and bodies",
       [=](G& g) {
         return g.AddTwist(TwistSpec::Of("d", "D").RelativeTo("N").ExpressedIn("d"), v, w);
       },
       ErrorCode::kOk},
      {"AddTwist converted",
       [=](G& g) { return g.AddTwist(TwistSpec::Of("p").RelativeTo("T").ExpressedIn("q"), v, w); },
       ErrorCode::kOk},
      {"AddTwist update",
       [=](G& g) { return g.AddTwist(TwistSpec::Of("b").RelativeTo("A").ExpressedIn("b"), v, w); },
       ErrorCode::kOk},
      {"AddTwist rejected (W3)",
       [=](G& g) {
         return g.AddTwist(TwistSpec::Of("a2").RelativeTo("W").ExpressedIn("a2"), v, w);
       },
       ErrorCode::kDuplicateTwistPath},
      {"AddPose stamped",
       [=](G& g) {
         return g.AddPose(PoseSpec::Of("l", "L").RelativeTo("c"), q, p, Stamp::Nanoseconds(7));
       },
       ErrorCode::kOk},
      {"AddTwist stamped",
       [=](G& g) {
         return g.AddTwist(TwistSpec::Of("s").RelativeTo("W").ExpressedIn("s"), v, w,
                           Stamp::Nanoseconds(7));
       },
       ErrorCode::kOk},
      {"AddPose repaired by the inverse",
       [=](G& g) {
         return Plain(g.AddPose(PoseSpec::Of("a").RelativeTo("s"), q, p, RepairPolicy{}));
       },
       ErrorCode::kOk},
      {"AddPose repaired by re-rooting",
       [=](G& g) {
         return Plain(g.AddPose(PoseSpec::Of("a").RelativeTo("q"), q, p, RepairPolicy{}));
       },
       ErrorCode::kOk},
      {"RemovePose split", [](G& g) { return g.RemovePose("b", "a"); }, ErrorCode::kOk},
      {"RemovePose leaf with a twist", [](G& g) { return g.RemovePose("c", "b"); }, ErrorCode::kOk},
      {"RemovePose constant leaf", [](G& g) { return g.RemovePose("a2", "a"); }, ErrorCode::kOk},
      {"RemovePose root edge", [](G& g) { return g.RemovePose("a", "w"); }, ErrorCode::kOk},
      {"RemovePose rejected", [](G& g) { return g.RemovePose("a", "b"); }, ErrorCode::kNoSuchEdge},
      {"RemoveTwist inner", [](G& g) { return g.RemoveTwist("b", "A"); }, ErrorCode::kOk},
      {"RemoveTwist last of a tree", [](G& g) { return g.RemoveTwist("r", "Q"); }, ErrorCode::kOk},
      {"RemoveTwist rejected", [](G& g) { return g.RemoveTwist("b", "W"); },
       ErrorCode::kNoSuchEdge},
      {"AddJoint new frames and bodies",
       [](G& g) { return g.AddJoint(Joint("k1", JointType::kRevolute, "kp", "KP", "kc", "KC")); },
       ErrorCode::kOk},
      {"AddJoint linking two trees",
       [](G& g) { return g.AddJoint(Joint("k1", JointType::kPrismatic, "c", "C", "p", "P")); },
       ErrorCode::kOk},
      {"AddJoint a single frame under a tree",
       [](G& g) { return g.AddJoint(Joint("k1", JointType::kContinuous, "jc", "JC", "s", "S")); },
       ErrorCode::kOk},
      {"AddJoint fixed, new child",
       [](G& g) { return g.AddJoint(Joint("k1", JointType::kFixed, "b", "B", "kc", "KC")); },
       ErrorCode::kOk},
      {"AddJoint mimic",
       [](G& g) {
         JointSpec k = Joint("k1", JointType::kRevolute, "jc", "JC", "kc", "KC");
         k.mimic = "j1";
         return g.AddJoint(k);
       },
       ErrorCode::kOk},
      {"AddJoint rejected (duplicate name)",
       [](G& g) { return g.AddJoint(Joint("j1", JointType::kRevolute, "kp", "KP", "kc", "KC")); },
       ErrorCode::kDuplicateJoint},
      {"RemovePose of a joint (mimic)", [](G& g) { return g.RemovePose("jc", "jb"); },
       ErrorCode::kOk},
      {"RemovePose of a joint (inner)", [](G& g) { return g.RemovePose("jb", "ja"); },
       ErrorCode::kOk},
      {"RemovePose of a mimicked joint, rejected", [](G& g) { return g.RemovePose("ja", "jw"); },
       ErrorCode::kJointEdge},
  };
}

ErrorCode CodeOf(const BuildResult& r) { return r ? ErrorCode::kOk : r.error().code; }

template <class B>
class AddOutOfMemory : public ::testing::Test {};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(AddOutOfMemory, Backends);

// Fill levels of the scene (see BuildScene): 0 .. kFills - 1 (fewer in Debug and sanitizer
// builds, which run this test several times slower; the smaller containers' growth points are
// all met below 10).
#ifdef NDEBUG
constexpr int kFills = 18;
#else
constexpr int kFills = 10;
#endif

TYPED_TEST(AddOutOfMemory, EveryBuildOperationIsAllOrNothingAtEveryAllocation) {
  using B = TypeParam;
  std::size_t runs = 0, points = 0, broken_points = 0;
  std::ostringstream table;
  const std::vector<Operation<B>> operations = Operations<B>();
  for (const Operation<B>& op : operations) {
    SCOPED_TRACE(op.name);
    std::size_t op_points = 0, op_most = 0;
    for (int fill = 0; fill < kFills; ++fill) {
      // The reference: the operation on an untouched scene.
      SceneGraph<B> reference;
      BuildScene(reference, fill);
      const std::string untouched = Dump(reference);
      const std::vector<double> untouched_answers = Answers(reference);
      ASSERT_EQ(CodeOf(op.run(reference)), op.expected);
      const std::string after = Dump(reference);
      const std::vector<double> after_answers = Answers(reference);
      ASSERT_EQ(CheckInvariants(reference), "");

      std::size_t n = 1;
      for (;; ++n) {
        SceneGraph<B> g;
        BuildScene(g, fill);
        const std::string& before = untouched;
        const std::vector<double>& before_answers = untouched_answers;
        bool threw = false;
        ErrorCode code = ErrorCode::kOk;
        AllocationCounter::Arm();
        AllocationCounter::FailAt(n);
        try {
          code = CodeOf(op.run(g));
        } catch (const std::bad_alloc&) {
          threw = true;
        }
        const bool failed = AllocationCounter::failed();
        AllocationCounter::Disarm();
        if (!failed) {  // the operation made fewer than n allocations
          ASSERT_FALSE(threw);
          EXPECT_EQ(code, op.expected);
          EXPECT_EQ(Dump(g), after);
          break;
        }
        // What went wrong, if anything (the first problem only: one line per broken point).
        std::string problem;
        if (!threw) {
          problem = "an allocation failed but the operation returned normally";
        } else if (Dump(g) != before) {
          problem = "Dump changed";
        } else if (const std::string broken = CheckInvariants(g); !broken.empty()) {
          problem = "invariants broken: " + broken;
        } else if (Answers(g) != before_answers) {
          problem = "query answers changed";
        } else if (CodeOf(op.run(g)) != op.expected || Dump(g) != after) {
          problem = "the operation, run again, gives another result";
        } else if (!CheckInvariants(g).empty() || Answers(g) != after_answers) {
          problem = "the operation, run again, breaks the graph";
        }
        if (!problem.empty()) {
          ++broken_points;
          ADD_FAILURE() << op.name << ", fill " << fill << ", allocation " << n
                        << " failed: " << problem;
        }
      }
      ++runs;
      op_points += n - 1;
      op_most = std::max(op_most, n - 1);
    }
    points += op_points;
    table << "  " << op.name << ": " << op_points << " (up to " << op_most << " per run)\n";
  }
  std::cout << B::kName << ": " << operations.size() << " operations x " << kFills
            << " fill levels = " << runs << " runs; " << points
            << " allocation points failed one at a time; " << broken_points << " broke the graph\n"
            << table.str();
  EXPECT_GT(points, 2 * runs);  // the test reaches allocations at all
}

}  // namespace
}  // namespace semgraph::core
