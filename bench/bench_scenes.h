// File: bench/bench_scenes.h
//
// Scenes, poses and kernels shared by semgraph_bench (Google Benchmark, wall time) and
// semgraph_icount (callgrind instruction counts), so that both time exactly the same work.
//
// Random numbers: one std::mt19937_64 per purpose with a fixed seed, mapped to doubles by hand
// (53 high bits), so the values do not depend on the standard library's distributions. Each
// link has a uniformly random rotation (Shoemake) with near-identity rotations rejected
// (|qw| < 0.99, as in the peer benchmarks) and a translation in [-1, 1]^3.
//
// Scenes:
//   chain of depth d     frames f0 <- f1 <- ... <- fd, frame fi on its own body Li; link i
//                        (1-based) is the pose of fi in f(i-1). The links of every depth are a
//                        prefix of one 64-link sequence.
//   chain extras         a second frame p0 on L0 (same-body edge from f0) and pd on Ld (from
//                        fd), the point / reference point of the "changes" query; the
//                        coordinate frame of that query is the mid-chain frame f((d+1)/2).
//   twist chain (k)      the chain of depth k plus twist edges L(i) -> {f(i+1)}, i = 0..k-1.
//   random tree (N)      frames t0 (root) .. tN, frame ti on its own body bi; the parent of ti
//                        is uniform among t0 .. t(i-1).
//
// Every set-up is verified against a hand-written reference (tolerance 1e-9) and aborts on a
// mismatch or on an unexpected error code.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "semgraph/core/compiled_query.h"
#include "semgraph/core/scene_graph.h"

#ifdef SEMGRAPH_HAVE_TF2
#include "tf2_peer.h"  // tf2 lives in a C++17 translation unit (ROS 1 messages do not build as C++20)
#endif

