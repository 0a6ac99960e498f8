// Scene export: a graph written back as a scene script that rebuilds it. Contract:
// WriteScene in semgraph/script/scene_script.h.
//
// How the ids come out the same. A graph numbers its names, bodies and frames in the order it
// created them, and the script ops create them in fixed orders (add.cc): `body X` interns X and
// creates the body; `frame f` (on an existing body) interns f and creates the frame; a pose op
// in edge form interns the new names among [a, C, b, D] in that order, then creates the new
// bodies C, D and then the new frames a, b; a twist op interns [h, H, D] and creates H, D, then
// the frame h. The writer replays the three sequences (names, bodies, frames) from the start:
// at each step it creates, by `body` / `frame` ops, everything whose name already exists, and
// otherwise looks for one op whose effects are exactly the next names, bodies and frames:
//   1. `body` / `frame` for the next body / frame, when the next name is its name;
//   2. one of the graph's own edges at the next frame (its pose edge from its parent, a pose
//      edge to a child, its twist edge), written with its value and not repeated later;
//   3. else an edge made only to create the nodes and removed at once: a pose edge from the
//      first frame, a twist edge from an existing body, or one between the next two frames.
// A frame whose name was interned before its body's (a pose op that created both) needs 2 or 3:
// no `frame` op can intern a frame's name before its body exists. Any set of the graph's edges
// obeys the rules (a part of a forest is a forest, and so on), so the remaining edges follow in
// index order. Should no op fit (a graph not built through its public calls), the nodes are
// written in index order and only the names' order may differ.
//
// Numbers: %.17g, so each double reads back to itself; rotations as the backend stores them (a
// quaternion for the quaternion backend, else the matrix), which validation keeps bit for bit
// (coord/validate.h: normalizing is idempotent). Pose edges are written in edge form (the stored
// value X_PF in [P]) and twist edges at their head in its frame, so nothing is converted.
//
// Cost: O((names + frames + edges) * k) with k the number of children of a frame looked at, plus
// the text. Thread safety: reads the graph only.
#include <cstdio>
#include <type_traits>
#include <vector>

#include "semgraph/script/scene_script.h"
#include "semgraph/script_runner.h"

namespace semgraph::script {

namespace {

using core::BodyIndex;
using core::FrameIndex;
using semantics::NameId;

std::string Number(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", x);
  return buffer;
}

template <class V>
std::string Numbers(const V& v, int n) {
  std::string s = "[";
  for (int i = 0; i < n; ++i) {
    if (i > 0) s += ", ";
    s += Number(v[i]);
  }
  return s + "]";
}

// Where the replay stands: names [0, name), bodies [0, body) and frames [0, frame) exist.
struct Cursor {
  std::uint32_t name = 0, body = 0, frame = 0;
};

// What one op would intern and create, in the graph's order (add.cc).
struct Effects {
  std::vector<NameId> names;
  std::vector<BodyIndex> bodies;
  std::vector<FrameIndex> frames;
};

template <coord::Backend B>
class Writer {
 public:
  explicit Writer(const core::SceneGraph<B>& g) : g_(g), t_(g.topology()) {
    pose_done_.assign(g.num_frames(), false);
    twist_done_.assign(g.num_frames(), false);
    children_.resize(g.num_frames());
    for (std::uint32_t i = 0; i < g.num_frames(); ++i) {
      const FrameIndex p = g.pose_parent(FrameIndex(i));
      if (p.is_valid()) children_[p.value()].push_back(FrameIndex(i));
    }
  }

  std::string Write() {
    out_ = "# A scene written by semgraph (semgraph export, semgraph::script::WriteScene): ";
    out_ += std::to_string(g_.num_bodies()) + " bodies, " + std::to_string(g_.num_frames()) +
            " frames, " + std::to_string(g_.num_pose_edges()) + " pose edges, " +
            std::to_string(g_.num_twist_edges()) + " twist edges.\n";
    out_ += "# Running it rebuilds the graph: the same names, ids, edges and values.\n";
    out_ += std::string("representation: ") + B::kName + "\nops:\n";
    if (g_.num_bodies() == 0 && g_.num_frames() == 0) {
      out_ += "  []\n";
      return out_;
    }
    CreateNodes();
    t_.ForEachPoseEdge([&](FrameIndex tail, FrameIndex head) {
      if (!pose_done_[head.value()]) Pose(head, tail);
    });
    t_.ForEachTwistEdge([&](BodyIndex tail, FrameIndex head) {
      if (!twist_done_[head.value()]) Twist(head, tail);
    });
    return out_;
  }

