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
// value X_PF in [P]) and twist edges at their head in its frame, so nothing is converted;
// an edge's covariance (docs/uncertainty.md) likewise, as stored, when not zero; a twist
// edge's acceleration (docs/dynamics.md §7) as its own `acceleration` op right after the
// twist's, in its edge form (at the head in its frame: nothing converted).
//
// Joints: each live joint as a `joint` op (origin, axis, limits, mimic as stored), in table
// order; one creates its frames where the order of ids needs it (a joint interns [p, c, P, C]
// and creates P, C, then c, p), the others follow the edges; then one `joints` op with the
// states (accelerations only of the joints that were given one). A joint's own pose and twist edges
// are not written (they follow from its state). The generation of a slot that held removed joints
// is rebuilt (the joint is removed and added again as often); records of removed joints that no
// live joint took over are not: such a graph comes back with its live joints renumbered (in order).
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
    joint_child_.assign(g.num_frames(), false);
    joints_at_.resize(g.num_frames());
    const auto& joints = g.joint_table().joints;
    joint_done_.assign(joints.size(), false);
    for (std::uint32_t k = 0; k < joints.size(); ++k) {
      if (!joints[k].alive) continue;
      joint_child_[joints[k].child.value()] = true;
      joints_at_[joints[k].child.value()].push_back(k);
      joints_at_[joints[k].parent.value()].push_back(k);
    }
    children_.resize(g.num_frames());
    for (std::uint32_t i = 0; i < g.num_frames(); ++i) {
      const FrameIndex p = g.pose_parent(FrameIndex(i));
      if (p.is_valid() && !joint_child_[i]) children_[p.value()].push_back(FrameIndex(i));
    }
  }

  std::string Write() {
    out_ = "# A scene written by semgraph (semgraph export, semgraph::script::WriteScene): ";
    out_ += std::to_string(g_.num_bodies()) + " bodies, " + std::to_string(g_.num_frames()) +
            " frames, " + std::to_string(g_.num_pose_edges()) + " pose edges, " +
            std::to_string(g_.num_twist_edges()) + " twist edges" +
            (g_.num_wrenches() > 0 ? ", " + std::to_string(g_.num_wrenches()) + " wrenches" : "") +
            ".\n";
    out_ += "# Running it rebuilds the graph: the same names, ids, edges and values.\n";
    out_ += std::string("representation: ") + B::kName + "\nops:\n";
    if (g_.num_bodies() == 0 && g_.num_frames() == 0) {
      out_ += "  []\n";
      return out_;
    }
    CreateNodes();
    // A joint's pose and twist edges are the joint's: written as the joint, below.
    t_.ForEachPoseEdge([&](FrameIndex tail, FrameIndex head) {
      if (!pose_done_[head.value()] && !joint_child_[head.value()]) Pose(head, tail);
    });
    t_.ForEachTwistEdge([&](BodyIndex tail, FrameIndex head) {
      if (!twist_done_[head.value()] && !joint_child_[head.value()]) Twist(head, tail);
    });
    Joints();
    Wrenches();
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

  // A joint op interns [p, c, P, C], creates the bodies P, C, then the frames c, p (AddJoint).
  Effects JointEffects(const core::internal::JointRecord& j) const {
    return {
        {FrameName(j.parent), FrameName(j.child), BodyName(j.parent_body), BodyName(j.child_body)},
        {j.parent_body, j.child_body},
        {j.child, j.parent}};
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
      Covariance(g_.pose_covariance(a));
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
      Covariance(g_.twist_covariance(h));
      twist_done_[h.value()] = true;
    }
    out_ += "}\n";
    if (g_.twist_parent(h) == D) Acceleration(h, D);
  }
  // The twist edge's acceleration, if it carries one, in its edge form (at {h} in [h]: the add
  // converts nothing, so the values read back exactly); its own op, after the twist's (a twist
  // op clears it), so that it goes with a covariance too.
  void Acceleration(FrameIndex h, BodyIndex D) {
    const std::optional<coord::Acceleration> A = g_.acceleration_value(h);
    if (!A) return;
    out_ += "  - {op: acceleration, point: " + Quoted(FrameName(h)) +
            ", body: " + Quoted(BodyName(g_.body_of(h))) + ", ref_body: " + Quoted(BodyName(D)) +
            ", coord: " + Quoted(FrameName(h)) + ", linear: " + Numbers(A->linear, 3) +
            ", angular: " + Numbers(A->angular, 3) + "}\n";
  }
  // An edge's covariance as stored (edge form, linear_angular, coordinates: the defaults of a
  // script's `covariance`); none when zero (an exact value).
  void Covariance(const coord::Covariance6& S) {
    if (S.isZero(0.0)) return;
    out_ += ", covariance: [";
    for (int i = 0; i < 6; ++i) out_ += (i > 0 ? ", " : "") + Numbers(S.row(i), 6);
    out_ += "]";
  }
  // Every stored wrench in its stored form, about its storage frame s (a frame of the body acted
  // on) in [s]: the add keeps s and converts nothing, so the values read back exactly (slots
  // are renumbered in order). A stamped pair is written as its newest sample, without a stamp,
  // as the stamped edges are (their values: the newest samples).
  void Wrenches() {
    const core::internal::WrenchStore& w = g_.wrench_store();
    for (std::size_t i = 0; i < w.slots.size(); ++i) {
      const core::internal::WrenchSlot& slot = w.slots[i];
      if (!slot.live) continue;
      const core::WrenchNumbers W = w.values[i].Load();
      out_ += "  - {op: wrench, on: " + Quoted(BodyName(slot.on)) +
              ", by: " + Quoted(BodyName(slot.by)) + ", point: " + Quoted(FrameName(slot.frame)) +
              ", coord: " + Quoted(FrameName(slot.frame)) + ", force: " + Numbers(W.f_S, 3) +
              ", moment: " + Numbers(W.m_So_S, 3) + "}\n";
    }
  }
  void RemovePose(FrameIndex a, FrameIndex b) {
    out_ += "  - {op: remove, kind: pose, of: " + Quoted(FrameName(a)) +
            ", wrt: " + Quoted(FrameName(b)) + "}\n";
  }
  void RemoveTwist(FrameIndex h, BodyIndex D) {
    out_ += "  - {op: remove, kind: twist, point: " + Quoted(FrameName(h)) +
            ", ref_body: " + Quoted(BodyName(D)) + "}\n";
  }

  // Every live joint in index order (a mimic after its master), with its origin, axis and
  // limits as stored, then one `joints` op with the states of the independent movable joints
  // (a mimic's follows; a fixed joint has none). The joint's edges follow from its state.
  void Joint(std::uint32_t k) {
    const core::internal::JointTable& table = g_.joint_table();
    const core::internal::JointRecord& j = table.joints[k];
    out_ += "  - {op: joint, name: " + JsonString(table.name(j)) +
            ", type: " + std::string(core::ToString(j.type)) +
            ", parent: " + Quoted(FrameName(j.parent)) +
            ", parent_body: " + Quoted(BodyName(j.parent_body)) +
            ", child: " + Quoted(FrameName(j.child)) +
            ", child_body: " + Quoted(BodyName(j.child_body)) +
            ", position: " + Numbers(j.p_origin, 3) + ", rotation: {quaternion: ";
    const double wxyz[4] = {j.q_origin.w(), j.q_origin.x(), j.q_origin.y(), j.q_origin.z()};
    out_ += Numbers(wxyz, 4) + "}";
    if (j.movable()) out_ += ", axis: " + Numbers(j.axis, 3);
    if (j.limited()) out_ += ", lower: " + Number(j.lower) + ", upper: " + Number(j.upper);
    if (j.is_mimic()) {
      out_ += ", mimic: {joint: " + JsonString(table.name(table[j.master])) +
              ", multiplier: " + Number(j.multiplier) + ", offset: " + Number(j.offset) + "}";
    }
    out_ += "}\n";
    // A slot that held removed joints before: remove and add again as often, so that the slot's
    // generation (what its handles carry) comes back too. Every slot before k is live then, so
    // the add takes slot k again.
    // (A joint added and removed by the replay itself counts: SlotAddedAndRemoved.)
    const std::size_t op_begin = out_.rfind("  - {op: joint, ");
    const std::string op = out_.substr(op_begin);
    for (std::uint32_t n = SlotGeneration(live_slots_); n < j.generation; ++n) {
      RemovePose(j.child, j.parent);
      out_ += op;
    }
    ++live_slots_;
    joint_done_[k] = true;
  }

  // The replay's joint table: slots [0, live_slots_) hold live joints (written in table order),
  // and a joint added and removed at once leaves the next slot dead one generation further.
  std::uint32_t SlotGeneration(std::uint32_t slot) const {
    return slot < replay_generation_.size() ? replay_generation_[slot] : 0;
  }
  void SlotAddedAndRemoved() {
    if (replay_generation_.size() <= live_slots_) replay_generation_.resize(live_slots_ + 1, 0);
    ++replay_generation_[live_slots_];
  }

  void Joints() {
    const core::internal::JointTable& table = g_.joint_table();
    std::string positions, velocities, accelerations;
    for (std::uint32_t k = 0; k < table.joints.size(); ++k) {
      const core::internal::JointRecord& j = table.joints[k];
      if (!j.alive) continue;
      if (!joint_done_[k]) Joint(k);
      if (j.movable() && !j.is_mimic()) {
        positions +=
            (positions.empty() ? "" : ", ") + JsonString(table.name(j)) + ": " + Number(j.q);
        velocities +=
            (velocities.empty() ? "" : ", ") + JsonString(table.name(j)) + ": " + Number(j.qdot);
        if (j.has_qddot) {  // a joint whose qddot was never given has none (docs/dynamics.md)
          accelerations += (accelerations.empty() ? "" : ", ") + JsonString(table.name(j)) + ": " +
                           Number(j.qddot);
        }
      }
    }
    if (!positions.empty()) {
      out_ += "  - {op: joints, positions: {" + positions + "}, velocities: {" + velocities + "}" +
              (accelerations.empty() ? "" : ", accelerations: {" + accelerations + "}") + "}\n";
    }
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
    if (const FrameIndex p = g_.pose_parent(nf);
        p.is_valid() && !joint_child_[nf.value()] && Fits(PoseEffects(nf, p), c)) {
      Pose(nf, p);
      return true;
    }
    for (const FrameIndex child : children_[nf.value()]) {
      if (Fits(PoseEffects(child, nf), c)) {
        Pose(child, nf);
        return true;
      }
    }
    if (const BodyIndex D = g_.twist_parent(nf);
        D.is_valid() && !joint_child_[nf.value()] && Fits(TwistEffects(nf, D), c)) {
      Twist(nf, D);
      return true;
    }
    // A joint at the next frame; the joints before it in the table come first (their frames
    // exist: they were added before it), so that every joint keeps its index.
    const auto& joints = g_.joint_table().joints;
    const auto exists = [&](const core::internal::JointRecord& j) {
      return j.parent.value() < c.frame && j.child.value() < c.frame;  // bodies exist before frames
    };
    for (const std::uint32_t k : joints_at_[nf.value()]) {
      if (joint_done_[k]) continue;
      bool earlier_ready = true;
      for (std::uint32_t i = 0; i < k && earlier_ready; ++i) {
        earlier_ready = !joints[i].alive || joint_done_[i] || exists(joints[i]);
      }
      if (!earlier_ready || !Fits(JointEffects(joints[k]), c)) continue;
      for (std::uint32_t i = 0; i < k; ++i) {
        if (joints[i].alive && !joint_done_[i]) Joint(i);
      }
      Joint(k);
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
    // Frames made by a joint that is gone: only a joint interns its parent's name first and
    // creates its child frame first. Added and removed at once (a removed joint's record stays
    // in the table: the graph had one too).
    if (c.frame + 1 < num_frames) {
      const FrameIndex next(c.frame + 1);
      const BodyIndex P = g_.body_of(next), C = g_.body_of(nf);
      const Effects e{
          {FrameName(next), FrameName(nf), BodyName(P), BodyName(C)}, {P, C}, {nf, next}};
      if (P != C && FrameName(next) != FrameName(nf) && Fits(e, c)) {
        std::string name = "semgraph export joint";
        while (g_.joint_table().Find(name) != nullptr) name += "'";
        out_ += "  - {op: joint, name: " + JsonString(name) +
                ", type: fixed, parent: " + Quoted(FrameName(next)) +
                ", parent_body: " + Quoted(BodyName(P)) + ", child: " + Quoted(FrameName(nf)) +
                ", child_body: " + Quoted(BodyName(C)) + "}\n";
        RemovePose(nf, next);
        SlotAddedAndRemoved();
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
  std::vector<bool> pose_done_, twist_done_;           // by head frame: the edge is written
  std::vector<bool> joint_child_;                      // by frame: the head of a joint's edges
  std::vector<std::vector<std::uint32_t>> joints_at_;  // by frame: live joints with it as an end
  std::vector<bool> joint_done_;                       // by joint index: written
  std::uint32_t live_slots_ = 0;                       // joints written so far (SlotGeneration)
  std::vector<std::uint32_t> replay_generation_;
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