namespace semgraph_bench {

using semgraph::core::CompiledPose;
using semgraph::core::CompiledTwist;
using semgraph::core::ErrorCode;
using semgraph::core::PoseCache;
using semgraph::core::PoseHandle;
using semgraph::core::PoseSpec;
using semgraph::core::SceneGraph;
using semgraph::core::TwistSpec;
using QuatB = semgraph::coord::QuaternionBackend;
using HomB = semgraph::coord::HomogeneousBackend;

inline constexpr int kMaxDepth = 64;
inline constexpr std::uint64_t kChainSeed = 20261121;
inline constexpr std::uint64_t kTreeSeed = 1000003;
inline constexpr double kTolerance = 1e-9;

[[noreturn]] inline void Fail(const std::string& what) {
  std::fprintf(stderr, "bench set-up check failed: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

// ------------------------------------------------------------------ random numbers

/// Uniform in [0, 1): the 53 high bits of one draw.
inline double Unit(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
}
inline double Symmetric(std::mt19937_64& rng) { return 2.0 * Unit(rng) - 1.0; }
/// Uniform integer in [0, n): floor(Unit * n).
inline std::uint32_t Below(std::mt19937_64& rng, std::uint32_t n) {
  const auto k = static_cast<std::uint32_t>(Unit(rng) * n);
  return k < n ? k : n - 1;
}

/// Uniform random rotation (Shoemake 1992), rejecting |w| >= 0.99 (angle below about 16 deg).
inline Eigen::Quaterniond RandomRotation(std::mt19937_64& rng) {
  constexpr double kTwoPi = 6.283185307179586476925286766559;
  for (;;) {
    const double u1 = Unit(rng), u2 = Unit(rng), u3 = Unit(rng);
    const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
    Eigen::Quaterniond q(b * std::cos(kTwoPi * u3),   // w
                         a * std::sin(kTwoPi * u2),   // x
                         a * std::cos(kTwoPi * u2),   // y
                         b * std::sin(kTwoPi * u3));  // z
    if (std::abs(q.w()) < 0.99) return q.normalized();
  }
}
inline Eigen::Vector3d RandomTranslation(std::mt19937_64& rng) {
  const double x = Symmetric(rng), y = Symmetric(rng), z = Symmetric(rng);
  return {x, y, z};
}

struct Link {
  Eigen::Quaterniond q;  ///< rotation of the child in the parent
  Eigen::Vector3d p;     ///< position of the child's origin in the parent, in [parent]
};

inline Link RandomLink(std::mt19937_64& rng) {
  Link l;
  l.q = RandomRotation(rng);
  l.p = RandomTranslation(rng);
  return l;
}

/// Links 1..64 of every chain (index 0 = link f0 <- f1), plus the extras' poses.
struct ChainPoses {
  std::vector<Link> links;                        // kMaxDepth
  Link p0_in_f0, pd_in_fd;                        // the extra frames of the "changes" scene
  std::vector<Eigen::Vector3d> twist_v, twist_w;  // per twist edge, in [head]
};

inline const ChainPoses& Poses() {
  static const ChainPoses poses = [] {
    ChainPoses c;
    std::mt19937_64 rng(kChainSeed);
    for (int i = 0; i < kMaxDepth; ++i) c.links.push_back(RandomLink(rng));
    c.p0_in_f0 = RandomLink(rng);
    c.pd_in_fd = RandomLink(rng);
    for (int i = 0; i < kMaxDepth; ++i) {
      c.twist_v.push_back(RandomTranslation(rng));
      c.twist_w.push_back(RandomTranslation(rng));
    }
    return c;
  }();
  return poses;
}

inline std::string FrameName(int i) { return "f" + std::to_string(i); }
inline std::string BodyName(int i) { return "L" + std::to_string(i); }

// ------------------------------------------------------------------ raw kernels (the limits)

/// The peer benchmark's eigen_quat_chain kernel: p = p + q*p_i; q = q*q_i; normalize at the end.
struct QuatPose {
  Eigen::Quaterniond q;
  Eigen::Vector3d p;
};
inline QuatPose RawQuatChain(const Link* links, int d) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = 0; i < d; ++i) {
    p = p + q * links[i].p;
    q = q * links[i].q;
  }
  q.normalize();
  return {q, p};
}

/// The peer benchmark's eigen_iso_chain kernel: r = r * T_i.
inline Eigen::Isometry3d RawIsoChain(const Eigen::Isometry3d* T, int d) {
  Eigen::Isometry3d r = Eigen::Isometry3d::Identity();
  for (int i = 0; i < d; ++i) r = r * T[i];
  return r;
}

inline std::vector<Eigen::Isometry3d> IsoLinks() {
  std::vector<Eigen::Isometry3d> T;
  for (const Link& l : Poses().links) {
    Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
    x.linear() = l.q.toRotationMatrix();
    x.translation() = l.p;
    T.push_back(x);
  }
  return T;
}

// ------------------------------------------------------------------ checks

inline double RotationDistance(const Eigen::Matrix3d& A, const Eigen::Matrix3d& B) {
  return (A - B).cwiseAbs().maxCoeff();
}
inline void CheckPose(const char* what, int d, const Eigen::Matrix3d& R, const Eigen::Vector3d& p,
                      const Eigen::Matrix3d& R_ref, const Eigen::Vector3d& p_ref) {
  const double dr = RotationDistance(R, R_ref), dp = (p - p_ref).cwiseAbs().maxCoeff();
  if (!(dr <= kTolerance && dp <= kTolerance)) {
    char buf[256];
    std::snprintf(buf, sizeof(buf), "%s at d=%d differs from the reference: |dR|=%g |dp|=%g", what,
                  d, dr, dp);
    Fail(buf);
  }
}
inline void CheckVector(const char* what, int d, const Eigen::Vector3d& v,
                        const Eigen::Vector3d& ref) {
  const double dv = (v - ref).cwiseAbs().maxCoeff();
  if (!(dv <= kTolerance)) {
    char buf[256];
    std::snprintf(buf, sizeof(buf), "%s at d=%d differs from the reference: |d|=%g", what, d, dv);
    Fail(buf);
  }
}
inline void CheckOk(const semgraph::core::BuildResult& r, const char* what) {
  if (!r) Fail(std::string(what) + ": " + r.error().message);
}

inline Eigen::Matrix3d ToMatrix(const QuatB::PoseCoords& X) {
  return X.rotation.toRotationMatrix();
}
inline Eigen::Matrix3d ToMatrix(const HomB::PoseCoords& X) { return X.linear(); }
inline Eigen::Vector3d Translation(const QuatB::PoseCoords& X) { return X.translation; }
inline Eigen::Vector3d Translation(const HomB::PoseCoords& X) { return X.translation(); }

// ------------------------------------------------------------------ chain scenes

/// A chain f0 <- ... <- fd on bodies L0..Ld, optionally with the extras p0/pd and k twist edges.
/// Lives on the heap and never moves (compiled queries point into the graph).
template <class B>
struct ChainScene {
  int d = 0;
  SceneGraph<B> graph;
  std::vector<std::string> frames, bodies;  // f0..fd, L0..Ld
  std::string p0 = "p0", pd = "pd", mid;    // extras; mid = f((d+1)/2)

