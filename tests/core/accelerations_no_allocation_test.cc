// The real-time claims of the acceleration queries (scene_graph.h "accelerations",
// accelerations.h), proven by counting the global operator new (tests/support/alloc_counter.h):
// GetAcceleration / GetLinearAcceleration / GetAngularAcceleration (along and against the twist
// edges, at a point and in a frame away from them; accepted and rejected), CompiledAcceleration::
// Evaluate, SetAcceleration, and SetTwist on an edge that carries an acceleration (which clears
// it) allocate nothing; on a stamped edge (docs/dynamics.md "Stamped accelerations"): SetTwist and
// SetAcceleration at a stamp, the timed one-shot and compiled queries. Each case is first run once
// unarmed to check that it takes the intended path, then kRepetitions times armed.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "semgraph/core/scene_graph.h"
#include "support/alloc_counter.h"

namespace semgraph::core {
namespace {

using semgraph::testing::CountAllocations;
using Vec = Eigen::Vector3d;

constexpr int kRepetitions = 100;

template <class F>
void ExpectNoAllocation(const std::string& what, ErrorCode expected, F&& run) {
  EXPECT_EQ(run(), expected) << what << " took another path than intended";
  std::size_t allocations = 0;
  {
    CountAllocations counting;
    for (int i = 0; i < kRepetitions; ++i) (void)run();
    allocations = counting.count();
  }
  EXPECT_EQ(allocations, 0u) << what;
}

template <class R>
ErrorCode CodeOf(const R& r) {
  return r ? ErrorCode::kOk : r.error().code;
}

template <class B>
class AccelerationsNoAllocation : public ::testing::Test {
 protected:
  // A chain of 8 poses w -> l1 -> ... -> l8 on bodies L1..L8, each with a twist edge and an
  // acceleration relative to the body before; a lone frame {iso}.
  void SetUp() override {
    std::string parent = "w", parent_body = "W";
    for (int i = 1; i <= 8; ++i) {
      const std::string f = "l" + std::to_string(i), b = "L" + std::to_string(i);
      ASSERT_TRUE(
          g.AddPose(PoseSpec::Of(f, b).RelativeTo(parent, parent_body),
                    Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * i, Vec(1, 2, 3).normalized())),
                    Vec(0.1 * i, -0.2, 0.3)));
      ASSERT_TRUE(g.AddTwist(TwistSpec::Of(f, b).RelativeTo(parent_body).ExpressedIn(f),
                             Vec(0.1, 0.2 * i, 0), Vec(0, 0.1, 0.3),
                             AccelerationInput{Vec(1, 0, 0.5), Vec(0.2, 0, 0.1 * i)}));
      parent = f;
      parent_body = b;
    }
    ASSERT_TRUE(g.AddBody("Iso"));
    ASSERT_TRUE(g.AddFrame("iso", "Iso"));
  }
  SceneGraph<B> g;
};
struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(AccelerationsNoAllocation, Backends, BackendName);

