// Stamped wrenches (scene_graph.h "wrenches", wrenches.h, docs/dynamics.md "Stamped wrenches"):
// samples of a pair interpolated linearly in the stored form, a stamped value converted with the
// poses at its stamp, queries under the time policies, the stamp rules with the graph unchanged,
// compiled queries at a policy, removal and reuse of a history.
//
// Ground truth, by hand:
//   the pose of {c}|C wrt {w}|W is the ScrewMotion of time_motions.h (a one-parameter subgroup:
//   screw interpolation between samples is exact), X(t) = (R(t), p(t)), sampled at 0, 0.1, .. 1;
//   {d}|D is fixed at (0, 2, 0) in [w].
//   an analytic wrench on C by D, given about c in [c] (the storage frame: no conversion),
//   f(t) = (1 + t, 2 t^2, -3), m(t) = (sin t, 0, t), sampled at the same stamps: between two
//   samples the graph answers the linear interpolation of the two samples (not f(t)).
//   Moving a wrench (f, m about q) to the point o: m_o = m_q + (q - o) x f (all in one frame);
//   rotating it from [c] to [w]: f_W = R f_C, m_W = R m_C.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "support/tolerance.h"
#include "time_motions.h"

namespace semgraph::core {
namespace {

using semgraph::testing::ExpectNear;
using Vec = Eigen::Vector3d;
using namespace time_motions;  // S, ScrewMotion

Vec F(double t) { return {1 + t, 2 * t * t, -3}; }
Vec M(double t) { return {std::sin(t), 0, t}; }

// The linear interpolation of samples at t0 < t < t1, written out.
Vec Lerp(const Vec& a0, const Vec& a1, double t0, double t1, double t) {
  const double l = (t - t0) / (t1 - t0);
  return a0 * (1 - l) + a1 * l;
}

template <class R>
ErrorCode CodeOf(const R& r) {
  return r ? ErrorCode::kOk : r.error().code;
}

template <class B>
class WrenchesTime : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(g.AddBody("W"));
    ASSERT_TRUE(g.AddFrame("w", "W"));
    for (int i = 0; i <= 10; ++i) {
      const double t = 0.1 * i;
      ASSERT_TRUE(
          g.AddPose(PoseSpec::Of("c", "C").RelativeTo("w"), motion.q(t), motion.p(t), S(t)));
    }
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("d", "D").RelativeTo("w"), Eigen::Quaterniond::Identity(),
                          Vec(0, 2, 0)));
    ASSERT_TRUE(g.AddPose(PoseSpec::Of("e", "E").RelativeTo("w"), Eigen::Quaterniond::Identity(),
                          Vec(-1, 0, 0)));
  }
  // The analytic wrench on C by D, sampled at 0, 0.1, .. 1 about c in [c].
  void AddAnalyticWrench() {
    for (int i = 0; i <= 10; ++i) {
      const double t = 0.1 * i;
      ASSERT_TRUE(g.AddWrench(WrenchSpec::On("C").By("D").At("c"), F(t), M(t), S(t)));
    }
  }
  Timed<coord::Wrench> Get(const WrenchSpec& spec, const TimePolicy& policy) {
    auto r = g.GetWrench(spec, policy);
    if (!r) {
      ADD_FAILURE() << g.Describe(r.error(), spec);
      return {};
    }
    return *r;
  }
  // Samples of the pair and its newest stamp (the history's state), for "graph unchanged".
  std::string History(std::string_view on, std::string_view by) {
    auto h = g.FindWrench(on, by);
    if (!h) return "none";
    const WrenchHistory* hist = g.wrench_store().history.of(h->slot);
    if (!hist) return "timeless";
    return std::to_string(hist->size()) + " " + std::to_string(hist->oldest_stamp()) + " " +
           std::to_string(hist->newest_stamp());
  }
  ScrewMotion motion;
  SceneGraph<B> g;
};
struct BackendName {
  template <class B>
  static std::string GetName(int) {
    return B::kName;
  }
};
using Backends = ::testing::Types<coord::QuaternionBackend, coord::HomogeneousBackend>;
TYPED_TEST_SUITE(WrenchesTime, Backends, BackendName);

