// One-shot queries by name and Compile* on reader threads while a writer thread changes the
// topology (docs/realtime.md, "Topology changes while readers run"; core/src/optimistic_read.h).
// Runs under ThreadSanitizer in CI (stage_tsan, g++ and clang).
//
// Scene: body W with frame {w}. The writer adds, one after the other, frames {f<i>} of bodies
// B<i> with X_WFi = Rz(0.01 i), (i, 0.5, 0) (in closed form below); keeps a frame {m} (body M)
// whose pose wrt {w} is always X_WM, re-parenting it between {w} and the {f<i>} (RemovePose +
// AddPose of X_FiM = X_WFi^-1 X_WM); and keeps a stamped frame {s} (body S) wrt {w} whose sample
// at stamp t (seconds) is the translation (t, 0, 0), removing and re-adding that stamped edge
// now and then. Readers ask GetPose / GetPosition / GetOrientation by name (untimed, Latest,
// At), and CompilePose + Evaluate. Every answer must be either a documented error of the
// moment (unknown_frame before {f<i>} exists, no_pose_path while {m} or {s} is between its
// RemovePose and AddPose, extrapolation for a sample dropped meanwhile, and, rarely,
// query_invalidated: every attempt overlapped a change) or equal to the closed form. The
// issue's reproduction (a writer adding a frame every 64 value updates while a reader runs
// GetPose) runs clean as its own case.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"