  ChainScene(int depth, bool extras, int twist_edges) : d(depth) {
    const ChainPoses& poses = Poses();
    for (int i = 0; i <= d; ++i) {
      frames.push_back(FrameName(i));
      bodies.push_back(BodyName(i));
    }
    mid = frames[static_cast<std::size_t>((d + 1) / 2)];
    for (int i = 1; i <= d; ++i) {
      const Link& l = poses.links[static_cast<std::size_t>(i - 1)];
      CheckOk(
          graph.AddPose(PoseSpec::Of(frames[i], bodies[i]).RelativeTo(frames[i - 1], bodies[i - 1]),
                        l.q, l.p),
          "chain AddPose");
    }
    if (extras) {
      CheckOk(graph.AddPose(PoseSpec::Of(p0, bodies[0]).RelativeTo(frames[0], bodies[0]),
                            poses.p0_in_f0.q, poses.p0_in_f0.p),
              "extra p0");
      CheckOk(graph.AddPose(PoseSpec::Of(pd, bodies[d]).RelativeTo(frames[d], bodies[d]),
                            poses.pd_in_fd.q, poses.pd_in_fd.p),
              "extra pd");
    }
    for (int i = 0; i < twist_edges; ++i) {
      CheckOk(graph.AddTwist(
                  TwistSpec::Of(frames[i + 1]).RelativeTo(bodies[i]).ExpressedIn(frames[i + 1]),
                  poses.twist_v[i], poses.twist_w[i]),
              "chain AddTwist");
    }
  }

  /// fd wrt f0 (frame to frame).
  PoseSpec F2FSpec() const { return PoseSpec::Of(frames[d]).RelativeTo(frames[0]); }
  /// (pd, [fd])|Ld wrt (p0, [f0])|L0 in [mid].
  PoseSpec ChangesSpec() const {
    return PoseSpec::Of(frames[d])
        .RelativeTo(frames[0])
        .ExpressedIn(mid)
        .AtPoint(pd)
        .RelativeToPoint(p0);
  }
  /// Twist of Lk wrt L0 at the origin of fk, in [f0] (k = d).
  TwistSpec TwistQuerySpec() const {
    return TwistSpec::Of(frames[d], bodies[d]).RelativeTo(bodies[0]).ExpressedIn(frames[0]);
  }

