// Compiled acceleration queries and SetAcceleration (compiled_acceleration.h, scene_graph.h
// "accelerations"): on random chains, Evaluate gives GetAcceleration's answer (which the DART
// test checks against the peer) before and after new values; on the spinning disc of
// accelerations_test.cc, a value written through a handle reads back by hand; the codes:
// kNoAcceleration (a twist given since without one), kQueryInvalidated (an edge removed),
// SetAcceleration's kNoSuchEdge, kInvalidNumber, kJointEdge, kStampMismatch, each writing nothing;
// under one concurrent writer every answer is one record's, never a mix of two (the record's
// words are read straight from its sequence lock).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>
#include <string>
#include <thread>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/tolerance.h"
#include "support/world_scene.h"

namespace semgraph::core {
namespace {

using semgraph::testing::Near;
using semgraph::testing::RandomUnitQuaternion;
using semgraph::testing::RandomVector;
using Vec = Eigen::Vector3d;

template <class B>
class CompiledAccelerations : public ::testing::Test {};
struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(CompiledAccelerations, Backends, BackendName);

// A chain W -> L1 -> ... -> L6 with random poses, twists and accelerations, each twist edge from
// the previous body (even i) or to it (odd i, on a frame g<i> of the previous body).
template <class B>
void BuildChain(SceneGraph<B>& g, std::mt19937_64& rng) {
  std::string parent = "w", parent_body = "W";
  for (int i = 1; i <= 6; ++i) {
    const std::string f = "l" + std::to_string(i), b = "L" + std::to_string(i);
    ASSERT_TRUE(g.AddPose(PoseSpec::Of(f, b).RelativeTo(parent, parent_body),
                          RandomUnitQuaternion(rng), RandomVector(rng, 1.0)));
    const AccelerationInput A{RandomVector(rng, 1.0), RandomVector(rng, 1.0)};
    if (i % 2 == 0) {
      ASSERT_TRUE(g.AddTwist(TwistSpec::Of(f, b).RelativeTo(parent_body).ExpressedIn(parent),
                             RandomVector(rng, 1.0), RandomVector(rng, 1.0), A));
    } else {
      const std::string h = "g" + std::to_string(i);
      ASSERT_TRUE(g.AddPose(PoseSpec::Of(h, parent_body).RelativeTo(parent, parent_body),
                            RandomUnitQuaternion(rng), RandomVector(rng, 1.0)));
      ASSERT_TRUE(g.AddTwist(TwistSpec::Of(h, parent_body).RelativeTo(b).ExpressedIn(f),
                             RandomVector(rng, 1.0), RandomVector(rng, 1.0), A));
    }
    parent = f;
    parent_body = b;
  }
}

TYPED_TEST(CompiledAccelerations, EvaluateAgreesWithTheOneShotQuery) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    std::mt19937_64 rng(seed);
    SceneGraph<TypeParam> g;
    BuildChain(g, rng);
    const TwistSpec specs[] = {TwistSpec::Of("l2", "L6").RelativeTo("W").ExpressedIn("l4"),
                               TwistSpec::Of("w", "L1").RelativeTo("L5").ExpressedIn("l5"),
                               TwistSpec::Of("l3", "L3").RelativeTo("L3").ExpressedIn("w")};
    for (const TwistSpec& spec : specs) {
      auto compiled = g.CompileAcceleration(spec);
      ASSERT_TRUE(compiled) << g.Describe(compiled.error(), spec);
      for (int round = 0; round < 2; ++round) {
        auto one_shot = g.GetAcceleration(spec);
        ASSERT_TRUE(one_shot) << g.Describe(one_shot.error(), spec);
        auto A = compiled->Evaluate();
        ASSERT_TRUE(A);
        EXPECT_EQ(A->semantics, one_shot->semantics);
        EXPECT_TRUE(Near(A->linear, one_shot->linear, 1e-12));
        EXPECT_TRUE(Near(A->angular, one_shot->angular, 1e-12));
        // New values of every edge (poses, twists with accelerations), then again.
        auto h = g.FindTwistEdge("l2", "L1");
        ASSERT_TRUE(h);
        ASSERT_EQ(g.SetTwist(*h, RandomVector(rng, 1.0), RandomVector(rng, 1.0)), ErrorCode::kOk);
        ASSERT_EQ(g.SetAcceleration(*h, RandomVector(rng, 1.0), RandomVector(rng, 1.0)),
                  ErrorCode::kOk);
        auto p = g.FindPoseEdge("l4", "l3");
        ASSERT_TRUE(p);
        ASSERT_EQ(g.SetPose(*p, RandomUnitQuaternion(rng), RandomVector(rng, 1.0)), ErrorCode::kOk);
      }
    }
    EXPECT_EQ(CheckInvariants(g), "");
  }
}