 private:
  NameId BodyName(BodyIndex b) const { return t_.body_name_id(b); }
  NameId FrameName(FrameIndex f) const { return t_.frame_name_id(f); }
  std::string Quoted(NameId id) const { return JsonString(g_.names().name(id)); }

  // ------------------------------------------------------------------ the effects of ops
  Effects PoseEffects(FrameIndex a, FrameIndex b) const {
    const BodyIndex C = g_.body_of(a), D = g_.body_of(b);
    return {{FrameName(a), BodyName(C), FrameName(b), BodyName(D)}, {C, D}, {a, b}};
  }
  Effects TwistEffects(FrameIndex h, BodyIndex D) const {
    const BodyIndex H = g_.body_of(h);
    return {{FrameName(h), BodyName(H), BodyName(D)}, {H, D}, {h}};
  }

  // Applies `e` to `c` if every name, body and frame it would make new is the next one (and
  // every frame's body exists by then); false, with `c` unchanged, otherwise.
  bool Fits(const Effects& e, Cursor& c) const {
    Cursor n = c;
    for (const NameId id : e.names) {
      if (id.value() < n.name) continue;
      if (id.value() != n.name) return false;
      ++n.name;
    }
    for (const BodyIndex b : e.bodies) {
      if (b.value() < n.body) continue;
      if (b.value() != n.body || BodyName(b).value() >= n.name) return false;
      ++n.body;
    }
    for (const FrameIndex f : e.frames) {
      if (f.value() < n.frame) continue;
      if (f.value() != n.frame || FrameName(f).value() >= n.name ||
          g_.body_of(f).value() >= n.body) {
        return false;
      }
      ++n.frame;
    }
    c = n;
    return true;
  }

  // ------------------------------------------------------------------ writing ops
  void Body(BodyIndex b) { out_ += "  - {op: body, name: " + Quoted(BodyName(b)) + "}\n"; }
  void Frame(FrameIndex f) {
    out_ += "  - {op: frame, name: " + Quoted(FrameName(f)) +
            ", body: " + Quoted(BodyName(g_.body_of(f))) + "}\n";
  }
  // The pose edge {b} -> {a} in edge form: its stored value when it is one of the graph's
  // edges, else the identity (an edge that is removed right away).
  void Pose(FrameIndex a, FrameIndex b) {
    out_ += "  - {op: pose, of: " + Quoted(FrameName(a)) +
            ", body: " + Quoted(BodyName(g_.body_of(a))) + ", wrt: " + Quoted(FrameName(b)) +
            ", ref_body: " + Quoted(BodyName(g_.body_of(b)));
    if (g_.pose_parent(a) == b) {
      const auto X = g_.pose_value(a);
      out_ += ", position: " + Numbers(B::TranslationOf(X), 3) + ", rotation: ";
      const auto R = B::RotationOf(X);
      if constexpr (std::is_same_v<typename B::Rotation, Eigen::Quaterniond>) {
        const double wxyz[4] = {R.w(), R.x(), R.y(), R.z()};
        out_ += "{quaternion: " + Numbers(wxyz, 4) + "}";
      } else {
        const Eigen::Matrix3d M = B::ToMatrix(R);
        out_ += "{matrix: [" + Numbers(M.row(0), 3) + ", " + Numbers(M.row(1), 3) + ", " +
                Numbers(M.row(2), 3) + "]}";
      }
      pose_done_[a.value()] = true;
    }
    out_ += "}\n";
  }
  // The twist edge D -> {h} as the screw twist at {h} in [h] (the stored form).
  void Twist(FrameIndex h, BodyIndex D) {
    out_ += "  - {op: twist, point: " + Quoted(FrameName(h)) +
            ", body: " + Quoted(BodyName(g_.body_of(h))) + ", ref_body: " + Quoted(BodyName(D)) +
            ", coord: " + Quoted(FrameName(h));
    if (g_.twist_parent(h) == D) {
      const std::optional<coord::Twist> V = g_.twist_value(h);
      out_ += ", linear: " + Numbers(V->linear, 3) + ", angular: " + Numbers(V->angular, 3);
      twist_done_[h.value()] = true;
    }
    out_ += "}\n";
  }
  void RemovePose(FrameIndex a, FrameIndex b) {
    out_ += "  - {op: remove, kind: pose, of: " + Quoted(FrameName(a)) +
            ", wrt: " + Quoted(FrameName(b)) + "}\n";
  }
  void RemoveTwist(FrameIndex h, BodyIndex D) {
    out_ += "  - {op: remove, kind: twist, point: " + Quoted(FrameName(h)) +
            ", ref_body: " + Quoted(BodyName(D)) + "}\n";
  }