TYPED_TEST(WrenchesTime, InterpolatesLinearlyBetweenSamplesInTheStoredForm) {
  this->AddAnalyticWrench();
  const auto spec = WrenchSpec::On("C").By("D").At("c");
  // Between samples 0.3 and 0.4: the samples' linear interpolation.
  const auto W = this->Get(spec, At(S(0.35)));
  ExpectNear(W.value.force, Lerp(F(0.3), F(0.4), 0.3, 0.4, 0.35), 1e-12);
  ExpectNear(W.value.moment, Lerp(M(0.3), M(0.4), 0.3, 0.4, 0.35), 1e-12);
  EXPECT_NEAR(W.value.force.y(), 0.25, 1e-12);  // 2 (0.09 + 0.16) / 2, not 2 * 0.35^2
  EXPECT_EQ(W.time.time, S(0.35));
  EXPECT_EQ(W.time.oldest, S(0.3));
  EXPECT_EQ(W.time.newest, S(0.4));
  EXPECT_FALSE(W.time.extrapolated);
  // At a stamp: that sample.
  const auto W7 = this->Get(spec, At(S(0.7)));
  ExpectNear(W7.value.force, F(0.7), 1e-12);
  ExpectNear(W7.value.moment, M(0.7), 1e-12);
  // The same wrench about w in [w], moved with the pose at the query's time.
  const double t = 0.62;
  const Vec f_C = Lerp(F(0.6), F(0.7), 0.6, 0.7, t), m_C = Lerp(M(0.6), M(0.7), 0.6, 0.7, t);
  const Eigen::Matrix3d R = this->motion.q(t).toRotationMatrix();
  const Vec p = this->motion.p(t);  // c's origin in [w]
  const Vec f_W = R * f_C, m_W = R * m_C + (p - Vec::Zero()).cross(f_W);
  const auto Ww = this->Get(WrenchSpec::On("C").By("D").At("w"), At(S(t)));
  ExpectNear(Ww.value.force, f_W, 1e-9);
  ExpectNear(Ww.value.moment, m_W, 1e-9);
  // The reaction (on D by C) about d in [w]: negated, moved to d = (0, 2, 0).
  const auto Wr = this->Get(WrenchSpec::On("D").By("C").At("d").ExpressedIn("w"), At(S(t)));
  ExpectNear(Wr.value.force, -f_W, 1e-9);
  ExpectNear(Wr.value.moment, -(m_W + (Vec::Zero() - Vec(0, 2, 0)).cross(f_W)), 1e-9);
}

TYPED_TEST(WrenchesTime, StampedValueIsConvertedAtItsStampAndMovedAtTheQueryTime) {
  // A constant world wrench: (0, 0, -10) with moment (1, 0, 0) about w in [w], given at each
  // stamp; stored about c in [c] with the pose at that stamp: f_C = R^T f, m_C = R^T (m - p x f).
  const Vec f(0, 0, -10), m(1, 0, 0);
  for (int i = 0; i <= 10; ++i) {
    ASSERT_TRUE(this->g.AddWrench(WrenchSpec::On("C").By("D").At("w"), f, m, S(0.1 * i)));
  }
  const auto stored = [&](double s, Vec& fc, Vec& mc) {
    const Eigen::Matrix3d R = this->motion.q(s).toRotationMatrix();
    fc = R.transpose() * f;
    mc = R.transpose() * (m - this->motion.p(s).cross(f));
  };
  auto h = this->g.FindWrench("C", "D");
  ASSERT_TRUE(h);
  EXPECT_EQ(this->g.wrench_store().slots[h->slot].frame, h->frame);
  Vec f0, m0, f1, m1;
  stored(0.4, f0, m0);
  stored(0.5, f1, m1);
  const double t = 0.43;
  const Vec fc = Lerp(f0, f1, 0.4, 0.5, t), mc = Lerp(m0, m1, 0.4, 0.5, t);
  const auto Wc = this->Get(WrenchSpec::On("C").By("D").At("c"), At(S(t)));
  ExpectNear(Wc.value.force, fc, 1e-9);
  ExpectNear(Wc.value.moment, mc, 1e-9);
  // Moved to w in [w] with the pose at t (not at either sample).
  const Eigen::Matrix3d R = this->motion.q(t).toRotationMatrix();
  const Vec fw = R * fc, mw = R * mc + this->motion.p(t).cross(fw);
  const auto Ww = this->Get(WrenchSpec::On("C").By("D").At("w"), At(S(t)));
  ExpectNear(Ww.value.force, fw, 1e-9);
  ExpectNear(Ww.value.moment, mw, 1e-9);
  // At a stamp the round trip gives the world wrench back.
  const auto Wk = this->Get(WrenchSpec::On("C").By("D").At("w"), At(S(0.8)));
  ExpectNear(Wk.value.force, f, 1e-9);
  ExpectNear(Wk.value.moment, m, 1e-9);
  // A stamp where the poses have no samples: extrapolation, nothing changes.
  const std::string before = Dump(this->g), history = this->History("C", "D");
  auto r = this->g.AddWrench(WrenchSpec::On("C").By("D").At("w"), f, m, S(3));
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kExtrapolation);
  EXPECT_NE(r.error().message.find("pose of {c}"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("[0.000, 1.000] s"), std::string::npos) << r.error().message;
  EXPECT_EQ(Dump(this->g), before);
  EXPECT_EQ(this->History("C", "D"), history);
}