namespace semgraph::core {
namespace {

using Eigen::AngleAxisd;
using Eigen::Isometry3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using Clock = std::chrono::steady_clock;

constexpr int kFrames = 20000;  // frames {f0} .. the writer adds at most this many

Isometry3d Make(const Quaterniond& q, const Vector3d& p) {
  Isometry3d X = Isometry3d::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = p;
  return X;
}
Isometry3d X_WF(int i) {
  return Make(Quaterniond(AngleAxisd(0.01 * i, Vector3d::UnitZ())), Vector3d(i, 0.5, 0.0));
}
const Isometry3d X_WM =
    Make(Quaterniond(AngleAxisd(0.7, Vector3d(1, 2, 3).normalized())), Vector3d(0.3, -0.2, 1.1));

bool Near(const Isometry3d& X, const Isometry3d& Y, double tol = 1e-9) {
  return (X.matrix() - Y.matrix()).cwiseAbs().maxCoeff() < tol;
}
std::string F(int i) { return "f" + std::to_string(i); }
std::string B(int i) { return "B" + std::to_string(i); }

// What the readers saw: answers checked against the closed form, documented errors, and the
// first unexpected thing (kept as text for the failure message).
struct Tally {
  std::atomic<long> checked{0}, errors{0}, busy{0}, bad{0};
  std::atomic<bool> stop{false};
  std::string first_bad;  // written once, by the thread that raised bad from 0
  void Bad(const std::string& what) {
    if (bad.fetch_add(1) == 0) first_bad = what;
  }
};

// The writer: frames, re-parenting of {m}, stamped samples of {s}, until `stop` or kFrames.
void Write(SceneGraph<>& g, Tally& tally, std::atomic<int>& frames_added) {
  int parent = -1;  // {m}'s parent: -1 = {w}, else {f<parent>}
  std::int64_t stamp_ms = 0;
  const auto add_sample = [&] {
    const Stamp t = Stamp::Nanoseconds(stamp_ms * 1'000'000);
    const Vector3d p(static_cast<double>(stamp_ms) * 1e-3, 0, 0);
    if (!g.AddPose(PoseSpec::Of("s", "S").RelativeTo("w"), Quaterniond::Identity(), p, t))
      tally.Bad("writer: stamped sample refused");
    ++stamp_ms;
  };
  for (int i = 0; i < kFrames && !tally.stop.load(); ++i) {
    const Isometry3d X = X_WF(i);
    if (!g.AddPose(PoseSpec::Of(F(i), B(i)).RelativeTo("w"), Quaterniond(X.linear()),
                   Vector3d(X.translation())))
      tally.Bad("writer: AddPose of a frame refused");
    frames_added.store(i + 1);
    add_sample();
    if (i % 4 == 0) {  // re-parent {m}: RemovePose + AddPose
      const std::string old_parent = parent < 0 ? "w" : F(parent);
      if (!g.RemovePose("m", old_parent)) tally.Bad("writer: RemovePose m refused");
      parent = parent < 0 ? i : -1;
      const Isometry3d X_PM = parent < 0 ? X_WM : X_WF(parent).inverse() * X_WM;
      if (!g.AddPose(PoseSpec::Of("m", "M").RelativeTo(parent < 0 ? "w" : F(parent)), X_PM))
        tally.Bad("writer: AddPose m refused");
    }
    if (i % 50 == 49) {  // the stamped edge removed and added again, with fresh samples
      if (!g.RemovePose("s", "w")) tally.Bad("writer: RemovePose s refused");
      add_sample();
      add_sample();
    }
    // A listener's pace, not a tight loop: readers see the topology quiet most of the time.
    std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
}

// One reader's round of queries; `known` = frames the writer had added before the round.
void ReadRound(const SceneGraph<>& g, Tally& tally, int known, unsigned& rng) {
  if (known == 0) return;
  rng = rng * 1664525u + 1013904223u;
  const int i = static_cast<int>(rng >> 8) % (known + 8);  // some not added yet
  const int j = static_cast<int>(rng >> 4) % known;
  const auto expect_error = [&](ErrorCode code, std::initializer_list<ErrorCode> allowed,
                                const char* what) {
    if (code == ErrorCode::kQueryInvalidated) {  // every attempt overlapped a change: rare
      tally.busy.fetch_add(1);
      return;
    }
    for (ErrorCode a : allowed) {
      if (code == a) {
        tally.errors.fetch_add(1);
        return;
      }
    }
    tally.Bad(std::string(what) + ": unexpected code " + std::string(ToString(code)));
  };
  // {f_i} wrt {f_j}: unknown until added; then X_FjFi.
  auto X = g.GetPose(PoseSpec::Of(F(i)).RelativeTo(F(j)));
  if (X) {
    if (!Near(X->ToIsometry(), X_WF(j).inverse() * X_WF(i))) tally.Bad("GetPose f_i wrt f_j");
    tally.checked.fetch_add(1);
  } else {
    if (i < known && X.error().code != ErrorCode::kQueryInvalidated)
      tally.Bad("GetPose of a frame added before the round failed");
    expect_error(X.error().code, {ErrorCode::kUnknownFrame}, "GetPose f_i wrt f_j");
  }
  // {m} wrt {w}: X_WM whatever its parent, or no_pose_path between the remove and the add.
  auto P = g.GetPosition(PoseSpec::Of("m").RelativeTo("w"));
  if (P) {
    if ((P->value - X_WM.translation()).norm() > 1e-9) tally.Bad("GetPosition m wrt w");
    tally.checked.fetch_add(1);
  } else {
    expect_error(P.error().code, {ErrorCode::kNoPosePath}, "GetPosition m");
  }
  auto R = g.GetOrientation(PoseSpec::Of("m").RelativeTo(F(j)));
  if (R) {
    const Eigen::Matrix3d R_FM = (X_WF(j).inverse() * X_WM).linear();
    const Eigen::Matrix3d R_got = R->value.toRotationMatrix();
    if ((R_got - R_FM).cwiseAbs().maxCoeff() > 1e-9) tally.Bad("GetOrientation m wrt f_j");
    tally.checked.fetch_add(1);
  } else {
    expect_error(R.error().code, {ErrorCode::kNoPosePath}, "GetOrientation m");
  }
  // {s} wrt {w}, Latest: the newest sample, whose translation is its stamp in seconds.
  auto S = g.GetPose(PoseSpec::Of("s").RelativeTo("w"), Latest{});
  if (S) {
    const double t = static_cast<double>(S->time.newest->nanoseconds()) * 1e-9;
    if (std::abs(S->value.ToIsometry().translation().x() - t) > 1e-9) tally.Bad("Latest s");
    tally.checked.fetch_add(1);
    // At that stamp: the same sample, or dropped meanwhile (the window: extrapolation).
    auto A = g.GetPose(PoseSpec::Of("s").RelativeTo("w"), At{*S->time.newest});
    if (A) {
      if (std::abs(A->value.ToIsometry().translation().x() - t) > 1e-9) tally.Bad("At s");
      tally.checked.fetch_add(1);
    } else {
      expect_error(A.error().code, {ErrorCode::kNoPosePath, ErrorCode::kExtrapolation}, "At s");
    }
  } else {
    expect_error(S.error().code, {ErrorCode::kNoPosePath}, "Latest s");
  }
  // Compile on the reader's thread, then evaluate: X_WFj, or invalidated (never for {f_j},
  // whose edge is never removed).
  auto C = g.CompilePose(PoseSpec::Of(F(j)).RelativeTo("w"));
  if (!C) {
    expect_error(C.error().code, {}, "CompilePose f_j");
    return;
  }
  const auto Y = C->Evaluate();
  if (!Y || !Near(Y->ToIsometry(), X_WF(j))) tally.Bad("compiled f_j wrt w");
  tally.checked.fetch_add(1);
}

TEST(ConcurrentOneShot, QueriesByNameAndCompileWhileTheWriterChangesTheTopology) {
  SceneGraph<> g;
  ASSERT_TRUE(g.AddBody("W"));
  ASSERT_TRUE(g.AddFrame("w", "W"));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("m", "M").RelativeTo("w"), X_WM));
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("s", "S").RelativeTo("w"), Quaterniond::Identity(),
                        Vector3d(-1e-3, 0, 0), Stamp::Nanoseconds(-1'000'000)));
  Tally tally;
  std::atomic<int> frames_added{0};
  std::vector<std::thread> readers;
  for (unsigned r = 0; r < 2; ++r) {
    readers.emplace_back([&, r] {
      unsigned rng = 12345u + r;
      while (!tally.stop.load()) ReadRound(g, tally, frames_added.load(), rng);
    });
  }
  std::thread writer([&] { Write(g, tally, frames_added); });
  const auto end = Clock::now() + std::chrono::seconds(2);
  while (Clock::now() < end && frames_added.load() < kFrames && tally.bad.load() == 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  tally.stop.store(true);
  writer.join();
  for (auto& t : readers) t.join();
  std::printf(
      "writer added %d frames; readers checked %ld answers, %ld documented errors, "
      "%ld kQueryInvalidated\n",
      frames_added.load(), tally.checked.load(), tally.errors.load(), tally.busy.load());
  EXPECT_EQ(tally.bad.load(), 0) << tally.first_bad;
  EXPECT_LT(tally.busy.load() * 100, tally.checked.load());
  EXPECT_GT(frames_added.load(), 50);
  EXPECT_GT(tally.checked.load(), 100);
  EXPECT_EQ(CheckInvariants(g), "");
  // After the writer: every query answers, as single-threaded.
  const int n = frames_added.load();
  auto X = g.GetPose(PoseSpec::Of(F(n - 1)).RelativeTo(F(0)));
  ASSERT_TRUE(X);
  EXPECT_TRUE(Near(X->ToIsometry(), X_WF(0).inverse() * X_WF(n - 1)));
}

