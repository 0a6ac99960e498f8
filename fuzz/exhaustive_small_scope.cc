// exhaustive_small_scope: EVERY operation sequence up to length kMaxLength over a small
// alphabet, on SceneGraph<QuaternionBackend> against the ReferenceModel, checked by
// Differential (support/scene_differential.h): the code of every op, Dump() unchanged by every
// rejection, CheckInvariants(), topology and stored values after every op, and after every
// sequence a full query comparison (the pose of every frame wrt every frame, and the twist of
// every body wrt every other body at every frame, one-shot and compiled).
//
// The scope: bodies A, B, C and frames {a}|A, {b}|A, {c}|B, {d}|C (two frames on A, so
// constant poses, P3 and W3 inside one body are reachable). The alphabet (50 ops):
//   pose t>h     12  the edge-form pose of {h}|body(h) wrt {t}|body(t), for every ordered pair of
//                    distinct frames (both directions), value V(t, h) (a distinct proper
//                    rotation and position per pair)
//   pose' t>h     2  a>b and b>a again with another value: constant_pose_change when the edge
//                    exists (and an ordinary add when it does not)
//   twist D>f    12  TwistCoord(f|body(f), D, [f]) for every body D and frame f (W2 when D is
//                    f's body), value W(D, f)
//   remove t>h   12  the pose edge t -> h, every ordered pair
//   untwist D>f  12  the twist edge D -> f, every pair
// Every add names the bodies of its frames, so a frame that does not exist yet is created by
// the add and attached to its body (docs/rules.md §1). Each sequence is run from two starting
// scenes: EMPTY (every node created by the adds) and DECLARED (the three bodies and four frames
// added first with AddBody/AddFrame, so the adds find unattached existing frames).
//
// Sequences: sum over k <= 4 of 50^k = 6,377,550 per start, 12,755,100 in all. Visited depth
// first; a rejected op leaves the graph unchanged (checked through Dump()), so the search goes on
// from the same objects, and after an accepted op the parent state is rebuilt by replaying its
// prefix. The full query comparison runs in the start state and after every accepted op: a
// rejected op leaves the state as it was (Dump() byte-identical and CheckInvariants() clean,
// both checked), so the comparison made when that state was reached stands for it. The other
// checks run after every op.
// Usage: exhaustive_small_scope [max_length (default 4)]. Prints the number of sequences.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "support/scene_differential.h"

namespace semgraph::fuzz {
namespace {

using Diff = Differential<coord::QuaternionBackend>;

const char* const kFrameNames[] = {"a", "b", "c", "d"};
const char* const kFrameBodies[] = {"A", "A", "B", "C"};
const char* const kBodyNames[] = {"A", "B", "C"};

struct Op {
  enum Kind { kPose, kTwist, kRemovePose, kRemoveTwist } kind;
  int x, y;         // pose / remove: tail frame x, head frame y; twist: body x, frame y
  int variant = 0;  // pose': 1
};

std::vector<Op> Alphabet() {
  std::vector<Op> ops;
  for (int t = 0; t < 4; ++t) {
    for (int h = 0; h < 4; ++h) {
      if (t != h) ops.push_back({Op::kPose, t, h});
    }
  }
  ops.push_back({Op::kPose, 0, 1, 1});
  ops.push_back({Op::kPose, 1, 0, 1});
  for (int D = 0; D < 3; ++D) {
    for (int f = 0; f < 4; ++f) ops.push_back({Op::kTwist, D, f});
  }
  for (int t = 0; t < 4; ++t) {
    for (int h = 0; h < 4; ++h) {
      if (t != h) ops.push_back({Op::kRemovePose, t, h});
    }
  }
  for (int D = 0; D < 3; ++D) {
    for (int f = 0; f < 4; ++f) ops.push_back({Op::kRemoveTwist, D, f});
  }
  return ops;
}

ErrorCode Apply(Diff& d, const Op& op) {
  const std::string x =
      op.kind == Op::kTwist || op.kind == Op::kRemoveTwist ? kBodyNames[op.x] : kFrameNames[op.x];
  const std::string y = kFrameNames[op.y];
  switch (op.kind) {
    case Op::kPose: {
      // V(t, h): a rotation about a pair-dependent axis and a pair-dependent position.
      const double s = 1 + op.x + 4 * op.y + 16 * op.variant;
      RotationInput r;
      r.q = Eigen::Quaterniond(
          Eigen::AngleAxisd(0.1 * s, Eigen::Vector3d(1.0, 0.5 * op.x, -0.3 * op.y).normalized()));
      return d.Pose(y, kFrameBodies[op.y], x, kFrameBodies[op.x], r,
                    Eigen::Vector3d(0.1 * s, -0.05 * s, 0.3));
    }
    case Op::kTwist: {
      const double s = 1 + op.x + 3 * op.y;
      return d.Twist(y, kFrameBodies[op.y], x, y, Eigen::Vector3d(0.01 * s, 0.2, -0.03 * s),
                     Eigen::Vector3d(-0.02 * s, 0.05, 0.1));
    }
    case Op::kRemovePose:
      return d.RemovePose(y, x);
    case Op::kRemoveTwist:
      return d.RemoveTwist(y, x);
  }
  return ErrorCode::kOk;
}

class Search {
 public:
  Search(bool declared, std::size_t max_length)
      : declared_(declared), max_length_(max_length), alphabet_(Alphabet()) {}