TYPED_TEST(WrenchesTime, Policies) {
  this->AddAnalyticWrench();
  auto& g = this->g;
  const auto spec = WrenchSpec::On("C").By("D").At("c");
  // Latest: the newest sample.
  const auto L = this->Get(spec, Latest());
  ExpectNear(L.value.force, F(1.0), 1e-12);
  EXPECT_EQ(L.time.newest, S(1.0));
  // Latest common over the wrench and the pose edges used: the pose edge of {c} stops at 0.8.
  for (int i = 11; i <= 14; ++i) {
    const double t = 0.1 * i;
    ASSERT_TRUE(g.AddWrench(WrenchSpec::On("C").By("D").At("c"), F(t), M(t), S(t)));
  }
  const auto LC = this->Get(WrenchSpec::On("C").By("D").At("w"), LatestCommon());
  EXPECT_EQ(LC.time.time, S(1.0));  // min(1.4 for the wrench, 1.0 for the pose)
  const Eigen::Matrix3d R1 = this->motion.q(1.0).toRotationMatrix();
  ExpectNear(LC.value.force, R1 * F(1.0), 1e-9);
  // Without a pose edge used, t* is the wrench's newest stamp.
  EXPECT_EQ(this->Get(spec, LatestCommon()).time.time, S(1.4));
  // Outside within the horizon: the nearest sample held.
  const auto H = this->Get(spec, At(S(1.6), Duration::Milliseconds(500)));
  ExpectNear(H.value.force, F(1.4), 1e-12);
  EXPECT_TRUE(H.time.extrapolated);
  const auto Hb = this->Get(spec, At(S(-0.1), Duration::Milliseconds(200)));
  ExpectNear(Hb.value.moment, M(0.0), 1e-12);
  EXPECT_TRUE(Hb.time.extrapolated);
  // Beyond: extrapolation naming the pair and its samples.
  auto X = g.GetWrench(spec, At(S(2.0), Duration::Milliseconds(500)));
  ASSERT_FALSE(X);
  EXPECT_EQ(X.error().code, ErrorCode::kExtrapolation);
  EXPECT_TRUE(X.error().time.wrench);
  EXPECT_EQ(X.error().time.first, S(0).nanoseconds());
  EXPECT_EQ(X.error().time.last, S(1.4).nanoseconds());
  const std::string text = g.Describe(X.error(), spec);
  EXPECT_NE(text.find("the wrench on C by D has samples in [0.000, 1.400] s; asked 2.000 s"),
            std::string::npos)
      << text;
  // A pose edge out of its samples (the wrench is inside): the pose edge is named.
  auto P = g.GetWrench(WrenchSpec::On("C").By("D").At("w"), At(S(1.2)));
  ASSERT_FALSE(P);
  EXPECT_EQ(P.error().code, ErrorCode::kExtrapolation);
  EXPECT_FALSE(P.error().time.wrench);
  EXPECT_NE(g.Describe(P.error(), spec).find("pose of {c}"), std::string::npos);
  // Stale: the newest sample older than not_before.
  auto St = g.GetWrench(spec, Latest(S(2.0)));
  ASSERT_FALSE(St);
  EXPECT_EQ(St.error().code, ErrorCode::kStale);
  EXPECT_NE(g.Describe(St.error(), spec).find("the wrench on C by D is stale"), std::string::npos)
      << g.Describe(St.error(), spec);
  EXPECT_EQ(CodeOf(g.GetWrench(spec, Latest(S(1.4)))), ErrorCode::kOk);
  // A negative horizon: invalid_number, after invalid_name.
  EXPECT_EQ(CodeOf(g.GetWrench(spec, At(S(0.5), Duration::Seconds(-1)))),
            ErrorCode::kInvalidNumber);
  EXPECT_EQ(
      CodeOf(g.GetWrench(WrenchSpec::On("C").By("D").At(""), At(S(0.5), Duration::Seconds(-1)))),
      ErrorCode::kInvalidName);
  EXPECT_EQ(CodeOf(g.GetWrench(WrenchSpec::On("C").By("Nobody").At("c"), At(S(0.5)))),
            ErrorCode::kUnknownBody);
}