// The issue's reproduction: one writer updating an edge's value and adding a frame every 64
// updates while another thread runs GetPose by name (it crashed within 5 s before).
TEST(ConcurrentOneShot, IssueReproductionFramesEvery64UpdatesWhileGetPoseRuns) {
  SceneGraph<> g;
  ASSERT_TRUE(g.AddPose(PoseSpec::Of("base", "Robot").RelativeTo("world", "World"),
                        Quaterniond::Identity(), Vector3d(1, 2, 3)));
  auto handle = g.FindPoseEdge(PoseSpec::Of("base").RelativeTo("world"));
  ASSERT_TRUE(handle);
  std::atomic<bool> stop{false};
  std::atomic<long> answers{0}, bad{0};
  std::atomic<int> added{0};
  int first_bad = 0;  // the reader's first unexpected answer
  std::thread writer([&] {
    for (long k = 0; !stop.load(); ++k) {
      // The value is always a translation along x of 1, 2 or 3: readers check that.
      const double x = 1.0 + static_cast<double>(k % 3);
      if (g.SetPose(handle->edge(), Quaterniond::Identity(), Vector3d(x, 2, 3)) != ErrorCode::kOk)
        bad.fetch_add(1);
      if (k % 64 == 63) {
        const int i = added.load();
        if (!g.AddPose(PoseSpec::Of("leaf" + std::to_string(i), "Robot").RelativeTo("base"),
                       Quaterniond::Identity(), Vector3d(0, 0, 0.1 * i)))
          bad.fetch_add(1);
        added.store(i + 1);
      }
    }
  });
  // An answer is exact, or kQueryInvalidated: the documented bound of a query that found the
  // topology changing on every attempt (core/src/optimistic_read.h); this writer changes it
  // every few microseconds, so a few may, and they must stay rare.
  std::atomic<long> busy{0};
  const auto busy_or_bad = [&](ErrorCode code, int what) {
    if (code == ErrorCode::kQueryInvalidated) {
      busy.fetch_add(1);
    } else if (bad.fetch_add(1) == 0) {
      first_bad = what + static_cast<int>(code);
    }
  };
  std::thread reader([&] {
    while (!stop.load()) {
      auto X = g.GetPose(PoseSpec::Of("base").RelativeTo("world"));
      const double x = X ? X->ToIsometry().translation().x() : 0.0;
      if (!X) {
        busy_or_bad(X.error().code, 0);
      } else if (x != 1.0 && x != 2.0 && x != 3.0) {
        busy_or_bad(ErrorCode::kOk, 0);
      }
      // A leaf added before this read: its pose wrt the world, in closed form.
      const int i = added.load() - 1;
      if (i >= 0) {
        auto P = g.GetPosition(PoseSpec::Of("leaf" + std::to_string(i)).RelativeTo("base"));
        if (!P) {
          busy_or_bad(P.error().code, 1000);
        } else if (std::abs(P->value.z() - 0.1 * i) > 1e-12) {
          busy_or_bad(ErrorCode::kOk, 1000);
        }
      }
      answers.fetch_add(1);
    }
  });
  std::this_thread::sleep_for(std::chrono::seconds(2));
  stop.store(true);
  writer.join();
  reader.join();
  std::printf(
      "reader answered %ld times (%ld kQueryInvalidated) while the writer added %d "
      "frames\n",
      answers.load(), busy.load(), added.load());
  EXPECT_EQ(bad.load(), 0) << "first (code, +1000: the leaf query): " << first_bad;
  EXPECT_LT(busy.load() * 100, answers.load());
  EXPECT_GT(answers.load(), 100);
  EXPECT_GT(added.load(), 10);
}