  CompiledPose<B> CompileOrDie(const PoseSpec& spec) const {
    auto c = graph.CompilePose(spec);
    if (!c) Fail("CompilePose: " + graph.Describe(c.error(), spec));
    return std::move(c).value();
  }
};

/// Reference pose (R, p) of f_j in f_0 for j = 0..d (top-down composition).
inline void ReferenceChain(int d, std::vector<Eigen::Matrix3d>& R,
                           std::vector<Eigen::Vector3d>& p) {
  R.assign(1, Eigen::Matrix3d::Identity());
  p.assign(1, Eigen::Vector3d::Zero());
  for (int i = 0; i < d; ++i) {
    const Link& l = Poses().links[static_cast<std::size_t>(i)];
    p.push_back(p.back() + R.back() * l.p);
    R.push_back(R.back() * l.q.toRotationMatrix());
  }
}

/// Verifies the f2f compiled query and the one-shot query of a chain scene against the raw
/// kernels. Aborts on a mismatch.
template <class B>
void VerifyF2F(const ChainScene<B>& s) {
  std::vector<Eigen::Matrix3d> R;
  std::vector<Eigen::Vector3d> p;
  ReferenceChain(s.d, R, p);
  const QuatPose raw = RawQuatChain(Poses().links.data(), s.d);
  CheckPose("raw_eigen_quat_chain", s.d, raw.q.toRotationMatrix(), raw.p, R.back(), p.back());
  const auto iso = IsoLinks();
  const Eigen::Isometry3d r = RawIsoChain(iso.data(), s.d);
  CheckPose("raw_eigen_iso_chain", s.d, r.linear(), r.translation(), R.back(), p.back());
  const auto c = s.CompileOrDie(s.F2FSpec());
  typename B::PoseCoords X;
  if (c.Evaluate(X) != ErrorCode::kOk) Fail("compiled f2f Evaluate");
  CheckPose("compiled_pose_f2f", s.d, ToMatrix(X), Translation(X), R.back(), p.back());
  auto one = s.graph.GetPose(s.F2FSpec());
  if (!one) Fail("GetPose f2f: " + s.graph.Describe(one.error(), s.F2FSpec()));
  CheckPose("oneshot_by_names", s.d, ToMatrix(one->value), Translation(one->value), R.back(),
            p.back());
}

/// Verifies the changes query: position of pd wrt p0, orientation of [fd] wrt [f0], in [mid].
inline void VerifyChanges(const ChainScene<QuatB>& s) {
  std::vector<Eigen::Matrix3d> R;
  std::vector<Eigen::Vector3d> p;
  ReferenceChain(s.d, R, p);
  const Link& e = Poses().pd_in_fd;
  const Link& f = Poses().p0_in_f0;
  const int m = (s.d + 1) / 2;
  const Eigen::Matrix3d& R_0d = R.back();
  const Eigen::Matrix3d& R_0m = R[static_cast<std::size_t>(m)];
  const Eigen::Vector3d p_ref = R_0m.transpose() * (p.back() + R_0d * e.p - f.p);
  const Eigen::Matrix3d M_ref = R_0m.transpose() * R_0d * R_0m;
  const auto c = s.CompileOrDie(s.ChangesSpec());
  QuatB::PoseCoords X;
  if (c.Evaluate(X) != ErrorCode::kOk) Fail("compiled changes Evaluate");
  CheckPose("compiled_pose_changes", s.d, ToMatrix(X), X.translation, M_ref, p_ref);
  auto one = s.graph.GetPose(s.ChangesSpec());
  if (!one) Fail("GetPose changes: " + s.graph.Describe(one.error(), s.ChangesSpec()));
  CheckPose("oneshot changes", s.d, ToMatrix(one->value), one->value.translation, M_ref, p_ref);
}

/// Verifies the twist query: v of the point at fk fixed to Lk relative to L0, w, both in [f0]:
///   w = sum_i R_0(i+1) w_i,  v = sum_i [R_0(i+1) v_i + (R_0(i+1) w_i) x (p_0k - p_0(i+1))].
inline void VerifyTwist(const ChainScene<QuatB>& s) {
  std::vector<Eigen::Matrix3d> R;
  std::vector<Eigen::Vector3d> p;
  ReferenceChain(s.d, R, p);
  Eigen::Vector3d v_ref = Eigen::Vector3d::Zero(), w_ref = Eigen::Vector3d::Zero();
  for (int i = 0; i < s.d; ++i) {
    const auto h = static_cast<std::size_t>(i + 1);
    const Eigen::Vector3d w_i = R[h] * Poses().twist_w[static_cast<std::size_t>(i)];
    v_ref += R[h] * Poses().twist_v[static_cast<std::size_t>(i)] + w_i.cross(p.back() - p[h]);
    w_ref += w_i;
  }
  auto c = s.graph.CompileTwist(s.TwistQuerySpec());
  if (!c) Fail("CompileTwist: " + s.graph.Describe(c.error(), s.TwistQuerySpec()));
  if (c->num_twist_edges() != static_cast<std::size_t>(s.d))
    Fail("compiled twist: wrong number of edges");
  Eigen::Vector3d v, w;
  if (c->Evaluate(v, w) != ErrorCode::kOk) Fail("compiled twist Evaluate");
  CheckVector("compiled_twist v", s.d, v, v_ref);
  CheckVector("compiled_twist w", s.d, w, w_ref);
  auto one = s.graph.GetTwist(s.TwistQuerySpec());
  if (!one) Fail("GetTwist: " + s.graph.Describe(one.error(), s.TwistQuerySpec()));
  CheckVector("GetTwist v", s.d, one->linear, v_ref);
  CheckVector("GetTwist w", s.d, one->angular, w_ref);
}

// ------------------------------------------------------------------ random tree (build / reject)

/// The random tree t0..tN: parent[i] uniform in [0, i) for i >= 1; names and poses pregenerated.
struct RandomTree {
  std::uint32_t n = 0;                       // inserted frames t1..tN
  std::vector<std::uint32_t> parent, depth;  // index 0 = root
  std::vector<std::string> frames, bodies;   // t0..tN, b0..bN
  std::vector<Link> poses;                   // poses[i] = ti in t(parent[i]); [0] unused
};

inline std::unique_ptr<RandomTree> MakeRandomTree(std::uint32_t n) {
  auto t = std::make_unique<RandomTree>();
  t->n = n;
  std::mt19937_64 rng(kTreeSeed);
  t->parent.resize(n + 1u, 0);
  t->depth.resize(n + 1u, 0);
  t->frames.reserve(n + 1u);
  t->bodies.reserve(n + 1u);
  t->poses.resize(n + 1u);
  for (std::uint32_t i = 0; i <= n; ++i) {
    t->frames.push_back("t" + std::to_string(i));
    t->bodies.push_back("b" + std::to_string(i));
    if (i == 0) continue;
    t->parent[i] = Below(rng, i);
    t->depth[i] = t->depth[t->parent[i]] + 1;
    t->poses[i] = RandomLink(rng);
  }
  return t;
}

/// The random tree of each size, generated once per process.
inline const RandomTree& TreeOf(std::uint32_t n) {
  static std::map<std::uint32_t, std::unique_ptr<RandomTree>> cache;
  auto& slot = cache[n];
  if (!slot) slot = MakeRandomTree(n);
  return *slot;
}

/// Adds t1..tN to `g` in order (the timed part of build_random_tree).
template <class B>
inline void AddTree(SceneGraph<B>& g, const RandomTree& t) {
  g.Reserve(t.n + 1, t.n + 1);  // the size is known: no reallocation while building
  for (std::uint32_t i = 1; i <= t.n; ++i) {
    const std::uint32_t par = t.parent[i];
    auto r =
        g.AddPose(PoseSpec::Of(t.frames[i], t.bodies[i]).RelativeTo(t.frames[par], t.bodies[par]),
                  t.poses[i].q, t.poses[i].p);
    if (!r) [[unlikely]]
      Fail("AddTree: " + r.error().message);
  }
}

/// A built random tree plus the three rejected operations of reject_P1/P3/W3.
///   P1: a second parent for the deepest frame y (tail: the root t0).
///   P3: a second tree  p3r|P3B <- p3c|b_x  (x: a frame at depth >= 2 on y's root path, so its
///       body b_x is in the big tree); linking p3r under y would put b_x in one tree twice.
///   W3: twist edges b0 -> {tx}, b_x -> {ty}, and a frame w3e on b_y (same-body edge from ty);
///       the twist edge b0 -> {w3e} would give TG a second path b_y .. b0.
struct RejectScene {
  const RandomTree* tree;
  SceneGraph<QuatB> graph;
  std::uint32_t y = 0, x = 0;
  std::string p3r = "p3r", p3b = "P3B", p3c = "p3c", w3e = "w3e";
  Link pose;