TYPED_TEST(CompiledAccelerations, SetAccelerationByHandAndItsCodes) {
  SceneGraph<TypeParam> g;
  const Eigen::Quaterniond q90(Eigen::AngleAxisd(M_PI / 2, Vec::UnitZ()));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("d", "Disc").RelativeTo("w", "G"), q90, Vec::Zero()));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("p", "Disc").RelativeTo("d", "Disc"),
                        Eigen::Quaterniond::Identity(), Vec(3, 0, 0)));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("d", "Disc").RelativeTo("G").ExpressedIn("d"), Vec::Zero(),
                         Vec(0, 0, 2)));
  const TwistSpec at_p = TwistSpec::Of("p", "Disc").RelativeTo("G").ExpressedIn("d");
  auto compiled = g.CompileAcceleration(at_p);
  ASSERT_TRUE(compiled);
  Vec a(7, 7, 7), alpha(7, 7, 7);
  EXPECT_EQ(compiled->Evaluate(a, alpha), ErrorCode::kNoAcceleration);
  EXPECT_EQ(a, Vec(7, 7, 7));  // unchanged
  auto h = g.FindTwistEdge("d", "G");
  ASSERT_TRUE(h);
  // Refused values write nothing.
  const std::string before = Dump(g);
  EXPECT_EQ(g.SetAcceleration(*h, Vec(std::nan(""), 0, 0), Vec::Zero()), ErrorCode::kInvalidNumber);
  EXPECT_EQ(g.SetAcceleration(TwistHandle{}, Vec::Zero(), Vec::Zero()), ErrorCode::kNoSuchEdge);
  EXPECT_EQ(Dump(g), before);
  // alpha = 0.5 about z at d: at p (R = 3, W = 2) a = (-12, 1.5, 0) in [d], as by hand.
  ASSERT_EQ(g.SetAcceleration(*h, Vec::Zero(), Vec(0, 0, 0.5)), ErrorCode::kOk);
  ASSERT_EQ(compiled->Evaluate(a, alpha), ErrorCode::kOk);
  EXPECT_TRUE(Near(a, Vec(-12, 1.5, 0)));
  EXPECT_TRUE(Near(alpha, Vec(0, 0, 0.5)));
  // A twist without an acceleration clears it; a removal invalidates.
  ASSERT_EQ(g.SetTwist(*h, Vec::Zero(), Vec(0, 0, 1)), ErrorCode::kOk);
  EXPECT_EQ(compiled->Evaluate(a, alpha), ErrorCode::kNoAcceleration);
  ASSERT_EQ(g.SetAcceleration(*h, Vec::Zero(), Vec(0, 0, 0.5)), ErrorCode::kOk);
  ASSERT_TRUE(g.RemoveTwist("d", "G"));
  EXPECT_EQ(compiled->Evaluate(a, alpha), ErrorCode::kQueryInvalidated);
  EXPECT_EQ(g.SetAcceleration(*h, Vec::Zero(), Vec::Zero()), ErrorCode::kNoSuchEdge);
  EXPECT_EQ(CheckInvariants(g), "");
}

TYPED_TEST(CompiledAccelerations, StampedEdgesRefuseAnAcceleration) {
  SceneGraph<TypeParam> g;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("d", "Disc").RelativeTo("w", "G"),
                        Eigen::Quaterniond::Identity(), Vec::Zero()));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("d", "Disc").RelativeTo("G").ExpressedIn("d"), Vec::Zero(),
                         Vec(0, 0, 2), Stamp::Nanoseconds(1000)));
  auto h = g.FindTwistEdge("d", "G");
  ASSERT_TRUE(h);
  EXPECT_EQ(g.SetAcceleration(*h, Vec::Zero(), Vec::Zero()), ErrorCode::kStampMismatch);
  auto r = g.AddAcceleration(TwistSpec::Of("d", "Disc").RelativeTo("G").ExpressedIn("d"),
                             Vec::Zero(), Vec::Zero());
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kStampMismatch);
  EXPECT_FALSE(g.acceleration_value(g.FindFrame("d")));
}