TYPED_TEST(WrenchesTime, NetWrenchSumsEveryTermAtTheQueryTime) {
  this->AddAnalyticWrench();
  auto& g = this->g;
  // On E by C, stamped at 0 and 1 about e in [w]: its reaction acts on C.
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("E").By("C").At("e").ExpressedIn("w"), Vec(0, 4, 0),
                          Vec::Zero(), S(0)));
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("E").By("C").At("e").ExpressedIn("w"), Vec(0, 8, 2),
                          Vec(0, 0, 1), S(1)));
  // On C by W, timeless: 1 N along z of [w] about w (converted once with the newest poses).
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("C").By("W").At("w"), Vec(0, 0, 1), Vec::Zero()));
  const double t = 0.25;
  const Eigen::Matrix3d R = this->motion.q(t).toRotationMatrix();
  const Vec p = this->motion.p(t);
  // About w in [w], each term by hand:
  //   on C by D: the samples' interpolation in [c] about c, moved;
  const Vec f1 = R * Lerp(F(0.2), F(0.3), 0.2, 0.3, t);
  const Vec m1 = R * Lerp(M(0.2), M(0.3), 0.2, 0.3, t) + p.cross(f1);
  //   on C by E: minus the wrench on E (E is fixed: its stored form is interpolated in [e] = [w]);
  const Vec f2 = -Vec(0, 4 + 4 * t, 2 * t), m2 = -(Vec(0, 0, t) + Vec(-1, 0, 0).cross(-f2));
  //   on C by W: stored about c in [c] with the newest pose (1.0), moved with the pose at t.
  const Eigen::Matrix3d R1 = this->motion.q(1.0).toRotationMatrix();
  const Vec f3c = R1.transpose() * Vec(0, 0, 1);
  const Vec m3c = R1.transpose() * (-this->motion.p(1.0).cross(Vec(0, 0, 1)));
  const Vec f3 = R * f3c, m3 = R * m3c + p.cross(f3);
  const auto N = this->Get(WrenchSpec::On("C").At("w"), At(S(t)));
  ExpectNear(N.value.force, f1 + f2 + f3, 1e-9);
  ExpectNear(N.value.moment, m1 + m2 + m3, 1e-9);
  EXPECT_TRUE(N.value.semantics.by_several);
}