  explicit RejectScene(const RandomTree& random_tree) : tree(&random_tree) {
    AddTree(graph, *tree);
    const RandomTree& t = *tree;
    y = static_cast<std::uint32_t>(std::max_element(t.depth.begin(), t.depth.end()) -
                                   t.depth.begin());
    if (t.depth[y] < 3) Fail("random tree too shallow");
    x = t.parent[y];
    std::mt19937_64 rng(kTreeSeed + 1);
    pose = RandomLink(rng);
    CheckOk(graph.AddPose(PoseSpec::Of(p3c, t.bodies[x]).RelativeTo(p3r, p3b), pose.q, pose.p),
            "P3 set-up");
    const Eigen::Vector3d v(0.1, 0.2, 0.3), w(0.3, -0.2, 0.1);
    CheckOk(graph.AddTwist(
                TwistSpec::Of(t.frames[x]).RelativeTo(t.bodies[0]).ExpressedIn(t.frames[x]), v, w),
            "W3 set-up 1");
    CheckOk(graph.AddTwist(
                TwistSpec::Of(t.frames[y]).RelativeTo(t.bodies[x]).ExpressedIn(t.frames[y]), v, w),
            "W3 set-up 2");
    CheckOk(graph.AddPose(PoseSpec::Of(w3e, t.bodies[y]).RelativeTo(t.frames[y], t.bodies[y]),
                          pose.q, pose.p),
            "W3 set-up 3");
    Expect(RejectP1(), ErrorCode::kMultiplePoseParents, "reject_P1");
    Expect(RejectP3(), ErrorCode::kDuplicatePosePath, "reject_P3");
    Expect(RejectW3(), ErrorCode::kDuplicateTwistPath, "reject_W3");
  }

  semgraph::core::BuildResult RejectP1() {
    return graph.AddPose(PoseSpec::Of(tree->frames[y]).RelativeTo(tree->frames[0]), pose.q, pose.p);
  }
  semgraph::core::BuildResult RejectP3() {
    return graph.AddPose(PoseSpec::Of(p3r).RelativeTo(tree->frames[y]), pose.q, pose.p);
  }
  semgraph::core::BuildResult RejectW3() {
    const Eigen::Vector3d v(0.1, 0.2, 0.3), w(0.3, -0.2, 0.1);
    return graph.AddTwist(TwistSpec::Of(w3e).RelativeTo(tree->bodies[0]).ExpressedIn(w3e), v, w);
  }

