// The real-time claims of the wrenches (scene_graph.h "wrenches", wrenches.h), proven by
// counting the global operator new (tests/support/alloc_counter.h): one-shot wrench queries
// (one wrench, a reaction, a net wrench; accepted and rejected), CompiledWrench::Evaluate, and
// SetWrench through a handle (accepted and rejected) allocate nothing. Each case is first run
// once unarmed to check that it takes the intended path, then kRepetitions times armed.
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
class WrenchesNoAllocation : public ::testing::Test {
 protected:
  // A chain of 8 poses w -> l1 -> ... -> l8 on bodies L1..L8, wrenches on L8 by L1 and on L4
  // by L8, and a lone frame {iso}.
  void SetUp() override {
    std::string parent = "w", parent_body = "W";
    for (int i = 1; i <= 8; ++i) {
      const std::string f = "l" + std::to_string(i), b = "L" + std::to_string(i);
      ASSERT_TRUE(
          g.AddPose(PoseSpec::Of(f, b).RelativeTo(parent, parent_body),
                    Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * i, Vec(1, 2, 3).normalized())),
                    Vec(0.1 * i, -0.2, 0.3)));
      parent = f;
      parent_body = b;
    }
    ASSERT_TRUE(g.AddBody("Iso"));
    ASSERT_TRUE(g.AddFrame("iso", "Iso"));
    ASSERT_TRUE(g.AddWrench(WrenchSpec::On("L8").By("L1").At("l1").ExpressedIn("w"), Vec(1, 2, 3),
                            Vec(4, 5, 6)));
    ASSERT_TRUE(g.AddWrench(WrenchSpec::On("L4").By("L8").At("l8"), Vec(-1, 0, 2), Vec(0, 1, 0)));
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
TYPED_TEST_SUITE(WrenchesNoAllocation, Backends, BackendName);

TYPED_TEST(WrenchesNoAllocation, QueriesCompiledEvaluationAndSetWrench) {
  auto& g = this->g;
  const WrenchSpec one = WrenchSpec::On("L8").By("L1").At("w");
  const WrenchSpec reaction = WrenchSpec::On("L1").By("L8").At("l3").ExpressedIn("l5");
  const WrenchSpec net = WrenchSpec::On("L8").At("l2").ExpressedIn("w");
  ExpectNoAllocation("one wrench", ErrorCode::kOk, [&] { return CodeOf(g.GetWrench(one)); });
  ExpectNoAllocation("reaction", ErrorCode::kOk, [&] { return CodeOf(g.GetWrench(reaction)); });
  ExpectNoAllocation("net wrench", ErrorCode::kOk, [&] { return CodeOf(g.GetWrench(net)); });
  ExpectNoAllocation("no_wrench", ErrorCode::kNoWrench,
                     [&] { return CodeOf(g.GetWrench(WrenchSpec::On("L2").At("w"))); });
  ExpectNoAllocation("no_pose_path", ErrorCode::kNoPosePath,
                     [&] { return CodeOf(g.GetWrench(WrenchSpec::On("L8").At("iso"))); });
  ExpectNoAllocation("unknown_frame", ErrorCode::kUnknownFrame,
                     [&] { return CodeOf(g.GetWrench(WrenchSpec::On("L8").At("nowhere"))); });

  auto compiled = g.CompileWrench(net);
  ASSERT_TRUE(compiled);
  ASSERT_EQ(compiled->num_terms(), 2u);
  Vec f, m;
  ExpectNoAllocation("compiled", ErrorCode::kOk, [&] { return compiled->Evaluate(f, m); });
  ExpectNoAllocation("compiled, result type", ErrorCode::kOk,
                     [&] { return CodeOf(compiled->Evaluate()); });
  auto h = g.FindWrench("L8", "L1");
  ASSERT_TRUE(h);
  ExpectNoAllocation("SetWrench", ErrorCode::kOk,
                     [&] { return g.SetWrench(*h, Vec(1, 1, 1), Vec(2, 2, 2)); });
  ExpectNoAllocation("SetWrench, bad number", ErrorCode::kInvalidNumber,
                     [&] { return g.SetWrench(*h, Vec(std::nan(""), 1, 1), Vec::Zero()); });
  ASSERT_TRUE(g.RemoveWrench("L8", "L1"));
  ExpectNoAllocation("SetWrench, removed", ErrorCode::kNoWrench,
                     [&] { return g.SetWrench(*h, Vec(1, 1, 1), Vec::Zero()); });
  ExpectNoAllocation("compiled, invalidated", ErrorCode::kQueryInvalidated,
                     [&] { return compiled->Evaluate(f, m); });
}

}  // namespace
}  // namespace semgraph::core