TYPED_TEST(WrenchesTime, StampRulesLeaveTheGraphUnchanged) {
  auto& g = this->g;
  this->AddAnalyticWrench();
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("E").By("D").At("e"), Vec(1, 0, 0), Vec::Zero()));
  const auto expect_rejected = [&](ErrorCode code, const WrenchSpec& spec,
                                   std::optional<Stamp> stamp, const std::string& words) {
    const std::string before = Dump(g), h1 = this->History("C", "D"), h2 = this->History("E", "D");
    auto r = g.AddWrench(spec, Vec(1, 2, 3), Vec(4, 5, 6), stamp);
    ASSERT_FALSE(r) << "accepted";
    EXPECT_EQ(r.error().code, code) << r.error().message;
    EXPECT_NE(r.error().message.find(words), std::string::npos) << r.error().message;
    EXPECT_EQ(Dump(g), before);
    EXPECT_EQ(this->History("C", "D"), h1);
    EXPECT_EQ(this->History("E", "D"), h2);
  };
  expect_rejected(ErrorCode::kStampMismatch, WrenchSpec::On("C").By("D").At("c"), std::nullopt,
                  "the wrench on C by D is stamped (samples in [0.000, 1.000] s)");
  expect_rejected(ErrorCode::kStampMismatch, WrenchSpec::On("E").By("D").At("e"), S(0.5),
                  "the wrench on E by D is timeless");
  // Duplicate wrench comes before the stamp rules.
  expect_rejected(ErrorCode::kDuplicateWrench, WrenchSpec::On("D").By("C").At("d"), S(0.5),
                  "reaction");
  // Handles: the same rules, nothing written.
  auto hc = g.FindWrench("C", "D");
  auto he = g.FindWrench("E", "D");
  ASSERT_TRUE(hc && he);
  const std::string before = Dump(g), h1 = this->History("C", "D");
  EXPECT_EQ(g.SetWrench(*hc, Vec(1, 1, 1), Vec::Zero()), ErrorCode::kStampMismatch);
  EXPECT_EQ(g.SetWrench(*he, Vec(1, 1, 1), Vec::Zero(), S(0.5)), ErrorCode::kStampMismatch);
  EXPECT_EQ(g.SetWrench(*hc, Vec(std::nan(""), 1, 1), Vec::Zero(), S(2)),
            ErrorCode::kInvalidNumber);
  EXPECT_EQ(Dump(g), before);
  EXPECT_EQ(this->History("C", "D"), h1);
  // An accepted stamped update: the newest sample, also the untimed readers' value.
  ASSERT_EQ(g.SetWrench(*hc, Vec(7, 8, 9), Vec(1, 2, 3), S(1.5)), ErrorCode::kOk);
  EXPECT_EQ(this->History("C", "D"), "12 0 1500000000");
  ExpectNear(g.GetWrench(WrenchSpec::On("C").By("D").At("c"))->force, Vec(7, 8, 9), 0);
  // Out of order: inserted, the newest value stays.
  ASSERT_EQ(g.SetWrench(*hc, Vec(0, 0, 0), Vec::Zero(), S(1.25)), ErrorCode::kOk);
  ExpectNear(this->Get(WrenchSpec::On("C").By("D").At("c"), At(S(1.25))).value.force, Vec::Zero(),
             0);
  ExpectNear(g.GetWrench(WrenchSpec::On("C").By("D").At("c"))->force, Vec(7, 8, 9), 0);
}

TEST(WrenchesTimeOptions, WindowAndDuplicatePolicyOfTheGraph) {
  TimeOptions o;
  o.window = Duration::Seconds(1);
  o.duplicate_stamp = DuplicatePolicy::kReject;
  o.sample_capacity = 4;
  auto made = SceneGraph<coord::QuaternionBackend>::Create(o);
  ASSERT_TRUE(made);
  auto& g = *made;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("c", "C").RelativeTo("w", "W"), Eigen::Quaterniond::Identity(),
                        Vec::Zero()));
  const auto spec = WrenchSpec::On("C").By("W").At("c");
  ASSERT_TRUE(g.AddWrench(spec, Vec(1, 0, 0), Vec::Zero(), S(5)));
  const std::string before = Dump(g);
  auto old = g.AddWrench(spec, Vec(1, 0, 0), Vec::Zero(), S(3.5));
  ASSERT_FALSE(old);
  EXPECT_EQ(old.error().code, ErrorCode::kStampTooOld);
  EXPECT_NE(old.error().message.find("minus the window (1.000 s)"), std::string::npos)
      << old.error().message;
  auto dup = g.AddWrench(spec, Vec(2, 0, 0), Vec::Zero(), S(5));
  ASSERT_FALSE(dup);
  EXPECT_EQ(dup.error().code, ErrorCode::kDuplicateStamp);
  EXPECT_EQ(Dump(g), before);
  EXPECT_TRUE(g.AddWrench(spec, Vec(1, 0, 0), Vec::Zero(), S(5)));  // the same value: a no-op
  // The capacity bounds the samples; the window drops the old ones.
  auto h = g.FindWrench("C", "W");
  ASSERT_TRUE(h);
  for (int i = 1; i <= 6; ++i) {
    ASSERT_EQ(g.SetWrench(*h, Vec(i, 0, 0), Vec::Zero(), S(5 + 0.1 * i)), ErrorCode::kOk);
  }
  const WrenchHistory* hist = g.wrench_store().history.of(h->slot);
  ASSERT_NE(hist, nullptr);
  EXPECT_EQ(hist->capacity(), 4u);
  EXPECT_EQ(hist->size(), 4u);
  EXPECT_EQ(hist->oldest_stamp(), S(5.3).nanoseconds());
  ASSERT_EQ(g.SetWrench(*h, Vec(9, 0, 0), Vec::Zero(), S(6.55)), ErrorCode::kOk);
  EXPECT_EQ(hist->size(), 2u);  // 5.6 and 6.55: older than 5.55 dropped
  // Removal retires the history; a new stamped pair reuses it (no new allocation).
  ASSERT_TRUE(g.RemoveWrench("C", "W"));
  EXPECT_EQ(g.wrench_store().history.retired(), 1u);
  ASSERT_TRUE(g.AddWrench(spec, Vec(3, 0, 0), Vec::Zero()));  // timeless now
  EXPECT_EQ(g.wrench_store().history.of(g.FindWrench("C", "W")->slot), nullptr);
  ASSERT_TRUE(g.RemoveWrench("C", "W"));
  ASSERT_TRUE(g.AddWrench(spec, Vec(4, 0, 0), Vec::Zero(), S(1)));
  EXPECT_EQ(g.wrench_store().history.allocated(), 1u);
  EXPECT_EQ(g.wrench_store().history.retired(), 0u);
  auto r = g.GetWrench(spec, Latest());
  ASSERT_TRUE(r);
  ExpectNear(r->value.force, Vec(4, 0, 0), 0);
  EXPECT_EQ(r->time.newest, S(1));
}