  // ------------------------------------------------------------------ the replay
  void CreateNodes() {
    const std::uint32_t num_bodies = static_cast<std::uint32_t>(g_.num_bodies());
    const std::uint32_t num_frames = static_cast<std::uint32_t>(g_.num_frames());
    Cursor c;
    while (c.body < num_bodies || c.frame < num_frames) {
      // Whatever needs no new name, in index order.
      bool more = true;
      while (more) {
        more = false;
        while (c.body < num_bodies && BodyName(BodyIndex(c.body)).value() < c.name) {
          Body(BodyIndex(c.body++));
          more = true;
        }
        while (c.frame < num_frames && FrameName(FrameIndex(c.frame)).value() < c.name &&
               g_.body_of(FrameIndex(c.frame)).value() < c.body) {
          Frame(FrameIndex(c.frame++));
          more = true;
        }
      }
      if (c.body == num_bodies && c.frame == num_frames) break;
      if (!Step(c)) Fallback(c);
    }
  }

  // One op that makes the next name(s) and node(s) exactly; false if none fits.
  bool Step(Cursor& c) {
    const std::uint32_t num_bodies = static_cast<std::uint32_t>(g_.num_bodies());
    const std::uint32_t num_frames = static_cast<std::uint32_t>(g_.num_frames());
    const BodyIndex nb(c.body);
    const FrameIndex nf(c.frame);
    if (c.body < num_bodies && Fits({{BodyName(nb)}, {nb}, {}}, c)) {
      Body(nb);
      return true;
    }
    if (c.frame >= num_frames) return false;
    if (g_.body_of(nf).value() < c.body && Fits({{FrameName(nf)}, {}, {nf}}, c)) {
      Frame(nf);
      return true;
    }
    // The graph's own edges at the next frame.
    if (const FrameIndex p = g_.pose_parent(nf); p.is_valid() && Fits(PoseEffects(nf, p), c)) {
      Pose(nf, p);
      return true;
    }
    for (const FrameIndex child : children_[nf.value()]) {
      if (Fits(PoseEffects(child, nf), c)) {
        Pose(child, nf);
        return true;
      }
    }
    if (const BodyIndex D = g_.twist_parent(nf); D.is_valid() && Fits(TwistEffects(nf, D), c)) {
      Twist(nf, D);
      return true;
    }
    // An edge that only creates the nodes, removed at once.
    if (c.frame > 0 && Fits(PoseEffects(nf, FrameIndex(0)), c)) {
      Pose(nf, FrameIndex(0));
      RemovePose(nf, FrameIndex(0));
      return true;
    }
    for (std::uint32_t d = 0; d < c.body && d < 2; ++d) {  // an existing body other than nf's
      if (BodyIndex(d) != g_.body_of(nf) && Fits(TwistEffects(nf, BodyIndex(d)), c)) {
        Twist(nf, BodyIndex(d));
        RemoveTwist(nf, BodyIndex(d));
        return true;
      }
    }
    if (c.frame + 1 < num_frames) {
      const FrameIndex next(c.frame + 1);
      if (FrameName(next) != FrameName(nf) && Fits(PoseEffects(nf, next), c)) {
        Pose(nf, next);
        RemovePose(nf, next);
        return true;
      }
    }
    if (c.body + 1 < num_bodies) {
      const BodyIndex next(c.body + 1);
      if (next != g_.body_of(nf) && Fits(TwistEffects(nf, next), c)) {
        Twist(nf, next);
        RemoveTwist(nf, next);
        return true;
      }
    }
    return false;
  }

  // Not reachable through the public calls (see the top): the next node by index, its name
  // out of turn.
  void Fallback(Cursor& c) {
    const auto skip_to = [&](NameId id) { c.name = std::max(c.name, id.value() + 1); };
    if (c.frame < g_.num_frames() && g_.body_of(FrameIndex(c.frame)).value() < c.body) {
      skip_to(FrameName(FrameIndex(c.frame)));
      Frame(FrameIndex(c.frame++));
    } else {
      skip_to(BodyName(BodyIndex(c.body)));
      Body(BodyIndex(c.body++));
    }
  }

  const core::SceneGraph<B>& g_;
  const topology::SceneTopology& t_;
  std::vector<bool> pose_done_, twist_done_;  // by head frame: the edge is written
  std::vector<std::vector<FrameIndex>> children_;
  std::string out_;
};

}  // namespace

template <coord::Backend B>
std::string WriteScene(const core::SceneGraph<B>& graph) {
  return Writer<B>(graph).Write();
}

template std::string WriteScene(const core::SceneGraph<coord::QuaternionBackend>&);
template std::string WriteScene(const core::SceneGraph<coord::HomogeneousBackend>&);

}  // namespace semgraph::script