// Found by scene_ops_fuzzer (op 15): a compiled query whose edge has no acceleration and whose
// pose chain lost an edge said kNoAcceleration; the removal comes first (kQueryInvalidated),
// as for a removed twist edge after an edge without an acceleration.
TYPED_TEST(CompiledAccelerations, ARemovedEdgeComesBeforeAMissingAcceleration) {
  SceneGraph<TypeParam> g;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c", "B").RelativeTo("a", "A"), Eigen::Quaterniond::Identity(),
                        Vec(1, 0, 0)));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("c", "B").RelativeTo("A").ExpressedIn("c"), Vec::Zero(),
                         Vec(0, 0, 1)));  // no acceleration
  auto at_a = g.CompileAcceleration(TwistSpec::Of("a", "B").RelativeTo("A").ExpressedIn("a"));
  ASSERT_TRUE(at_a);
  Vec a, alpha;
  EXPECT_EQ(at_a->Evaluate(a, alpha), ErrorCode::kNoAcceleration);
  ASSERT_TRUE(g.RemovePose("c", "a"));  // the pose chain from c to the point a and [a]
  EXPECT_EQ(at_a->Evaluate(a, alpha), ErrorCode::kQueryInvalidated);
  // Two edges: the first without an acceleration, the second removed.
  SceneGraph<TypeParam> h;
  ASSERT_TRUE(h.AddTwist(TwistSpec::Of("b", "B").RelativeTo("A").ExpressedIn("b"), Vec::Zero(),
                         Vec(0, 0, 1)));
  ASSERT_TRUE(h.AddTwist(TwistSpec::Of("c", "C").RelativeTo("B").ExpressedIn("c"), Vec::Zero(),
                         Vec(0, 0, 1), AccelerationInput{Vec::Zero(), Vec::Zero()}));
  ASSERT_TRUE(h.AddPose(PoseSpec::Of("c", "C").RelativeTo("b", "B"), Eigen::Quaterniond::Identity(),
                        Vec(1, 0, 0)));
  auto chain = h.CompileAcceleration(TwistSpec::Of("c", "C").RelativeTo("A").ExpressedIn("c"));
  ASSERT_TRUE(chain);
  EXPECT_EQ(chain->Evaluate(a, alpha), ErrorCode::kNoAcceleration);
  ASSERT_TRUE(h.RemoveTwist("c", "B"));
  EXPECT_EQ(chain->Evaluate(a, alpha), ErrorCode::kQueryInvalidated);
}

// The query at the edge's own head in its own frame answers the record exactly (Z = d: no pose
// edge, identity rotation and shift). The writer stores records whose words all derive from one
// k (a = (k, k, k), alpha = (k, -k, 2k)), each after a twist that clears the record; the reader
// gets kOk with one record's words, or kNoAcceleration between the two stores.
TYPED_TEST(CompiledAccelerations, AConcurrentWriterNeverTearsARecord) {
  SceneGraph<TypeParam> g;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("d", "Disc").RelativeTo("w", "G"),
                        Eigen::Quaterniond::Identity(), Vec(1, 2, 3)));
  ASSERT_TRUE(g.AddTwist(TwistSpec::Of("d", "Disc").RelativeTo("G").ExpressedIn("d"), Vec::Zero(),
                         Vec(0, 0, 1), AccelerationInput{Vec::Zero(), Vec::Zero()}));
  auto compiled =
      g.CompileAcceleration(TwistSpec::Of("d", "Disc").RelativeTo("G").ExpressedIn("d"));
  ASSERT_TRUE(compiled);
  auto h = g.FindTwistEdge("d", "G");
  ASSERT_TRUE(h);
  std::atomic<bool> done{false};
  int torn = 0, ok = 0, other = 0;
  std::thread reader([&] {
    const auto read = [&] {
      Vec a, alpha;
      const ErrorCode code = compiled->Evaluate(a, alpha);
      if (code == ErrorCode::kOk) {
        ++ok;
        const double k = a.x();
        torn += (a != Vec(k, k, k) || alpha != Vec(k, -k, 2 * k)) ? 1 : 0;
      } else if (code != ErrorCode::kNoAcceleration) {
        ++other;
      }
    };
    while (!done.load(std::memory_order_acquire)) read();
    read();  // after the last store: a whole record
  });
  int refused = 0;  // counted, not asserted: the reader must be joined
  for (int k = 1; k <= 200000; ++k) {
    const double x = k;
    refused += g.SetTwist(*h, Vec(x, x, x), Vec(0, 0, x)) != ErrorCode::kOk ? 1 : 0;
    refused += g.SetAcceleration(*h, Vec(x, x, x), Vec(x, -x, 2 * x)) != ErrorCode::kOk ? 1 : 0;
  }
  done.store(true, std::memory_order_release);
  reader.join();
  EXPECT_EQ(refused, 0);
  EXPECT_EQ(torn, 0);
  EXPECT_EQ(other, 0);
  EXPECT_GE(ok, 1);
}

}  // namespace
}  // namespace semgraph::core
