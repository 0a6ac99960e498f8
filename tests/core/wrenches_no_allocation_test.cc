// The real-time claims of the wrenches (scene_graph.h "wrenches", wrenches.h), proven by
// counting the global operator new (tests/support/alloc_counter.h): one-shot wrench queries
// (one wrench, a reaction, a net wrench; accepted and rejected), CompiledWrench::Evaluate, and
// SetWrench through a handle (accepted and rejected) allocate nothing; so do the stamped ones:
// SetWrench with a stamp (in order, out of order, refused), GetWrench and the compiled
// Evaluate at a time policy. Each case is first run
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

TYPED_TEST(WrenchesNoAllocation, StampedSetWrenchAndTimedQueries) {
  auto& g = this->g;
  // A stamped pose edge l8 -> m|M (samples 0 .. 1 s) and a stamped wrench on M by L1.
  for (int i = 0; i <= 10; ++i) {
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("m", "M").RelativeTo("l8"),
                          Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * i, Vec::UnitZ())),
                          Vec(0.1 * i, 0, 0), Stamp::Nanoseconds(100'000'000LL * i)));
    ASSERT_TRUE(g.AddWrench(WrenchSpec::On("M").By("L1").At("l1"), Vec(i, 1, 0), Vec(0, 0, i),
                            Stamp::Nanoseconds(100'000'000LL * i)));
  }
  auto h = g.FindWrench("M", "L1");
  ASSERT_TRUE(h);
  std::int64_t next = 1'000'000'000;
  ExpectNoAllocation("SetWrench, stamped in order", ErrorCode::kOk, [&] {
    next += 1'000'000;
    return g.SetWrench(*h, Vec(1, 2, 3), Vec(4, 5, 6), Stamp::Nanoseconds(next));
  });
  std::int64_t back = 500'000'000;
  ExpectNoAllocation("SetWrench, stamped out of order", ErrorCode::kOk, [&] {
    back += 1'000;
    return g.SetWrench(*h, Vec(1, 2, 3), Vec(4, 5, 6), Stamp::Nanoseconds(back));
  });
  ExpectNoAllocation("SetWrench, stamp_mismatch", ErrorCode::kStampMismatch,
                     [&] { return g.SetWrench(*h, Vec(1, 2, 3), Vec(4, 5, 6)); });
  ExpectNoAllocation("SetWrench, stamp_too_old", ErrorCode::kStampTooOld, [&] {
    return g.SetWrench(*h, Vec(1, 2, 3), Vec(4, 5, 6), Stamp::Nanoseconds(-20'000'000'000LL));
  });
  const Stamp mid = Stamp::Nanoseconds(450'000'000);
  const WrenchSpec net = WrenchSpec::On("M").At("l2").ExpressedIn("w");
  ExpectNoAllocation("GetWrench at a time", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetWrench(net, At(mid))); });
  ExpectNoAllocation("GetWrench, latest common", ErrorCode::kOk,
                     [&] { return CodeOf(g.GetWrench(net, LatestCommon())); });
  ExpectNoAllocation("GetWrench, extrapolation", ErrorCode::kExtrapolation, [&] {
    return CodeOf(g.GetWrench(net, At(Stamp::Nanoseconds(-1'000'000'000))));
  });
  auto compiled = g.CompileWrench(net);
  ASSERT_TRUE(compiled);
  Vec f, m;
  TimeReport report;
  ExpectNoAllocation("compiled at a time", ErrorCode::kOk,
                     [&] { return compiled->Evaluate(f, m, At(mid), report); });
  ExpectNoAllocation("compiled, latest", ErrorCode::kOk,
                     [&] { return compiled->Evaluate(f, m, Latest(), report); });
  ExpectNoAllocation("compiled, latest common", ErrorCode::kOk,
                     [&] { return compiled->Evaluate(f, m, LatestCommon(), report); });
  auto at_m = g.CompileWrench(WrenchSpec::On("M").By("L1").At("m"));  // no pose edge read
  ASSERT_TRUE(at_m);
  ExpectNoAllocation("compiled, held within the horizon", ErrorCode::kOk, [&] {
    return at_m->Evaluate(f, m, At(Stamp::Nanoseconds(-1'000'000), Duration::Seconds(1)), report);
  });
  ExpectNoAllocation("compiled, stale", ErrorCode::kStale, [&] {
    return compiled->Evaluate(f, m, Latest(Stamp::Nanoseconds(50'000'000'000LL)), report);
  });
}

}  // namespace
}  // namespace semgraph::core