 private:
  static void Expect(const semgraph::core::BuildResult& r, ErrorCode code, const char* what) {
    if (r) Fail(std::string(what) + ": the add was accepted");
    if (r.error().code != code) {
      Fail(std::string(what) + ": expected " + std::string(semgraph::base::ToString(code)) +
           ", got " + r.error().message);
    }
  }
};

// ------------------------------------------------------------------ tf2

#ifdef SEMGRAPH_HAVE_TF2
inline tf2peer::Pose7 ToPose7(const Eigen::Quaterniond& q, const Eigen::Vector3d& p) {
  return {q.w(), q.x(), q.y(), q.z(), p.x(), p.y(), p.z()};
}

/// The small extra motion of a dynamic link between t = 1 s and t = 2 s: 0.05-0.3 rad about a
/// random axis, translation in [-0.1, 0.1]^3. Sample 2 = (q1*dq, p1 + dp).
inline Link ExtraMotion(std::mt19937_64& rng) {
  const double angle = 0.05 + 0.25 * Unit(rng);
  Eigen::Vector3d axis = RandomTranslation(rng);
  while (axis.norm() < 1e-3) axis = RandomTranslation(rng);
  Link l;
  l.q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
  l.p = 0.1 * RandomTranslation(rng);
  return l;
}

/// tf2 chain f0 <- ... <- fd (tf2_peer.h): static (one setTransform each, is_static = true) or
/// dynamic (samples at t = 1 s and t = 2 s per link; lookups at t = 1.5 s interpolate every
/// link). The constructor checks tf2's answer against the reference (slerp/lerp per link).
struct Tf2Chain {
  int d;
  bool dynamic;
  std::unique_ptr<tf2peer::Chain> chain;

  Tf2Chain(int depth, bool dyn) : d(depth), dynamic(dyn) {
    std::mt19937_64 rng(kChainSeed + 7);
    std::vector<tf2peer::Pose7> at1, at2;
    std::vector<Eigen::Matrix3d> R(1, Eigen::Matrix3d::Identity());
    std::vector<Eigen::Vector3d> p(1, Eigen::Vector3d::Zero());
    for (int i = 1; i <= d; ++i) {
      const Link& l = Poses().links[static_cast<std::size_t>(i - 1)];
      Link at = l;
      at1.push_back(ToPose7(l.q, l.p));
      if (dynamic) {
        const Link dm = ExtraMotion(rng);
        const Eigen::Quaterniond q2 = (l.q * dm.q).normalized();
        const Eigen::Vector3d p2 = l.p + dm.p;
        at2.push_back(ToPose7(q2, p2));
        at.q = l.q.slerp(0.5, q2);
        at.p = 0.5 * (l.p + p2);
      }
      p.push_back(p.back() + R.back() * at.p);
      R.push_back(R.back() * at.q.toRotationMatrix());
    }
    chain = std::make_unique<tf2peer::Chain>(at1, dynamic ? &at2 : nullptr);
    tf2peer::Pose7 out{};
    try {
      out = chain->Lookup();
    } catch (const std::exception& e) {
      Fail(std::string("tf2 lookupTransform: ") + e.what());
    }
    const Eigen::Quaterniond q(out.qw, out.qx, out.qy, out.qz);
    CheckPose(dynamic ? "tf2_lookup_dynamic" : "tf2_lookup_static", d, q.toRotationMatrix(),
              Eigen::Vector3d(out.x, out.y, out.z), R.back(), p.back());
  }

  /// One lookupTransform("f0", "fd", t), result sunk (the timed kernel).
  void LookupOnce() const { chain->LookupOnce(); }
};

/// The random tree as tf2 static messages, built outside the timing.
inline std::unique_ptr<tf2peer::TreeMessages> Tf2TreeMessages(const RandomTree& t) {
  std::vector<tf2peer::Pose7> poses;
  poses.reserve(t.poses.size());
  for (const Link& l : t.poses) poses.push_back(ToPose7(l.q, l.p));
  return std::make_unique<tf2peer::TreeMessages>(t.frames, t.parent, poses);
}
#endif  // SEMGRAPH_HAVE_TF2

}  // namespace semgraph_bench