  std::size_t Run() {
    std::vector<int> seq;
    auto d = Fresh(seq);
    d->SweepQueries();
    Visit(seq, d);
    return count_;
  }

 private:
  // The state after seq, replayed. Every op of seq was fully checked when it was first reached,
  // so the replay only compares codes.
  std::unique_ptr<Diff> Fresh(const std::vector<int>& seq) {
    auto d = std::make_unique<Diff>();
    d->set_checks(false);
    if (declared_) {
      for (const char* b : kBodyNames) {
        if (d->Body(b) != ErrorCode::kOk) d->Fail("declaring body failed");
      }
      for (int f = 0; f < 4; ++f) {
        if (d->Frame(kFrameNames[f], kFrameBodies[f]) != ErrorCode::kOk)
          d->Fail("declaring frame failed");
      }
    }
    for (int i : seq) Apply(*d, alphabet_[static_cast<std::size_t>(i)]);
    d->set_checks(true);
    ++replays_;
    return d;
  }

  // d holds the state after seq (which has been counted and swept).
  void Visit(std::vector<int>& seq, std::unique_ptr<Diff>& d) {
    ++count_;
    if (seq.size() == max_length_) return;
    for (std::size_t i = 0; i < alphabet_.size(); ++i) {
      seq.push_back(static_cast<int>(i));
      const ErrorCode code = Apply(*d, alphabet_[i]);
      // A rejection left the state as it was (Differential checked Dump() and the invariants);
      // its queries were compared when that state was reached.
      if (code == ErrorCode::kOk && sweeps_enabled_ &&
          swept_.insert(std::hash<std::string>{}(Dump(d->graph()))).second) {
        d->SweepQueries();
        ++sweeps_;
      }
      accepted_ += code == ErrorCode::kOk;
      if (code == ErrorCode::kOk) {
        Visit(seq, d);
        seq.pop_back();
        d = Fresh(seq);
      } else {
        Visit(seq, d);
        d->PopTrace();
        seq.pop_back();
      }
    }
  }

  bool declared_;
  std::size_t max_length_;
  std::vector<Op> alphabet_;
  std::size_t count_ = 0;
  std::unordered_set<std::size_t> swept_;  // hashes of the Dump() of every state compared

 public:
  std::size_t accepted_ = 0, sweeps_ = 0, replays_ = 0;
  bool sweeps_enabled_ = std::getenv("NOSWEEP") == nullptr;
};

}  // namespace
}  // namespace semgraph::fuzz

// exhaustive_small_scope [LENGTH [empty|declared]]: both starts by default; one start alone
// lets two processes share the work (CI runs the two starts side by side on its two cores).
int main(int argc, char** argv) {
  const std::size_t max_length = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 4;
  const std::string_view only = argc > 2 ? argv[2] : "";
  if (argc > 3 || (argc > 2 && only != "empty" && only != "declared")) {
    std::fprintf(stderr, "usage: %s [LENGTH [empty|declared]]\n", argv[0]);
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  std::size_t total = 0;
  for (const bool declared : {false, true}) {
    if (!only.empty() && declared != (only == "declared")) continue;
    semgraph::fuzz::Search search(declared, max_length);
    const std::size_t n = search.Run();
    std::printf(
        "exhaustive_small_scope: %s start: %zu sequences (length <= %zu) agree "
        "(%zu accepted ops, %zu full query comparisons)\n",
        declared ? "declared" : "empty", n, max_length, search.accepted_, search.sweeps_);
    std::fflush(stdout);
    total += n;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("exhaustive_small_scope: %zu operation sequences checked in %.1f s\n", total,
              seconds);
  return 0;
}