// Twist queries while the writer adds and removes twist edges. Scene: body W with frame {w};
// the writer adds frames {g<i>} of bodies G<i>, all at {w} (identity poses: every point and
// axes coincide, so a twist path's twists simply add), and the twist edge G<p(i)> -> {g<i>}
// (p(i) = (i - 1) / 2, a binary tree under W = G<-1>) with V_i = (v, w) = (i + 1) (1, 0, 0 |
// 0, 0, 0.01). The twist of G<i> wrt G<j> is then S(i) - S(j), S the sum of V along the path
// to W. Every 8th frame the writer removes an earlier twist edge and adds it back (the
// forest's Unlink and Link with rerooting): queries across it may meanwhile answer
// no_twist_path. Readers run GetTwist (untimed and Latest), GetLinearVelocity,
// GetAngularVelocity by name and CompileTwist + Evaluate.
int TwistParent(int i) { return i == 0 ? -1 : (i - 1) / 2; }
double TwistSum(int i) {  // the factor of (1, 0, 0 | 0, 0, 0.01) in S(i)
  double s = 0;
  for (; i >= 0; i = TwistParent(i)) s += i + 1;
  return s;
}
std::string G(int i) { return i < 0 ? "W" : "G" + std::to_string(i); }
std::string Gf(int i) { return i < 0 ? "w" : "g" + std::to_string(i); }