TYPED_TEST(AccelerationsNoAllocation, QueriesAndSetTwist) {
  auto& g = this->g;
  const TwistSpec tip = TwistSpec::Of("l3", "L8").RelativeTo("W").ExpressedIn("l5");
  const TwistSpec back = TwistSpec::Of("w", "L1").RelativeTo("L8").ExpressedIn("l8");
  ExpectNoAllocation("tip wrt base", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetAcceleration(tip)); });
  ExpectNoAllocation("against the edges", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetAcceleration(back)); });
  ExpectNoAllocation("linear", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetLinearAcceleration(tip)); });
  ExpectNoAllocation("angular", ErrorCode::kOk, [&] {
    return CodeOf(
        g.GetAngularAcceleration(TwistSpec::Of("", "L8").RelativeTo("L2").ExpressedIn("w")));
  });
  ExpectNoAllocation("no_twist_path", ErrorCode::kNoTwistPath, [&] {
    return CodeOf(
        g.GetAcceleration(TwistSpec::Of("iso", "Iso").RelativeTo("W").ExpressedIn("iso")));
  });
  ExpectNoAllocation("unknown_frame", ErrorCode::kUnknownFrame, [&] {
    return CodeOf(
        g.GetAcceleration(TwistSpec::Of("nowhere", "L8").RelativeTo("W").ExpressedIn("w")));
  });
  auto compiled = g.CompileAcceleration(tip);
  ASSERT_TRUE(compiled);
  Vec a, alpha;
  ExpectNoAllocation("compiled", ErrorCode::kOk, [&] { return compiled->Evaluate(a, alpha); });
  ExpectNoAllocation("compiled, result type", ErrorCode::kOk,
                     [&] { return CodeOf(compiled->Evaluate()); });
  auto h = g.FindTwistEdge("l5", "L4");
  ASSERT_TRUE(h);
  ExpectNoAllocation("SetAcceleration", ErrorCode::kOk,
                     [&] { return g.SetAcceleration(*h, Vec(1, 0, 0), Vec(0, 1, 0)); });
  ExpectNoAllocation("SetAcceleration, bad number", ErrorCode::kInvalidNumber,
                     [&] { return g.SetAcceleration(*h, Vec(std::nan(""), 0, 0), Vec::Zero()); });
  ExpectNoAllocation("SetTwist clearing an acceleration", ErrorCode::kOk,
                     [&] { return g.SetTwist(*h, Vec(1, 1, 1), Vec(0, 0, 1)); });
  ExpectNoAllocation("no_acceleration", ErrorCode::kNoAcceleration,
                     [&] { return CodeOf(g.GetAcceleration(tip)); });
  ExpectNoAllocation("compiled, no_acceleration", ErrorCode::kNoAcceleration,
                     [&] { return compiled->Evaluate(a, alpha); });
}

TYPED_TEST(AccelerationsNoAllocation, Stamped) {
  SceneGraph<TypeParam> g;
  ASSERT_TRUE(g.AddBody("W"));
  ASSERT_TRUE(g.AddFrame("w", "W"));
  const auto stamp = [](int k) { return Stamp::Nanoseconds(k * 1000000); };
  const TwistSpec edge = TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("a");
  for (int k = 0; k < 4; ++k) {
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("a", "A").RelativeTo("w", "W"),
                          Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * k, Vec::UnitZ())),
                          Vec(k, 0, 0), stamp(k)));
    ASSERT_TRUE(g.AddTwist(edge, Vec(1, 0, 0), Vec(0, 0, 0.1), stamp(k),
                           AccelerationInput{Vec(0, 1, 0), Vec(0, 0, 0.2)}));
  }
  auto h = g.FindTwistEdge("a", "W");
  ASSERT_TRUE(h);
  int k = 4;
  // Each repetition a new newest sample, then its acceleration.
  ExpectNoAllocation("SetTwist, then SetAcceleration at its stamp", ErrorCode::kOk, [&] {
    const Stamp s = stamp(k++);
    const ErrorCode code = g.SetTwist(*h, Vec(1, 0, 0), Vec(0, 0, 0.1), s);
    return code != ErrorCode::kOk ? code : g.SetAcceleration(*h, Vec(0, 1, 0), Vec::Zero(), s);
  });
  ExpectNoAllocation("SetAcceleration, no sample at the stamp", ErrorCode::kStampMismatch,
                     [&] { return g.SetAcceleration(*h, Vec(0, 1, 0), Vec::Zero(), stamp(-5)); });
  const TwistSpec in_w = TwistSpec::Of("a", "A").RelativeTo("W").ExpressedIn("w");
  const Stamp between = Stamp::Nanoseconds(1500000);
  ExpectNoAllocation("timed query", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetAcceleration(in_w, At{between})); });
  ExpectNoAllocation("timed query, latest common", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetAcceleration(in_w, LatestCommon{})); });
  auto compiled = g.CompileAcceleration(in_w);
  ASSERT_TRUE(compiled);
  Vec a, alpha;
  TimeReport report;
  ExpectNoAllocation("compiled, timed", ErrorCode::kOk,
                     [&] { return compiled->Evaluate(a, alpha, At{between}, report); });
}

}  // namespace
}  // namespace semgraph::core