TYPED_TEST(WrenchesTime, CompiledQueryAtAPolicyAgreesWithTheOneShot) {
  this->AddAnalyticWrench();
  auto& g = this->g;
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("E").By("C").At("e").ExpressedIn("w"), Vec(0, 4, 0),
                          Vec::Zero(), S(0)));
  ASSERT_TRUE(g.AddWrench(WrenchSpec::On("E").By("C").At("e").ExpressedIn("w"), Vec(1, 4, 0),
                          Vec(0, 1, 0), S(1)));
  for (const WrenchSpec& spec : {WrenchSpec::On("C").By("D").At("w"), WrenchSpec::On("C").At("d"),
                                 WrenchSpec::On("C").At("c").ExpressedIn("w")}) {
    auto compiled = g.CompileWrench(spec);
    ASSERT_TRUE(compiled);
    for (const TimePolicy& policy :
         {TimePolicy(At(S(0.37))), TimePolicy(At(S(0.5))), TimePolicy(Latest()),
          TimePolicy(LatestCommon()), TimePolicy(At(S(1.1), Duration::Milliseconds(200)))}) {
      Vec f, m;
      TimeReport report;
      const ErrorCode code = compiled->Evaluate(f, m, policy, report);
      auto one = g.GetWrench(spec, policy);
      ASSERT_EQ(code, CodeOf(one));
      if (code != ErrorCode::kOk) continue;
      ExpectNear(f, one->value.force, 1e-12);
      ExpectNear(m, one->value.moment, 1e-12);
      EXPECT_EQ(report.time, one->time.time);
      EXPECT_EQ(report.newest, one->time.newest);
    }
    Vec f, m;
    TimeReport report;
    EXPECT_EQ(compiled->Evaluate(f, m, At(S(5)), report), ErrorCode::kExtrapolation);
    EXPECT_EQ(compiled->Evaluate(f, m, At(S(0.5), Duration::Seconds(-1)), report),
              ErrorCode::kInvalidNumber);
  }
  // Removed since compiled: invalidated, also at a policy.
  auto compiled = g.CompileWrench(WrenchSpec::On("C").At("c"));
  ASSERT_TRUE(compiled);
  ASSERT_TRUE(g.RemoveWrench("C", "D"));
  Vec f, m;
  TimeReport report;
  EXPECT_EQ(compiled->Evaluate(f, m, At(S(0.3)), report), ErrorCode::kQueryInvalidated);
}

}  // namespace
}  // namespace semgraph::core