void WriteTwists(SceneGraph<>& g, Tally& tally, std::atomic<int>& added) {
  for (int i = 0; i < kFrames && !tally.stop.load(); ++i) {
    if (!g.AddPose(PoseSpec::Of(Gf(i), G(i)).RelativeTo("w"), Isometry3d::Identity()))
      tally.Bad("writer: AddPose g_i refused");
    const auto add_twist = [&](int e) {
      const double f = e + 1;
      const std::string point = Gf(e), ref_body = G(TwistParent(e));
      if (!g.AddTwist(TwistSpec::Of(point).RelativeTo(ref_body).ExpressedIn(point),
                      Vector3d(f, 0, 0), Vector3d(0, 0, 0.01 * f)))
        tally.Bad("writer: AddTwist refused");
    };
    add_twist(i);
    added.store(i + 1);
    if (i % 8 == 7) {  // an earlier edge out and back in: Unlink, then Link (rerooting)
      const int e = i / 2;
      if (!g.RemoveTwist(Gf(e), G(TwistParent(e)))) tally.Bad("writer: RemoveTwist refused");
      std::this_thread::sleep_for(std::chrono::microseconds(20));
      add_twist(e);
    }
    // A listener's pace (slower than the pose case's: each round here makes two or four
    // changes, and under ThreadSanitizer a change takes long enough for readers to overlap it
    // often).
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}

void ReadTwistRound(const SceneGraph<>& g, Tally& tally, int known, unsigned& rng) {
  if (known == 0) return;
  rng = rng * 1664525u + 1013904223u;
  const int i = static_cast<int>(rng >> 8) % (known + 4);      // some not added yet
  const int j = static_cast<int>(rng >> 4) % (known + 1) - 1;  // -1: W
  const double want = TwistSum(i) - (j < 0 ? 0.0 : TwistSum(j));
  const auto expect_error = [&](ErrorCode code, const char* what) {
    if (code == ErrorCode::kQueryInvalidated) {
      tally.busy.fetch_add(1);
    } else if (code == ErrorCode::kNoTwistPath ||
               (i >= known &&
                (code == ErrorCode::kUnknownFrame || code == ErrorCode::kUnknownBody))) {
      tally.errors.fetch_add(1);
    } else {
      tally.Bad(std::string(what) + ": unexpected code " + std::string(ToString(code)));
    }
  };
  const auto check = [&](const Vector3d& v, const Vector3d& w, const char* what) {
    if ((v - Vector3d(want, 0, 0)).norm() > 1e-9 || (w - Vector3d(0, 0, 0.01 * want)).norm() > 1e-9)
      tally.Bad(std::string(what) + ": wrong value");
    tally.checked.fetch_add(1);
  };
  const std::string point = Gf(i), body = G(i), ref_body = G(j);  // the specs view these
  const TwistSpec spec = TwistSpec::Of(point).RelativeTo(ref_body).ExpressedIn(point);
  const TwistSpec angular = TwistSpec::Of("", body).RelativeTo(ref_body).ExpressedIn(point);
  if (auto V = g.GetTwist(spec)) {
    check(V->linear, V->angular, "GetTwist");
  } else {
    expect_error(V.error().code, "GetTwist");
  }
  if (auto V = g.GetTwist(spec, Latest{})) {
    check(V->value.linear, V->value.angular, "GetTwist Latest");
  } else {
    expect_error(V.error().code, "GetTwist Latest");
  }
  if (auto v = g.GetLinearVelocity(spec)) {
    check(v->value, Vector3d(0, 0, 0.01 * want), "GetLinearVelocity");
  } else {
    expect_error(v.error().code, "GetLinearVelocity");
  }
  if (auto w = g.GetAngularVelocity(angular)) {
    check(Vector3d(want, 0, 0), w->value, "GetAngularVelocity");
  } else {
    expect_error(w.error().code, "GetAngularVelocity");
  }
  auto C = g.CompileTwist(spec);
  if (!C) {
    expect_error(C.error().code, "CompileTwist");
    return;
  }
  // Evaluated later: an edge of its path may have been removed (and re-added) meanwhile,
  // which a compiled query reports as invalidated.
  const auto V = C->Evaluate();
  if (V) {
    check(V->linear, V->angular, "compiled twist");
  } else if (V.error().code != ErrorCode::kQueryInvalidated) {
    tally.Bad("compiled twist: unexpected code " + std::string(ToString(V.error().code)));
  }
}

TEST(ConcurrentOneShot, TwistQueriesAndCompileTwistWhileTheWriterChangesTwistEdges) {
  SceneGraph<> g;
  ASSERT_TRUE(g.AddBody("W"));
  ASSERT_TRUE(g.AddFrame("w", "W"));
  Tally tally;
  std::atomic<int> added{0};
  std::vector<std::thread> readers;
  for (unsigned r = 0; r < 2; ++r) {
    readers.emplace_back([&, r] {
      unsigned rng = 777u + r;
      while (!tally.stop.load()) ReadTwistRound(g, tally, added.load(), rng);
    });
  }
  std::thread writer([&] { WriteTwists(g, tally, added); });
  const auto end = Clock::now() + std::chrono::seconds(2);
  while (Clock::now() < end && added.load() < kFrames && tally.bad.load() == 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  tally.stop.store(true);
  writer.join();
  for (auto& t : readers) t.join();
  std::printf(
      "writer added %d twist edges; readers checked %ld answers, %ld documented "
      "errors, %ld kQueryInvalidated\n",
      added.load(), tally.checked.load(), tally.errors.load(), tally.busy.load());
  EXPECT_EQ(tally.bad.load(), 0) << tally.first_bad;
  EXPECT_LT(tally.busy.load() * 100, tally.checked.load());
  EXPECT_GT(added.load(), 50);
  EXPECT_GT(tally.checked.load(), 100);
  EXPECT_EQ(CheckInvariants(g), "");
  // After the writer: every twist answers, as single-threaded.
  const int n = added.load();
  const std::string last = Gf(n - 1);
  auto V = g.GetTwist(TwistSpec::Of(last).RelativeTo("W").ExpressedIn(last));
  ASSERT_TRUE(V);
  EXPECT_NEAR(V->linear.x(), TwistSum(n - 1), 1e-9);
  EXPECT_NEAR(V->angular.z(), 0.01 * TwistSum(n - 1), 1e-9);
}

}  // namespace
}  // namespace semgraph::core
