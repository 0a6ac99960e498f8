// SceneGraph: the constrained directed forest. Contract, invariants and costs: scene_graph.h.
// Rules and error order: spec/scene-graph.md. Monograms: X_PF pose of frame F in its parent P.
#include "semgraph/core/scene_graph.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "semgraph/core/compiled_query.h"
#include "semgraph/semantics/describe.h"

namespace semgraph::core {

using coord::Result;
using semantics::Field;
using semantics::Unexpected;

namespace {

std::string Braced(std::string_view frame, std::string_view body) {
  return "{" + std::string(frame) + "}|" + std::string(body);
}

BuildResult Reject(ErrorCode code, const std::string& what, const std::string& reason) {
  return Unexpected{BuildError{code, what + " rejected (" + std::string(semantics::ToString(code)) +
                                         "): " + reason}};
}

// Restores the name table on every early return of a build operation (atomicity).
class NameRollback {
 public:
  explicit NameRollback(semantics::NameTable& names) : names_(names), size_(names.size()) {}
  ~NameRollback() {
    if (armed_) names_.TruncateTo(size_);
  }
  void Commit() { armed_ = false; }

 private:
  semantics::NameTable& names_;
  std::size_t size_;
  bool armed_ = true;
};

std::string FormatVector(const Eigen::Vector3d& v) {
  char buf[128];
  std::snprintf(buf, sizeof(buf), "[%.9g, %.9g, %.9g]", v.x(), v.y(), v.z());
  return buf;
}

QueryError QError(ErrorCode code, Field field = Field::kPoint, NameId name = {}, NameId other = {},
                  NameId asked = {}) {
  QueryError e;
  e.asked = asked;
  e.code = code;
  e.field = field;
  e.name = name;
  e.other = other;
  return e;
}

QueryError QError(const coord::Error& detail) {
  QueryError e;
  e.code = detail.code;
  e.detail = detail;
  return e;
}

}  // namespace

// ====================================================================== nodes

template <coord::Backend B>
void SceneGraph<B>::GrowNameMaps() {
  frame_of_name_.resize(names_.size(), kNone);
  body_of_name_.resize(names_.size(), kNone);
}

template <coord::Backend B>
BodyIndex SceneGraph<B>::CreateBody(NameId name) {
  GrowNameMaps();
  const BodyIndex b(static_cast<std::uint32_t>(bodies_.size()));
  bodies_.push_back(BodyNode{name, kNone});
  body_of_name_[name.value()] = b.value();
  return b;
}

template <coord::Backend B>
FrameIndex SceneGraph<B>::CreateFrame(NameId name, BodyIndex body) {
  GrowNameMaps();
  const FrameIndex f = forest_.AddNode();
  const std::uint32_t uf = trees_.AddElement();
  SEMGRAPH_DEMAND(f.value() == frames_.size() && uf == f.value());
  frames_.push_back(FrameNode{name, body, kNone, bodies_[body.value()].first_frame});
  bodies_[body.value()].first_frame = f.value();
  X_PF_.emplace_back(B::MakePose(B::FromQuaternion(Eigen::Quaterniond::Identity()),
                                 Eigen::Vector3d::Zero()));
  frame_of_name_[name.value()] = f.value();
  return f;
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddBody(std::string_view name) {
  const std::string what = name.empty() ? std::string("body with an empty name") : "body " + std::string(name);
  if (auto ok = semantics::ValidateName(name); !ok) {
    return Reject(ErrorCode::kInvalidName, what, semantics::Describe(ok.error(), name));
  }
  if (FindBody(name).is_valid()) {
    return Reject(ErrorCode::kDuplicateBody, what, "body " + std::string(name) + " already exists");
  }
  CreateBody(*names_.Intern(name));
  return Ok{};
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddFrame(std::string_view name, std::string_view body) {
  const std::string what = "frame " + Braced(name, body);
  if (auto ok = semantics::ValidateName(name); !ok) {
    return Reject(ErrorCode::kInvalidName, what, semantics::Describe(ok.error(), name));
  }
  if (body.empty()) {
    return Reject(ErrorCode::kFrameWithoutBody, "frame {" + std::string(name) + "}",
                  "a frame must name the body it is attached to");
  }
  if (auto ok = semantics::ValidateName(body); !ok) {
    return Reject(ErrorCode::kInvalidName, what, "body: " + semantics::Describe(ok.error(), body));
  }
  if (const FrameIndex f = FindFrame(name); f.is_valid()) {
    return Reject(ErrorCode::kDuplicateFrame, what, "frame " + FrameText(f) + " already exists");
  }
  const BodyIndex b = FindBody(body);
  if (!b.is_valid()) {
    return Reject(ErrorCode::kUnknownBody, what, "body " + std::string(body) + " does not exist");
  }
  CreateFrame(*names_.Intern(name), b);
  return Ok{};
}

template <coord::Backend B>
FrameIndex SceneGraph<B>::FindFrame(std::string_view name) const noexcept {
  return FrameOfName(names_.Find(name));
}

template <coord::Backend B>
BodyIndex SceneGraph<B>::FindBody(std::string_view name) const noexcept {
  return BodyOfName(names_.Find(name));
}

template <coord::Backend B>
std::string_view SceneGraph<B>::frame_name(FrameIndex f) const noexcept {
  return names_.name(frames_[f.value()].name);
}

template <coord::Backend B>
std::string_view SceneGraph<B>::body_name(BodyIndex b) const noexcept {
  return names_.name(bodies_[b.value()].name);
}

template <coord::Backend B>
std::string SceneGraph<B>::FrameText(FrameIndex f) const {
  return Braced(frame_name(f), body_name(body_of(f)));
}

template <coord::Backend B>
std::string SceneGraph<B>::PoseText(const semantics::PoseSemantics& s) const {
  return semantics::Describe(s, names_);
}

template <coord::Backend B>
BodyIndex SceneGraph<B>::twist_parent(FrameIndex f) const noexcept {
  const std::uint32_t e = frames_[f.value()].twist_edge;
  return e == kNone ? BodyIndex() : twist_edges_[e].tail;
}

template <coord::Backend B>
std::optional<coord::Twist> SceneGraph<B>::twist_value(FrameIndex f) const noexcept {
  const std::uint32_t e = frames_[f.value()].twist_edge;
  if (e == kNone) return std::nullopt;
  return LoadTwist(twist_edges_[e]);
}

// ====================================================================== tree records

template <coord::Backend B>
auto SceneGraph<B>::RecordOf(FrameIndex f) const noexcept -> const TreeRecord* {
  const std::uint32_t* index = record_of_rep_.Find(trees_.FindConst(f.value()));
  return index ? &records_[*index] : nullptr;
}

template <coord::Backend B>
auto SceneGraph<B>::EnsureRecord(FrameIndex f) -> TreeRecord& {
  const std::uint32_t rep = trees_.Find(f.value());
  if (const std::uint32_t* index = record_of_rep_.Find(rep)) return records_[*index];
  // Only a single-frame tree has no record: its body set is {body(f)}.
  SEMGRAPH_DEMAND(forest_.is_root(f) && !forest_.first_child(f).is_valid());
  return NewRecord(rep, f);
}

template <coord::Backend B>
auto SceneGraph<B>::NewRecord(std::uint32_t rep, FrameIndex f) -> TreeRecord& {
  std::uint32_t index;
  if (!free_records_.empty()) {
    index = free_records_.back();
    free_records_.pop_back();
  } else {
    index = static_cast<std::uint32_t>(records_.size());
    records_.emplace_back();
  }
  records_[index].body_counts.Clear();
  records_[index].twists.Clear();
  records_[index].body_counts.Insert(body_of(f).value(), 1);
  record_of_rep_.Insert(rep, index);
  return records_[index];
}

template <coord::Backend B>
bool SceneGraph<B>::TreeHasBody(FrameIndex f, BodyIndex body) const noexcept {
  if (const TreeRecord* rec = RecordOf(f)) return rec->body_counts.Contains(body.value());
  return body_of(f) == body;
}

template <coord::Backend B>
BodyIndex SceneGraph<B>::SharedBody(FrameIndex t, FrameIndex h, BodyIndex allowed) const noexcept {
  const TreeRecord* rec_t = RecordOf(t);
  const TreeRecord* rec_h = RecordOf(h);
  // Iterate the smaller body set, look each body up in the other: O(min(b_t, b_h)).
  const std::size_t size_t_ = rec_t ? rec_t->body_counts.size() : 1;
  const std::size_t size_h = rec_h ? rec_h->body_counts.size() : 1;
  const FrameIndex small = size_t_ <= size_h ? t : h;
  const FrameIndex large = size_t_ <= size_h ? h : t;
  const TreeRecord* rec_small = size_t_ <= size_h ? rec_t : rec_h;
  BodyIndex found;
  if (!rec_small) {
    const BodyIndex b = body_of(small);
    if (b != allowed && TreeHasBody(large, b)) found = b;
    return found;
  }
  rec_small->body_counts.ForEach([&](std::uint32_t body, const std::uint32_t&) {
    if (found.is_valid()) return;
    const BodyIndex b(body);
    if (b != allowed && TreeHasBody(large, b)) found = b;
  });
  return found;
}

template <coord::Backend B>
FrameIndex SceneGraph<B>::SomeFrameOfBodyInTree(BodyIndex body, FrameIndex tree_member) const noexcept {
  for (std::uint32_t f = bodies_[body.value()].first_frame; f != kNone; f = frames_[f].next_in_body) {
    if (trees_.SameSet(f, tree_member.value())) return FrameIndex(f);
  }
  return FrameIndex();
}

// Rebuilds the union-find set and the record of the tree rooted at `root` after a split.
// `twist_edges` holds the twist edges of the old tree; those whose head is in this tree are
// linked into its new TG. O(|tree| + twist edges).
template <coord::Backend B>
void SceneGraph<B>::RebuildTree(FrameIndex root, std::vector<std::uint32_t>& twist_edges) {
  std::size_t count = 0;
  forest_.ForEachInSubtree(root, [&](FrameIndex f) {
    trees_.Union(root.value(), f.value());
    ++count;
  });
  bool has_twist = false;
  for (std::uint32_t e : twist_edges) {
    if (trees_.SameSet(twist_edges_[e].head.value(), root.value())) has_twist = true;
  }
  if (count == 1 && !has_twist) return;  // a single frame needs no record
  TreeRecord& rec = NewRecord(trees_.Find(root.value()), root);
  rec.body_counts.Clear();
  forest_.ForEachInSubtree(root, [&](FrameIndex f) {
    rec.body_counts.FindOrInsert(body_of(f).value(), 0) += 1;
  });
  for (std::uint32_t e : twist_edges) {
    const TwistEdge& te = twist_edges_[e];
    if (trees_.SameSet(te.head.value(), root.value())) {
      rec.twists.Link(e, te.tail.value(), body_of(te.head).value());
    }
  }
}

// ====================================================================== queries: building blocks

template <coord::Backend B>
auto SceneGraph<B>::EdgePose(FrameIndex child) const noexcept -> Pose {
  const FrameIndex parent = forest_.parent(child);
  return Pose{semantics::PoseSemantics::OfFrame(FrameSem(child), BodyOfSem(child), FrameSem(parent),
                                                BodyOfSem(parent), FrameSem(parent).axes()),
              X_PF_[child.value()].Load()};
}

template <coord::Backend B>
auto SceneGraph<B>::IdentityPose(FrameIndex f) const noexcept -> Pose {
  return Pose{semantics::PoseSemantics::OfFrame(FrameSem(f), BodyOfSem(f), FrameSem(f), BodyOfSem(f),
                                                FrameSem(f).axes()),
              B::MakePose(B::FromQuaternion(Eigen::Quaterniond::Identity()), Eigen::Vector3d::Zero())};
}

// X_AF: pose of f wrt its ancestor, in [ancestor], composed upward in natural order
// (Algorithm 3): X_AF = X_PF composed with each further edge.
//
// Every one of these compositions is semantically valid by construction: the edge into g stores
// PoseCoord({g}|G, {p}|P, [p]) and the next edge up starts at p, which is exactly the forest's
// invariant. So the hot loop composes numbers only (B::ComposeChain), and the result carries the
// semantics PoseCoord({f}|F, {A}|A, [A]). Debug and SEMGRAPH_EXPENSIVE_CHECKS builds also run
// the same path through the checked coord::Compose, edge by edge, and demand identical results,
// so the shortcut is verified wherever the tests run with checks armed.
template <coord::Backend B>
Result<typename SceneGraph<B>::Pose> SceneGraph<B>::PoseUpTo(FrameIndex f,
                                                             FrameIndex ancestor) const noexcept {
  if (f == ancestor) return IdentityPose(f);
  typename B::PoseCoords X_AF = X_PF_[f.value()].Load();
  for (FrameIndex g = forest_.parent(f); g != ancestor; g = forest_.parent(g)) {
    X_AF = B::ComposeChain(X_AF, X_PF_[g.value()].Load());
  }
  Pose X{semantics::PoseSemantics::OfFrame(FrameSem(f), BodyOfSem(f), FrameSem(ancestor),
                                           BodyOfSem(ancestor), FrameSem(ancestor).axes()),
         X_AF};
#if !defined(NDEBUG) || defined(SEMGRAPH_EXPENSIVE_CHECKS)
  Pose checked = EdgePose(f);
  for (FrameIndex g = forest_.parent(f); g != ancestor; g = forest_.parent(g)) {
    auto next = coord::Compose(checked, EdgePose(g));
    SEMGRAPH_DEMAND(next.has_value());
    checked = *next;
  }
  SEMGRAPH_DEMAND(checked.semantics == X.semantics);
#endif
  return X;
}

// Algorithm 2 in natural order: X_BA = X_CA composed with inverse(X_CB), C the youngest common
// ancestor.
template <coord::Backend B>
Result<typename SceneGraph<B>::Pose> SceneGraph<B>::BasicPose(FrameIndex a,
                                                              FrameIndex b) const noexcept {
  const FrameIndex anc = forest_.CommonAncestor(a, b);
  SEMGRAPH_DEMAND(anc.is_valid());
  auto X_CA = PoseUpTo(a, anc);
  if (!X_CA) return X_CA;
  auto X_CB = PoseUpTo(b, anc);
  if (!X_CB) return X_CB;
  auto X_BC = coord::InverseInNewRef(*X_CB);
  if (!X_BC) return Unexpected{X_BC.error()};
  return coord::Compose(*X_CA, *X_BC);
}

// ====================================================================== pose queries

template <coord::Backend B>
QueryResult<typename SceneGraph<B>::Pose> SceneGraph<B>::GetPose(
    const semantics::PoseSemantics& q) const noexcept {
  const FrameIndex e = FrameOfName(q.point.id()), a = FrameOfName(q.orientation.id());
  const FrameIndex f = FrameOfName(q.ref_point.id()), b = FrameOfName(q.ref_orientation.id());
  const FrameIndex r = FrameOfName(q.coordinate_frame.id());
  if (!e.is_valid()) return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kPoint, q.point.id())};
  if (!a.is_valid()) {
    return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kOrientation, q.orientation.id())};
  }
  if (!f.is_valid()) return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kRefPoint, q.ref_point.id())};
  if (!b.is_valid()) {
    return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kRefOrientation, q.ref_orientation.id())};
  }
  if (!r.is_valid()) {
    return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kCoordinateFrame, q.coordinate_frame.id())};
  }
  const BodyIndex C = BodyOfName(q.body.id()), D = BodyOfName(q.ref_body.id());
  if (!C.is_valid()) return Unexpected{QError(ErrorCode::kUnknownBody, Field::kBody, q.body.id())};
  if (!D.is_valid()) return Unexpected{QError(ErrorCode::kUnknownBody, Field::kRefBody, q.ref_body.id())};
  const auto mismatch = [&](FrameIndex x, BodyIndex body, Field field) {
    return body_of(x) != body ? QError(ErrorCode::kFrameBodyMismatch, field, frames_[x.value()].name,
                                       bodies_[body_of(x).value()].name, bodies_[body.value()].name)
                              : QError(ErrorCode::kOk);
  };
  for (const QueryError& m : {mismatch(e, C, Field::kPoint), mismatch(a, C, Field::kOrientation),
                              mismatch(f, D, Field::kRefPoint), mismatch(b, D, Field::kRefOrientation)}) {
    if (m.code != ErrorCode::kOk) return Unexpected{m};
  }
  const auto no_path = [&](FrameIndex x, FrameIndex y, Field field) {
    return QError(ErrorCode::kNoPosePath, field, frames_[x.value()].name, frames_[y.value()].name);
  };
  if (!trees_.SameSet(a.value(), b.value())) return Unexpected{no_path(a, b, Field::kOrientation)};
  if (!trees_.SameSet(e.value(), a.value())) return Unexpected{no_path(e, a, Field::kPoint)};
  if (!trees_.SameSet(f.value(), b.value())) return Unexpected{no_path(f, b, Field::kRefPoint)};
  if (!trees_.SameSet(r.value(), b.value())) return Unexpected{no_path(r, b, Field::kCoordinateFrame)};
  if (auto ok = coord::CheckRepresentation<B>(q); !ok) return Unexpected{QError(ok.error())};

  // Algorithm 1.
  auto X = BasicPose(a, b);  // PoseCoord({a}|C, {b}|D, [b])
  if (!X) return Unexpected{QError(X.error())};
  if (!semantics::IsOriginOf(q.ref_point, q.ref_orientation)) {
    auto X_BF = BasicPose(f, b);  // position of f wrt b, in [b]
    if (!X_BF) return Unexpected{QError(X_BF.error())};
    auto next = coord::ChangeRefPoint(*X, coord::Inverse(coord::PositionOf(*X_BF)));
    if (!next) return Unexpected{QError(next.error())};
    X = *next;
  }
  if (!semantics::IsOriginOf(q.point, q.orientation)) {
    // p(e wrt a) in [a], re-expressed in [b] with the orientation of [a] wrt [b].
    auto X_AE = BasicPose(e, a);
    if (!X_AE) return Unexpected{QError(X_AE.error())};
    auto R_BA = coord::OrientationOf(*BasicPose(a, b));
    if (!R_BA) return Unexpected{QError(R_BA.error())};
    auto p_AE_B = coord::ChangeCoordinateFrame(coord::PositionOf(*X_AE), *R_BA);
    if (!p_AE_B) return Unexpected{QError(p_AE_B.error())};
    auto next = coord::ChangePoint(*X, *p_AE_B);
    if (!next) return Unexpected{QError(next.error())};
    X = *next;
  }
  if (!(q.coordinate_frame == q.ref_orientation)) {
    auto X_RB = BasicPose(b, r);
    if (!X_RB) return Unexpected{QError(X_RB.error())};
    auto R_RB = coord::OrientationOf(*X_RB);
    if (!R_RB) return Unexpected{QError(R_RB.error())};
    auto next = coord::ChangeCoordinateFrame(*X, *R_RB);
    if (!next) return Unexpected{QError(next.error())};
    X = *next;
  }
  return *X;
}

template <coord::Backend B>
QueryResult<coord::Position> SceneGraph<B>::GetPosition(
    const semantics::PositionSemantics& q) const noexcept {
  const FrameIndex e = FrameOfName(q.point.id()), f = FrameOfName(q.ref_point.id());
  const FrameIndex r = FrameOfName(q.coordinate_frame.id());
  if (!e.is_valid()) return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kPoint, q.point.id())};
  if (!f.is_valid()) return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kRefPoint, q.ref_point.id())};
  if (!r.is_valid()) {
    return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kCoordinateFrame, q.coordinate_frame.id())};
  }
  const BodyIndex C = BodyOfName(q.body.id()), D = BodyOfName(q.ref_body.id());
  if (!C.is_valid()) return Unexpected{QError(ErrorCode::kUnknownBody, Field::kBody, q.body.id())};
  if (!D.is_valid()) return Unexpected{QError(ErrorCode::kUnknownBody, Field::kRefBody, q.ref_body.id())};
  if (body_of(e) != C) {
    return Unexpected{QError(ErrorCode::kFrameBodyMismatch, Field::kPoint, q.point.id(),
                             bodies_[body_of(e).value()].name, q.body.id())};
  }
  if (body_of(f) != D) {
    return Unexpected{QError(ErrorCode::kFrameBodyMismatch, Field::kRefPoint, q.ref_point.id(),
                             bodies_[body_of(f).value()].name, q.ref_body.id())};
  }
  if (!trees_.SameSet(e.value(), f.value())) {
    return Unexpected{QError(ErrorCode::kNoPosePath, Field::kPoint, q.point.id(), q.ref_point.id())};
  }
  if (!trees_.SameSet(r.value(), f.value())) {
    return Unexpected{QError(ErrorCode::kNoPosePath, Field::kCoordinateFrame, q.coordinate_frame.id(),
                             q.ref_point.id())};
  }
  auto X_FE = BasicPose(e, f);
  if (!X_FE) return Unexpected{QError(X_FE.error())};
  coord::Position p = coord::PositionOf(*X_FE);  // in [f]
  if (!(q.coordinate_frame == semantics::OrientationFrame(q.ref_point.id()))) {
    auto X_RF = BasicPose(f, r);
    if (!X_RF) return Unexpected{QError(X_RF.error())};
    auto R_RF = coord::OrientationOf(*X_RF);
    if (!R_RF) return Unexpected{QError(R_RF.error())};
    auto next = coord::ChangeCoordinateFrame(p, *R_RF);
    if (!next) return Unexpected{QError(next.error())};
    p = *next;
  }
  return p;
}

template <coord::Backend B>
QueryResult<typename SceneGraph<B>::Orientation> SceneGraph<B>::GetOrientation(
    const semantics::OrientationSemantics& q) const noexcept {
  const FrameIndex a = FrameOfName(q.orientation.id()), b = FrameOfName(q.ref_orientation.id());
  const FrameIndex r = FrameOfName(q.coordinate_frame.id());
  if (!a.is_valid()) {
    return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kOrientation, q.orientation.id())};
  }
  if (!b.is_valid()) {
    return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kRefOrientation, q.ref_orientation.id())};
  }
  if (!r.is_valid()) {
    return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kCoordinateFrame, q.coordinate_frame.id())};
  }
  const BodyIndex C = BodyOfName(q.body.id()), D = BodyOfName(q.ref_body.id());
  if (!C.is_valid()) return Unexpected{QError(ErrorCode::kUnknownBody, Field::kBody, q.body.id())};
  if (!D.is_valid()) return Unexpected{QError(ErrorCode::kUnknownBody, Field::kRefBody, q.ref_body.id())};
  if (body_of(a) != C) {
    return Unexpected{QError(ErrorCode::kFrameBodyMismatch, Field::kOrientation, q.orientation.id(),
                             bodies_[body_of(a).value()].name, q.body.id())};
  }
  if (body_of(b) != D) {
    return Unexpected{QError(ErrorCode::kFrameBodyMismatch, Field::kRefOrientation,
                             q.ref_orientation.id(), bodies_[body_of(b).value()].name, q.ref_body.id())};
  }
  if (!trees_.SameSet(a.value(), b.value())) {
    return Unexpected{QError(ErrorCode::kNoPosePath, Field::kOrientation, q.orientation.id(),
                             q.ref_orientation.id())};
  }
  if (!trees_.SameSet(r.value(), b.value())) {
    return Unexpected{QError(ErrorCode::kNoPosePath, Field::kCoordinateFrame, q.coordinate_frame.id(),
                             q.ref_orientation.id())};
  }
  if (auto ok = coord::CheckRepresentation<B>(q); !ok) return Unexpected{QError(ok.error())};
  auto X_BA = BasicPose(a, b);
  if (!X_BA) return Unexpected{QError(X_BA.error())};
  auto R = coord::OrientationOf(*X_BA);
  if (!R) return Unexpected{QError(R.error())};
  if (!(q.coordinate_frame == q.ref_orientation)) {
    auto X_RB = BasicPose(b, r);
    if (!X_RB) return Unexpected{QError(X_RB.error())};
    auto R_RB = coord::OrientationOf(*X_RB);
    if (!R_RB) return Unexpected{QError(R_RB.error())};
    auto next = coord::ChangeCoordinateFrame(*R, *R_RB);
    if (!next) return Unexpected{QError(next.error())};
    return *next;
  }
  return *R;
}

// ====================================================================== twist queries

// One stored twist edge, seen from body `from` (the moving body of this step), moved to point
// e and re-expressed in [r]: TwistCoord(e|from, to, [r]).
template <coord::Backend B>
Result<coord::Twist> SceneGraph<B>::EdgeTwistAt(std::uint32_t edge, std::uint32_t from_body,
                                                FrameIndex e, FrameIndex r) const noexcept {
  const TwistEdge& te = twist_edges_[edge];
  // Stored: TwistCoord(h|H, D, [h]). Traversed from H it is used as is; from D, inverted.
  const coord::Twist stored = LoadTwist(te);
  coord::Twist tw = body_of(te.head).value() == from_body ? stored : coord::Inverse(stored);
  const FrameIndex h = te.head;
  if (h != e) {
    // A = position of the old point h wrt the new point e, in [h].
    auto X_HE = BasicPose(e, h);  // e wrt h in [h]
    if (!X_HE) return Unexpected{X_HE.error()};
    auto next = coord::ChangePoint(tw, coord::Inverse(coord::PositionOf(*X_HE)));
    if (!next) return Unexpected{next.error()};
    tw = *next;
  }
  if (h != r) {
    auto X_RH = BasicPose(h, r);
    if (!X_RH) return Unexpected{X_RH.error()};
    auto R_RH = coord::OrientationOf(*X_RH);
    if (!R_RH) return Unexpected{R_RH.error()};
    auto next = coord::ChangeCoordinateFrame(tw, *R_RH);
    if (!next) return Unexpected{next.error()};
    tw = *next;
  }
  return tw;
}

// TwistCoord(e|body, ancestor, [r]): walk TG from `body` up to `ancestor`, composing in order.
template <coord::Backend B>
Result<coord::Twist> SceneGraph<B>::TwistUpTo(FrameIndex e, FrameIndex r, const TreeRecord& rec,
                                              std::uint32_t body,
                                              std::uint32_t ancestor) const noexcept {
  coord::Twist acc{{FrameSem(e).origin(), semantics::Body(bodies_[body].name),
                    semantics::Body(bodies_[body].name), FrameSem(r).axes()},
                   Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  bool first = true;
  for (std::uint32_t x = body; x != ancestor; x = rec.twists.parent(x)) {
    auto step = EdgeTwistAt(rec.twists.parent_edge(x), x, e, r);
    if (!step) return step;
    if (first) {
      acc = *step;
      first = false;
      continue;
    }
    auto next = coord::Compose(acc, *step);
    if (!next) return next;
    acc = *next;
  }
  return acc;
}

template <coord::Backend B>
QueryResult<coord::Twist> SceneGraph<B>::GetTwist(const semantics::TwistSemantics& q) const noexcept {
  const FrameIndex e = FrameOfName(q.point.id()), r = FrameOfName(q.coordinate_frame.id());
  if (!e.is_valid()) return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kPoint, q.point.id())};
  if (!r.is_valid()) {
    return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kCoordinateFrame, q.coordinate_frame.id())};
  }
  const BodyIndex C = BodyOfName(q.body.id()), D = BodyOfName(q.ref_body.id());
  if (!C.is_valid()) return Unexpected{QError(ErrorCode::kUnknownBody, Field::kBody, q.body.id())};
  if (!D.is_valid()) return Unexpected{QError(ErrorCode::kUnknownBody, Field::kRefBody, q.ref_body.id())};
  if (!trees_.SameSet(e.value(), r.value())) {
    return Unexpected{QError(ErrorCode::kNoPosePath, Field::kCoordinateFrame, q.coordinate_frame.id(),
                             q.point.id())};
  }
  const semantics::TwistSemantics s{FrameSem(e).origin(), BodySem(C), BodySem(D), FrameSem(r).axes()};
  if (C == D) return coord::Twist{s, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  const TreeRecord* rec = RecordOf(e);
  const auto no_twist = QError(ErrorCode::kNoTwistPath, Field::kBody, q.body.id(), q.ref_body.id());
  if (!rec || !rec->twists.Connected(C.value(), D.value())) return Unexpected{no_twist};
  // Youngest common ancestor of C and D in the rooted TG, by depth.
  std::uint32_t x = C.value(), y = D.value();
  while (rec->twists.depth(x) > rec->twists.depth(y)) x = rec->twists.parent(x);
  while (rec->twists.depth(y) > rec->twists.depth(x)) y = rec->twists.parent(y);
  while (x != y) {
    x = rec->twists.parent(x);
    y = rec->twists.parent(y);
  }
  // V_A_C (C wrt ancestor A) composed with the inverse of V_A_D (= A wrt D).
  auto tw_C = TwistUpTo(e, r, *rec, C.value(), x);
  if (!tw_C) return Unexpected{QError(tw_C.error())};
  auto tw_D = TwistUpTo(e, r, *rec, D.value(), x);
  if (!tw_D) return Unexpected{QError(tw_D.error())};
  if (D.value() == x) return *tw_C;
  if (C.value() == x) return coord::Inverse(*tw_D);
  auto tw = coord::Compose(*tw_C, coord::Inverse(*tw_D));
  if (!tw) return Unexpected{QError(tw.error())};
  return *tw;
}

// ====================================================================== queries by name

namespace {
// Resolves a required name to its id; kInvalidName when empty.
struct Resolved {
  bool ok = true;
  QueryError error;
};
// invalid_name for an optional body name that is given but invalid (spec §1, §4). O(|name|),
// allocation-free.
std::optional<QueryError> InvalidBodyNames(std::string_view body, std::string_view ref_body) noexcept {
  if (!body.empty() && !semantics::ValidateName(body)) return QError(ErrorCode::kInvalidName, Field::kBody);
  if (!ref_body.empty() && !semantics::ValidateName(ref_body)) {
    return QError(ErrorCode::kInvalidName, Field::kRefBody);
  }
  return std::nullopt;
}
}  // namespace

// Query names, in the spec's order: every frame name and given body name valid (invalid_name),
// then every frame known (unknown_frame). Each distinct name is hashed once: Of(x).RelativeTo(y)
// repeats names.
template <coord::Backend B>
std::optional<QueryError> SceneGraph<B>::ResolveFrameNames(std::span<const std::string_view> fields,
                                                           std::span<const Field> kinds,
                                                           std::span<NameId> ids, std::string_view body,
                                                           std::string_view ref_body) const noexcept {
  // Fast path: every name found. An interned name is valid by the table's invariant, so no name
  // needs validating unless a lookup fails; then the spec's order decides what to report.
  bool all_found = true;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    std::size_t same = i;
    for (std::size_t j = 0; j < i && same == i; ++j) {
      if (fields[j] == fields[i]) same = j;
    }
    ids[i] = same < i ? ids[same] : names_.Find(fields[i]);
    all_found &= FrameOfName(ids[i]).is_valid();
  }
  const auto unknown_body_name = [&](std::string_view n) {
    return !n.empty() && !names_.Find(n).is_valid() && !semantics::ValidateName(n);
  };
  if (all_found && !unknown_body_name(body) && !unknown_body_name(ref_body)) return std::nullopt;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (!ids[i].is_valid() && !semantics::ValidateName(fields[i])) {
      return QError(ErrorCode::kInvalidName, kinds[i]);
    }
  }
  if (auto bad = InvalidBodyNames(body, ref_body)) return bad;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (!FrameOfName(ids[i]).is_valid()) return QError(ErrorCode::kUnknownFrame, kinds[i], ids[i]);
  }
  return std::nullopt;
}

// A query's body: the given name (unknown_body if absent), or the body of `frame`.
template <coord::Backend B>
std::optional<QueryError> SceneGraph<B>::ResolveBodyName(std::string_view body, NameId frame, Field field,
                                                         NameId& id) const noexcept {
  id = body.empty() ? bodies_[body_of(FrameOfName(frame)).value()].name : names_.Find(body);
  if (!BodyOfName(id).is_valid()) return QError(ErrorCode::kUnknownBody, field, id);
  return std::nullopt;
}

template <coord::Backend B>
QueryResult<typename SceneGraph<B>::Pose> SceneGraph<B>::GetPose(const PoseSpec& spec) const noexcept {
  const std::string_view fields[] = {spec.point, spec.orientation, spec.ref_point, spec.ref_orientation,
                                     spec.coordinate_frame};
  const Field kinds[] = {Field::kPoint, Field::kOrientation, Field::kRefPoint, Field::kRefOrientation,
                         Field::kCoordinateFrame};
  NameId ids[5], C, D;
  if (auto e = ResolveFrameNames(fields, kinds, ids, spec.body, spec.ref_body)) return Unexpected{*e};
  if (auto e = ResolveBodyName(spec.body, ids[1], Field::kBody, C)) return Unexpected{*e};
  if (auto e = ResolveBodyName(spec.ref_body, ids[3], Field::kRefBody, D)) return Unexpected{*e};
  return GetPose(semantics::PoseSemantics{semantics::Point(ids[0]), semantics::OrientationFrame(ids[1]),
                                          semantics::Body(C), semantics::Point(ids[2]),
                                          semantics::OrientationFrame(ids[3]), semantics::Body(D),
                                          semantics::OrientationFrame(ids[4])});
}

template <coord::Backend B>
QueryResult<coord::Position> SceneGraph<B>::GetPosition(const PoseSpec& spec) const noexcept {
  const std::string_view fields[] = {spec.point, spec.ref_point, spec.coordinate_frame};
  const Field kinds[] = {Field::kPoint, Field::kRefPoint, Field::kCoordinateFrame};
  NameId ids[3], C, D;
  if (auto e = ResolveFrameNames(fields, kinds, ids, spec.body, spec.ref_body)) return Unexpected{*e};
  if (auto e = ResolveBodyName(spec.body, ids[0], Field::kBody, C)) return Unexpected{*e};
  if (auto e = ResolveBodyName(spec.ref_body, ids[1], Field::kRefBody, D)) return Unexpected{*e};
  return GetPosition(semantics::PositionSemantics{semantics::Point(ids[0]), semantics::Body(C),
                                                  semantics::Point(ids[1]), semantics::Body(D),
                                                  semantics::OrientationFrame(ids[2])});
}

template <coord::Backend B>
QueryResult<typename SceneGraph<B>::Orientation> SceneGraph<B>::GetOrientation(
    const PoseSpec& spec) const noexcept {
  const std::string_view fields[] = {spec.orientation, spec.ref_orientation, spec.coordinate_frame};
  const Field kinds[] = {Field::kOrientation, Field::kRefOrientation, Field::kCoordinateFrame};
  NameId ids[3], C, D;
  if (auto e = ResolveFrameNames(fields, kinds, ids, spec.body, spec.ref_body)) return Unexpected{*e};
  if (auto e = ResolveBodyName(spec.body, ids[0], Field::kBody, C)) return Unexpected{*e};
  if (auto e = ResolveBodyName(spec.ref_body, ids[1], Field::kRefBody, D)) return Unexpected{*e};
  return GetOrientation(semantics::OrientationSemantics{
      semantics::OrientationFrame(ids[0]), semantics::Body(C), semantics::OrientationFrame(ids[1]),
      semantics::Body(D), semantics::OrientationFrame(ids[2])});
}

template <coord::Backend B>
QueryResult<coord::Twist> SceneGraph<B>::GetTwist(const TwistSpec& spec) const noexcept {
  if (!semantics::ValidateName(spec.point)) return Unexpected{QError(ErrorCode::kInvalidName, Field::kPoint)};
  if (!semantics::ValidateName(spec.ref_body)) return Unexpected{QError(ErrorCode::kInvalidName, Field::kRefBody)};
  if (!semantics::ValidateName(spec.coordinate_frame)) {
    return Unexpected{QError(ErrorCode::kInvalidName, Field::kCoordinateFrame)};
  }
  if (auto bad = InvalidBodyNames(spec.body, {})) return Unexpected{*bad};
  const NameId e = names_.Find(spec.point), r = names_.Find(spec.coordinate_frame);
  if (!FrameOfName(e).is_valid()) return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kPoint, e)};
  if (!FrameOfName(r).is_valid()) return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kCoordinateFrame, r)};
  const NameId C = spec.body.empty() ? bodies_[body_of(FrameOfName(e)).value()].name : names_.Find(spec.body);
  const NameId D = names_.Find(spec.ref_body);
  if (!BodyOfName(C).is_valid()) return Unexpected{QError(ErrorCode::kUnknownBody, Field::kBody, C)};
  if (!BodyOfName(D).is_valid()) return Unexpected{QError(ErrorCode::kUnknownBody, Field::kRefBody, D)};
  return GetTwist(semantics::TwistSemantics{semantics::Point(e), semantics::Body(C), semantics::Body(D),
                                            semantics::OrientationFrame(r)});
}

template <coord::Backend B>
QueryResult<coord::LinearVelocity> SceneGraph<B>::GetLinearVelocity(const TwistSpec& spec) const noexcept {
  auto tw = GetTwist(spec);
  if (!tw) return Unexpected{tw.error()};
  return coord::LinearOf(*tw);
}

template <coord::Backend B>
QueryResult<coord::AngularVelocity> SceneGraph<B>::GetAngularVelocity(
    const TwistSpec& spec) const noexcept {
  // The angular velocity needs no point: use the coordinate frame's origin.
  TwistSpec s = spec;
  s.point = spec.coordinate_frame;
  if (s.body.empty()) {
    if (spec.coordinate_frame.empty()) return Unexpected{QError(ErrorCode::kInvalidName, Field::kCoordinateFrame)};
    return Unexpected{QError(ErrorCode::kInvalidName, Field::kBody)};
  }
  auto tw = GetTwist(s);
  if (!tw) {
    QueryError e = tw.error();
    if (e.field == Field::kPoint) e.field = Field::kCoordinateFrame;  // the point was [r]'s origin
    return Unexpected{e};
  }
  return coord::AngularOf(*tw);
}

// ====================================================================== adds

template <coord::Backend B>
BuildResult SceneGraph<B>::AddPose(const PoseSpec& spec, const Eigen::Quaterniond& q_rotation,
                                   const Eigen::Vector3d& p_position) {
  return AddPoseImpl(spec, q_rotation, p_position);
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddPose(const PoseSpec& spec, const Eigen::Matrix3d& R_rotation,
                                   const Eigen::Vector3d& p_position) {
  return AddPoseImpl(spec, R_rotation, p_position);
}

template <coord::Backend B>
template <class R>
BuildResult SceneGraph<B>::AddPoseImpl(const PoseSpec& spec, const R& rotation,
                                       const Eigen::Vector3d& p_position) {
  NameRollback rollback(names_);
  // The relation as the user wrote it, for messages; formatted only when a rule rejects it.
  const auto what = [&spec] {
    const auto part = [](std::string_view point, std::string_view orientation, std::string_view body) {
      std::string s = point == orientation ? "{" + std::string(point) + "}"
                                           : "(" + std::string(point) + ",[" + std::string(orientation) + "])";
      return body.empty() ? s : s + "|" + std::string(body);
    };
    std::string text = "pose of " + part(spec.point, spec.orientation, spec.body) + " wrt " +
                       part(spec.ref_point, spec.ref_orientation, spec.ref_body);
    if (spec.coordinate_frame != spec.ref_orientation || spec.point != spec.orientation ||
        spec.ref_point != spec.ref_orientation) {
      text += " in [" + std::string(spec.coordinate_frame) + "]";
    }
    return text;
  };

  // 1. invalid_name.
  struct NamedField {
    std::string_view value;
    const char* role;
    bool required;
  };
  const NamedField named[] = {{spec.point, "point", true},
                              {spec.orientation, "orientation frame", true},
                              {spec.body, "body", false},
                              {spec.ref_point, "reference point", true},
                              {spec.ref_orientation, "reference orientation frame", true},
                              {spec.ref_body, "reference body", false},
                              {spec.coordinate_frame, "coordinate frame", true}};
  // Each distinct name is looked up once; an interned name is valid by the table's invariant, so
  // only new names are validated (the edge form repeats names: Of(x).RelativeTo(y)).
  NameId found[7];
  for (int i = 0; i < 7; ++i) {
    const NamedField& n = named[i];
    if (n.value.empty() && !n.required) continue;
    int same = -1;
    for (int j = 0; j < i && same < 0; ++j) {
      if (named[j].value == n.value) same = j;
    }
    found[i] = same >= 0 ? found[same] : names_.Find(n.value);
    if (found[i].is_valid()) continue;
    if (auto ok = semantics::ValidateName(n.value); !ok) {
      return Reject(ErrorCode::kInvalidName, what(),
                    std::string(n.role) + ": " + semantics::Describe(ok.error(), n.value));
    }
  }
  // 2-3. invalid_number -> invalid_rotation.
  auto p_ok = coord::ValidateVector(p_position, coord::ValueRole::kPosition);
  if (!p_ok) return Reject(p_ok.error().code, what(), coord::Describe(p_ok.error(), names_));
  typename B::Rotation M;
  if constexpr (std::is_same_v<R, Eigen::Quaterniond>) {
    auto q_ok = coord::ValidateQuaternion(rotation);
    if (!q_ok) return Reject(q_ok.error().code, what(), coord::Describe(q_ok.error(), names_));
    M = B::FromQuaternion(*q_ok);
  } else {
    auto R_ok = coord::ValidateRotationMatrix(rotation);
    if (!R_ok) return Reject(R_ok.error().code, what(), coord::Describe(R_ok.error(), names_));
    M = B::FromMatrix(*R_ok);
  }

  // 4. Node resolution. Names are interned now (rolled back on rejection).
  for (int i = 0; i < 7; ++i) {
    if (!found[i].is_valid() && !named[i].value.empty()) found[i] = *names_.Intern(named[i].value);
  }
  const NameId e_id = found[0], a_id = found[1], C_id = found[2];
  const NameId f_id = found[3], b_id = found[4], D_id = found[5];
  const NameId r_id = found[6];
  GrowNameMaps();
  const FrameIndex a = FrameOfName(a_id), b = FrameOfName(b_id);
  BodyIndex C = BodyOfName(C_id), D = BodyOfName(D_id);
  NameId C_name = C_id, D_name = D_id;
  const auto resolve = [&](FrameIndex x, std::string_view frame, std::string_view body_text,
                           BodyIndex& body, NameId& body_name_id) -> BuildResult {
    if (x.is_valid()) {
      if (!body_text.empty() && body != body_of(x)) {
        return Reject(ErrorCode::kFrameBodyMismatch, what(),
                      "frame {" + std::string(frame) + "} is attached to body " +
                          std::string(body_name(body_of(x))) + ", not " + std::string(body_text));
      }
      body = body_of(x);
      body_name_id = bodies_[body.value()].name;
      return Ok{};
    }
    if (body_text.empty()) {
      return Reject(ErrorCode::kFrameWithoutBody, what(),
                    "frame {" + std::string(frame) +
                        "} does not exist and no body is given to attach it to");
    }
    return Ok{};
  };
  if (auto ok = resolve(a, spec.orientation, spec.body, C, C_name); !ok) return ok;
  if (auto ok = resolve(b, spec.ref_orientation, spec.ref_body, D, D_name); !ok) return ok;
  const FrameIndex e = FrameOfName(e_id), f = FrameOfName(f_id), r = FrameOfName(r_id);
  if (e.is_valid() && e != a && body_of(e) != C) {
    return Reject(ErrorCode::kFrameBodyMismatch, what(),
                  "point " + std::string(spec.point) + " is the origin of " + FrameText(e) +
                      ", not of a frame of body " + std::string(names_.name(C_name)));
  }
  if (f.is_valid() && f != b && body_of(f) != D) {
    return Reject(ErrorCode::kFrameBodyMismatch, what(),
                  "reference point " + std::string(spec.ref_point) + " is the origin of " +
                      FrameText(f) + ", not of a frame of body " + std::string(names_.name(D_name)));
  }
  // 5. self_edge.
  if (a_id == b_id) {
    return Reject(ErrorCode::kSelfEdge, what(), "a pose edge from {" + std::string(spec.orientation) +
                                                  "} to itself is meaningless");
  }
  // 6. representation_constraint.
  const semantics::PoseSemantics given{semantics::Point(e_id), semantics::OrientationFrame(a_id),
                                       semantics::Body(C_name), semantics::Point(f_id),
                                       semantics::OrientationFrame(b_id), semantics::Body(D_name),
                                       semantics::OrientationFrame(r_id)};
  if (auto ok = coord::CheckRepresentation<B>(given); !ok) {
    return Reject(ErrorCode::kRepresentationConstraint, what(), coord::Describe(ok.error(), names_));
  }
  // 7. pose_not_convertible, then the conversion to the edge form X_BA in [b].
  Pose X{given, B::MakePose(M, *p_ok)};
  if (e_id != a_id && !(a.is_valid() && e.is_valid() && trees_.SameSet(a.value(), e.value()))) {
    return Reject(ErrorCode::kPoseNotConvertible, what(),
                  "point " + std::string(spec.point) + " must be a frame of " +
                      std::string(names_.name(C_name)) + " in the pose tree of {" +
                      std::string(spec.orientation) + "}");
  }
  if (f_id != b_id && !(b.is_valid() && f.is_valid() && trees_.SameSet(b.value(), f.value()))) {
    return Reject(ErrorCode::kPoseNotConvertible, what(),
                  "reference point " + std::string(spec.ref_point) + " must be a frame of " +
                      std::string(names_.name(D_name)) + " in the pose tree of {" +
                      std::string(spec.ref_orientation) + "}");
  }
  if (r_id != b_id && !(b.is_valid() && r.is_valid() && trees_.SameSet(b.value(), r.value()))) {
    return Reject(ErrorCode::kPoseNotConvertible, what(),
                  "coordinate frame [" + std::string(spec.coordinate_frame) +
                      "] must be a frame in the pose tree of {" + std::string(spec.ref_orientation) + "}");
  }
  const auto conversion_failed = [&](const coord::Error& err) {
    return Reject(ErrorCode::kPoseNotConvertible, what(), "conversion failed: " + coord::Describe(err, names_));
  };
  if (r_id != b_id) {  // re-express in [b]: O = [r] wrt [b] in [b]
    auto X_BR = BasicPose(r, b);
    if (!X_BR) return conversion_failed(X_BR.error());
    auto R_BR = coord::OrientationOf(*X_BR);
    if (!R_BR) return conversion_failed(R_BR.error());
    auto next = coord::ChangeCoordinateFrame(X, *R_BR);
    if (!next) return conversion_failed(next.error());
    X = *next;
  }
  if (f_id != b_id) {  // reference point f -> b: A = p(f wrt b) in [b]
    auto X_BF = BasicPose(f, b);
    if (!X_BF) return conversion_failed(X_BF.error());
    auto next = coord::ChangeRefPoint(X, coord::PositionOf(*X_BF));
    if (!next) return conversion_failed(next.error());
    X = *next;
  }
  if (e_id != a_id) {  // point e -> a: A = p(a wrt e), from [e] to [a] to [b]
    auto X_EA = BasicPose(a, e);
    if (!X_EA) return conversion_failed(X_EA.error());
    auto X_AE = BasicPose(e, a);
    if (!X_AE) return conversion_failed(X_AE.error());
    auto R_AE = coord::OrientationOf(*X_AE);
    if (!R_AE) return conversion_failed(R_AE.error());
    auto p_EA_A = coord::ChangeCoordinateFrame(coord::PositionOf(*X_EA), *R_AE);
    if (!p_EA_A) return conversion_failed(p_EA_A.error());
    auto R_BA = coord::OrientationOf(X);
    if (!R_BA) return conversion_failed(R_BA.error());
    // Relabel [a] wrt [b] in [b] as the coordinate change from [a] to [b].
    auto p_EA_B = coord::ChangeCoordinateFrame(*p_EA_A, *R_BA);
    if (!p_EA_B) return conversion_failed(p_EA_B.error());
    auto next = coord::ChangePoint(X, *p_EA_B);
    if (!next) return conversion_failed(next.error());
    X = *next;
  }
  SEMGRAPH_DEMAND(X.semantics.is_edge_form());

  // 8. Existing edge b -> a: constant_pose_change, or a value update.
  if (a.is_valid() && b.is_valid() && forest_.parent(a) == b) {
    if (body_of(a) == body_of(b)) {
      const auto stored = X_PF_[a.value()].Load();
      const Eigen::Matrix3d dR = B::ToMatrix(B::RotationOf(stored)) - B::ToMatrix(B::RotationOf(X.value));
      const Eigen::Vector3d p_stored = B::TranslationOf(stored);
      const double dp = (p_stored - B::TranslationOf(X.value)).norm();
      if (dR.cwiseAbs().maxCoeff() <= 1e-6 && dp <= 1e-6 * std::max(1.0, p_stored.norm())) {
        rollback.Commit();
        return Ok{};  // same value again: accepted, stored value kept
      }
      return Reject(ErrorCode::kConstantPoseChange, what(),
                    FrameText(a) + " and " + FrameText(b) + " are both fixed to body " +
                        std::string(body_name(body_of(a))) +
                        ", so their pose is constant; it is already set (position " +
                        FormatVector(p_stored) + "); remove the edge first to recalibrate");
    }
    X_PF_[a.value()].Store(X.value);
    rollback.Commit();
    return Ok{};
  }
  // 9. multiple_pose_parents.
  if (a.is_valid() && forest_.parent(a).is_valid()) {
    return Reject(ErrorCode::kMultiplePoseParents, what(),
                  FrameText(a) + " already has a pose parent " + FrameText(forest_.parent(a)));
  }
  // 10. pose_cycle: a is a root; b in a's tree means b descends from a.
  if (a.is_valid() && b.is_valid() && trees_.SameSet(a.value(), b.value())) {
    return Reject(ErrorCode::kPoseCycle, what(),
                  FrameText(b) + " is already connected below " + FrameText(a) +
                      " (through the pose tree rooted at " + FrameText(forest_.Root(b)) +
                      "); the edge would close a cycle");
  }
  // 11. duplicate_pose_path (P3), on body sets; frames that do not exist yet form trees {x}.
  const bool same_body = C_name == D_name;
  BodyIndex shared;
  if (a.is_valid() && b.is_valid()) {
    shared = SharedBody(b, a, same_body ? D : BodyIndex());
  } else if (a.is_valid()) {  // b new: tree(b) = {D}
    if (!same_body && D.is_valid() && TreeHasBody(a, D)) shared = D;
  } else if (b.is_valid()) {  // a new: tree(a) = {C}
    if (!same_body && C.is_valid() && TreeHasBody(b, C)) shared = C;
  }
  if (shared.is_valid()) {
    const FrameIndex in_t = b.is_valid() ? SomeFrameOfBodyInTree(shared, b) : FrameIndex();
    const FrameIndex in_h = a.is_valid() ? SomeFrameOfBodyInTree(shared, a) : FrameIndex();
    std::string reason = "body " + std::string(body_name(shared)) + " would be reachable twice: ";
    reason += in_t.is_valid() ? FrameText(in_t) : std::string("{" + std::string(spec.ref_orientation) + "}");
    reason += " is in the pose tree of {" + std::string(spec.ref_orientation) + "} and ";
    reason += in_h.is_valid() ? FrameText(in_h) : std::string("{" + std::string(spec.orientation) + "}");
    reason += " is in the pose tree of {" + std::string(spec.orientation) + "}";
    return Reject(ErrorCode::kDuplicatePosePath, what(), reason);
  }
  // 12. twist_merge_conflict (W4).
  if (a.is_valid() && b.is_valid()) {
    const TreeRecord* rec_a = RecordOf(a);
    const TreeRecord* rec_b = RecordOf(b);
    if (rec_a && rec_b && !rec_a->twists.empty() && !rec_b->twists.empty() &&
        !rec_b->twists.CanMerge(rec_a->twists)) {
      return Reject(ErrorCode::kTwistMergeConflict, what(),
                    "joining the pose trees of " + FrameText(b) + " and " + FrameText(a) +
                        " would give two twist paths between the same bodies (their twist "
                        "edges would form a cycle)");
    }
  }

  // 13. Apply: create nodes, link, merge tree sets and records, store the value.
  rollback.Commit();
  if (!C.is_valid()) C = CreateBody(C_name);
  if (!D.is_valid()) D = C_name == D_name ? C : CreateBody(D_name);
  const FrameIndex head = a.is_valid() ? a : CreateFrame(a_id, C);
  const FrameIndex tail = b.is_valid() ? b : CreateFrame(b_id, D);
  const std::uint32_t rep_t = trees_.Find(tail.value());
  const std::uint32_t rep_h = trees_.Find(head.value());
  const std::uint32_t* idx_t = record_of_rep_.Find(rep_t);
  const std::uint32_t* idx_h = record_of_rep_.Find(rep_h);
  const bool head_is_single = idx_h == nullptr;
  const std::uint32_t index_h = head_is_single ? kNone : *idx_h;
  // Records are materialized before linking (EnsureRecord relies on single-frame trees).
  const std::uint32_t index_t = idx_t ? *idx_t : (EnsureRecord(tail), *record_of_rep_.Find(rep_t));
  forest_.Link(tail, head);
  X_PF_[head.value()].Store(X.value);
  ++num_pose_edges_;
  if (head_is_single) {
    // Fast path: the head is a single frame without twists; count its body into tail's tree.
    TreeRecord& rec = records_[index_t];
    rec.body_counts.FindOrInsert(body_of(head).value(), 0) += 1;
    const std::uint32_t rep = trees_.Union(tail.value(), head.value());
    if (rep != rep_t) {
      record_of_rep_.Erase(rep_t);
      record_of_rep_.Insert(rep, index_t);
    }
    return Ok{};
  }
  record_of_rep_.Erase(rep_t);
  record_of_rep_.Erase(rep_h);
  // Merge the smaller record into the larger.
  std::uint32_t keep = index_t, drop = index_h;
  if (records_[keep].body_counts.size() < records_[drop].body_counts.size()) std::swap(keep, drop);
  records_[drop].body_counts.ForEach([&](std::uint32_t body, std::uint32_t count) {
    records_[keep].body_counts.FindOrInsert(body, 0) += count;
  });
  records_[keep].twists.Merge(std::move(records_[drop].twists));
  records_[drop].body_counts.Clear();
  records_[drop].twists.Clear();
  free_records_.push_back(drop);
  const std::uint32_t rep = trees_.Union(tail.value(), head.value());
  record_of_rep_.Insert(rep, keep);
  return Ok{};
}

template <coord::Backend B>
BuildResult SceneGraph<B>::AddTwist(const TwistSpec& spec, const Eigen::Vector3d& v_linear,
                                    const Eigen::Vector3d& w_angular) {
  NameRollback rollback(names_);
  const auto what = [&spec] {  // formatted only when a rule rejects the twist
    return "twist of " + std::string(spec.point) + (spec.body.empty() ? "" : "|" + std::string(spec.body)) +
           " wrt " + std::string(spec.ref_body) + " in [" + std::string(spec.coordinate_frame) + "]";
  };
  struct NamedField {
    std::string_view value;
    const char* role;
    bool required;
  };
  const NamedField named[] = {{spec.point, "point", true},
                              {spec.body, "body", false},
                              {spec.ref_body, "reference body", true},
                              {spec.coordinate_frame, "coordinate frame", true}};
  for (const NamedField& n : named) {
    if (n.value.empty() && !n.required) continue;
    if (auto ok = semantics::ValidateName(n.value); !ok) {
      return Reject(ErrorCode::kInvalidName, what(),
                    std::string(n.role) + ": " + semantics::Describe(ok.error(), n.value));
    }
  }
  auto v_ok = coord::ValidateVector(v_linear, coord::ValueRole::kLinearVelocity);
  if (!v_ok) return Reject(v_ok.error().code, what(), coord::Describe(v_ok.error(), names_));
  auto w_ok = coord::ValidateVector(w_angular, coord::ValueRole::kAngularVelocity);
  if (!w_ok) return Reject(w_ok.error().code, what(), coord::Describe(w_ok.error(), names_));

  // Node resolution: the point must be the origin of a frame on the moving body.
  const NameId e_id = *names_.Intern(spec.point);
  const NameId C_id = spec.body.empty() ? NameId() : *names_.Intern(spec.body);
  const NameId D_id = *names_.Intern(spec.ref_body);
  const NameId r_id = *names_.Intern(spec.coordinate_frame);
  GrowNameMaps();
  const FrameIndex e = FrameOfName(e_id);
  BodyIndex C = BodyOfName(C_id);
  NameId C_name = C_id;
  if (e.is_valid()) {
    if (C_id.is_valid() && C != body_of(e)) {
      return Reject(ErrorCode::kFrameBodyMismatch, what(),
                    "the point of a twist must be the origin of a frame on the moving body: " +
                        FrameText(e) + " is not on body " + std::string(spec.body));
    }
    C = body_of(e);
    C_name = bodies_[C.value()].name;
  } else if (!C_id.is_valid()) {
    return Reject(ErrorCode::kFrameWithoutBody, what(),
                  "frame {" + std::string(spec.point) + "} does not exist and no body is given");
  }
  const BodyIndex D = BodyOfName(D_id);
  if (C_name == D_id) {
    return Reject(ErrorCode::kTwistSameBody, what(),
                  "a twist of body " + std::string(names_.name(C_name)) + " relative to itself");
  }
  // twist_not_convertible: [r] must be in the pose tree of {e}.
  const FrameIndex r = FrameOfName(r_id);
  coord::Twist tw{{semantics::Point(e_id), semantics::Body(C_name), semantics::Body(D_id),
                   semantics::OrientationFrame(r_id)},
                  *v_ok, *w_ok};
  if (r_id != e_id) {
    if (!(e.is_valid() && r.is_valid() && trees_.SameSet(e.value(), r.value()))) {
      return Reject(ErrorCode::kTwistNotConvertible, what(),
                    "coordinate frame [" + std::string(spec.coordinate_frame) +
                        "] must be a frame in the pose tree of {" + std::string(spec.point) + "}");
    }
    auto X_ER = BasicPose(r, e);  // [r] wrt [e] in [e]
    auto R_ER = X_ER ? coord::OrientationOf(*X_ER) : Result<Orientation>(Unexpected{X_ER.error()});
    auto next = R_ER ? coord::ChangeCoordinateFrame(tw, *R_ER) : Result<coord::Twist>(Unexpected{R_ER.error()});
    if (!next) {
      return Reject(ErrorCode::kTwistNotConvertible, what(),
                    "conversion failed: " + coord::Describe(next.error(), names_));
    }
    tw = *next;
  }
  SEMGRAPH_DEMAND(tw.semantics.is_screw_twist());
  // Existing edge D -> e: update; another parent: multiple_twist_parents.
  if (e.is_valid() && frames_[e.value()].twist_edge != kNone) {
    TwistEdge& te = twist_edges_[frames_[e.value()].twist_edge];
    if (te.tail == D && D.is_valid()) {
      te.value.Store(TwistNumbers{tw.linear, tw.angular});
      rollback.Commit();
      return Ok{};
    }
    return Reject(ErrorCode::kMultipleTwistParents, what(),
                  FrameText(e) + " already has a twist parent: body " +
                      std::string(body_name(te.tail)));
  }
  // duplicate_twist_path (W3).
  if (e.is_valid() && D.is_valid()) {
    if (const TreeRecord* rec = RecordOf(e); rec && rec->twists.Connected(C.value(), D.value())) {
      return Reject(ErrorCode::kDuplicateTwistPath, what(),
                    "the twist of " + std::string(body_name(C)) + " relative to " +
                        std::string(body_name(D)) +
                        " already follows from the twist edges of the pose tree of " + FrameText(e));
    }
  }
  // Apply.
  rollback.Commit();
  if (!C.is_valid()) C = CreateBody(C_name);
  const BodyIndex tail = D.is_valid() ? D : CreateBody(D_id);
  const FrameIndex head = e.is_valid() ? e : CreateFrame(e_id, C);
  std::uint32_t index;
  if (!free_twist_edges_.empty()) {
    index = free_twist_edges_.back();
    free_twist_edges_.pop_back();
  } else {
    index = static_cast<std::uint32_t>(twist_edges_.size());
    twist_edges_.emplace_back();
  }
  tw.semantics.body = BodySem(C);
  tw.semantics.ref_body = BodySem(tail);
  TwistEdge& te = twist_edges_[index];
  te.tail = tail;
  te.head = head;
  te.alive = true;
  te.semantics = tw.semantics;
  te.value.Store(TwistNumbers{tw.linear, tw.angular});
  frames_[head.value()].twist_edge = index;
  EnsureRecord(head).twists.Link(index, tail.value(), C.value());
  ++num_twist_edges_;
  return Ok{};
}

// ====================================================================== removal

template <coord::Backend B>
BuildResult SceneGraph<B>::RemovePose(std::string_view of, std::string_view wrt) {
  const std::string what = "removal of the pose of {" + std::string(of) + "} wrt {" + std::string(wrt) + "}";
  for (std::string_view n : {of, wrt}) {
    if (auto ok = semantics::ValidateName(n); !ok) {
      return Reject(ErrorCode::kInvalidName, what, semantics::Describe(ok.error(), n));
    }
  }
  const FrameIndex h = FindFrame(of), t = FindFrame(wrt);
  if (!h.is_valid()) return Reject(ErrorCode::kUnknownFrame, what, "frame {" + std::string(of) + "} does not exist");
  if (!t.is_valid()) return Reject(ErrorCode::kUnknownFrame, what, "frame {" + std::string(wrt) + "} does not exist");
  if (forest_.parent(h) != t) {
    const FrameIndex p = forest_.parent(h);
    return Reject(ErrorCode::kNoSuchEdge, what,
                  "there is no pose edge " + FrameText(t) + " -> " + FrameText(h) +
                      (p.is_valid() ? " (the pose parent of " + FrameText(h) + " is " + FrameText(p) + ")"
                                    : " (" + FrameText(h) + " has no pose parent)"));
  }
  // Collect the old tree's twist edges, split the forest, then rebuild both trees' sets.
  std::vector<std::uint32_t> twist_edges;
  const std::uint32_t old_rep = trees_.Find(h.value());
  if (const std::uint32_t* index = record_of_rep_.Find(old_rep)) {
    records_[*index].twists.ForEachEdge(
        [&](std::uint32_t edge, std::uint32_t, std::uint32_t) { twist_edges.push_back(edge); });
    records_[*index].body_counts.Clear();
    records_[*index].twists.Clear();
    free_records_.push_back(*index);
    record_of_rep_.Erase(old_rep);
  }
  const FrameIndex old_root = forest_.Root(t);
  forest_.ForEachInSubtree(old_root, [&](FrameIndex f) { trees_.Reset(f.value()); });
  forest_.Cut(h);
  X_PF_[h.value()].BumpEpoch();  // compiled queries and handles using this edge become invalid
  --num_pose_edges_;
  RebuildTree(old_root, twist_edges);
  RebuildTree(h, twist_edges);
  return Ok{};
}

template <coord::Backend B>
BuildResult SceneGraph<B>::RemoveTwist(std::string_view point, std::string_view ref_body) {
  const auto shown = [](std::string_view n) { return n.empty() ? std::string("\"\"") : std::string(n); };
  const std::string what = "removal of the twist of " + shown(point) + " wrt " + shown(ref_body);
  for (std::string_view n : {point, ref_body}) {
    if (auto ok = semantics::ValidateName(n); !ok) {
      return Reject(ErrorCode::kInvalidName, what, semantics::Describe(ok.error(), n));
    }
  }
  const FrameIndex h = FindFrame(point);
  if (!h.is_valid()) return Reject(ErrorCode::kUnknownFrame, what, "frame {" + std::string(point) + "} does not exist");
  const BodyIndex D = FindBody(ref_body);
  if (!D.is_valid()) return Reject(ErrorCode::kUnknownBody, what, "body " + std::string(ref_body) + " does not exist");
  const std::uint32_t index = frames_[h.value()].twist_edge;
  if (index == kNone || twist_edges_[index].tail != D) {
    return Reject(ErrorCode::kNoSuchEdge, what,
                  "there is no twist edge " + std::string(ref_body) + " -> " + FrameText(h) +
                      (index == kNone ? " (" + FrameText(h) + " has no twist parent)"
                                      : " (its twist parent is " +
                                            std::string(body_name(twist_edges_[index].tail)) + ")"));
  }
  const std::uint32_t rep = trees_.Find(h.value());
  TreeRecord& rec = records_[*record_of_rep_.Find(rep)];
  rec.twists.Unlink(index);
  frames_[h.value()].twist_edge = kNone;
  twist_edges_[index].alive = false;
  twist_edges_[index].value.BumpEpoch();  // compiled queries using this edge become invalid
  free_twist_edges_.push_back(index);
  --num_twist_edges_;
  // A single-frame tree without twists needs no record.
  if (rec.twists.empty() && !forest_.first_child(h).is_valid() && forest_.is_root(h)) {
    rec.body_counts.Clear();
    free_records_.push_back(*record_of_rep_.Find(rep));
    record_of_rep_.Erase(rep);
  }
  return Ok{};
}

// ====================================================================== text, dump, checks

template <coord::Backend B>
std::string SceneGraph<B>::Describe(const QueryError& e) const {
  return Describe(e, PoseSpec{});
}

namespace {
std::string_view SpecField(const PoseSpec& s, Field f) {
  switch (f) {
    case Field::kPoint: return s.point;
    case Field::kOrientation: return s.orientation;
    case Field::kBody: return s.body;
    case Field::kRefPoint: return s.ref_point;
    case Field::kRefOrientation: return s.ref_orientation;
    case Field::kRefBody: return s.ref_body;
    case Field::kCoordinateFrame: return s.coordinate_frame;
  }
  return {};
}
std::string_view FieldRole(Field f) {
  switch (f) {
    case Field::kPoint: return "point";
    case Field::kOrientation: return "orientation frame";
    case Field::kBody: return "body";
    case Field::kRefPoint: return "reference point";
    case Field::kRefOrientation: return "reference orientation frame";
    case Field::kRefBody: return "reference body";
    case Field::kCoordinateFrame: return "coordinate frame";
  }
  return "argument";
}
}  // namespace

template <coord::Backend B>
std::string SceneGraph<B>::Describe(const QueryError& e, const TwistSpec& spec) const {
  PoseSpec p;
  p.point = spec.point;
  p.body = spec.body;
  p.ref_body = spec.ref_body;
  p.coordinate_frame = spec.coordinate_frame;
  return Describe(e, p);
}

template <coord::Backend B>
std::string SceneGraph<B>::Describe(const QueryError& e, const PoseSpec& spec) const {
  const std::string role(FieldRole(e.field));
  const std::string name = e.name.is_valid() ? std::string(names_.name(e.name)) : std::string(SpecField(spec, e.field));
  switch (e.code) {
    case ErrorCode::kInvalidName:
      return "the " + role + " name is missing or invalid";
    case ErrorCode::kUnknownFrame:
      return "the " + role + " names frame {" + name + "}, which does not exist";
    case ErrorCode::kUnknownBody:
      return "the " + role + " names body " + name + ", which does not exist";
    case ErrorCode::kFrameBodyMismatch:
      return "the " + role + " {" + name + "} is attached to body " + std::string(names_.name(e.other)) +
             (e.asked.is_valid() ? ", not to body " + std::string(names_.name(e.asked)) + " named in the query"
                                 : ", not to the body named in the query");
    case ErrorCode::kNoPosePath:
      return "{" + name + "} and {" + std::string(names_.name(e.other)) +
             "} are in different pose trees: no pose path joins them";
    case ErrorCode::kNoTwistPath:
      return "no twist path joins body " + std::string(names_.name(e.name)) + " and body " +
             std::string(names_.name(e.other)) + " in this pose tree";
    default:
      return coord::Describe(e.detail, names_);
  }
}

template <coord::Backend B>
std::string SceneGraph<B>::Dump() const {
  std::ostringstream out;
  out.precision(17);
  out << "representation " << B::kName << "\nnames " << names_.size() << "\n";
  for (std::size_t i = 0; i < names_.size(); ++i) out << "  name " << i << " " << names_.name(NameId(i)) << "\n";
  out << "bodies " << bodies_.size() << "\n";
  for (std::size_t i = 0; i < bodies_.size(); ++i) out << "  body " << i << " " << body_name(BodyIndex(i)) << "\n";
  out << "frames " << frames_.size() << "\n";
  for (std::uint32_t i = 0; i < frames_.size(); ++i) {
    const FrameIndex f(i);
    out << "  frame " << i << " " << FrameText(f);
    if (forest_.parent(f).is_valid()) {
      const auto X = X_PF_[i].Load();
      const Eigen::Quaterniond q = B::ToQuaternion(B::RotationOf(X));
      const Eigen::Vector3d p = B::TranslationOf(X);
      out << " parent " << forest_.parent(f).value() << " p " << p.x() << " " << p.y() << " " << p.z()
          << " q " << q.w() << " " << q.x() << " " << q.y() << " " << q.z();
    }
    if (const std::optional<coord::Twist> tw = twist_value(f)) {
      out << " twist_parent " << body_name(twist_parent(f)) << " v " << tw->linear.transpose()
          << " w " << tw->angular.transpose();
    }
    out << " tree " << forest_.Root(f).value() << "\n";
  }
  return out.str();
}

template <coord::Backend B>
std::string SceneGraph<B>::CheckInvariants() const {
  std::ostringstream out;
  if (!forest_.CheckInvariants()) out << "pose forest invariants broken\n";
  // Union-find sets = pose trees; records = body multisets and TG of each tree.
  for (std::uint32_t i = 0; i < frames_.size(); ++i) {
    const FrameIndex f(i);
    if (trees_.FindConst(i) != trees_.FindConst(forest_.Root(f).value())) {
      out << "frame " << FrameText(f) << " is in another set than its root\n";
    }
  }
  // Per tree: recount bodies, check P3 (a body's frames in one tree are same-body connected:
  // count of frames of body X == 1 + number of same-body edges among them), and TG is a forest.
  for (std::uint32_t i = 0; i < frames_.size(); ++i) {
    const FrameIndex root(i);
    if (!forest_.is_root(root)) continue;
    FlatMap<std::uint32_t> counts, same_edges;
    std::size_t size = 0;
    forest_.ForEachInSubtree(root, [&](FrameIndex f) {
      ++size;
      counts.FindOrInsert(body_of(f).value(), 0) += 1;
      const FrameIndex p = forest_.parent(f);
      if (p.is_valid() && body_of(p) == body_of(f)) same_edges.FindOrInsert(body_of(f).value(), 0) += 1;
    });
    counts.ForEach([&](std::uint32_t body, std::uint32_t c) {
      const std::uint32_t* s = same_edges.Find(body);
      if (c != 1 + (s ? *s : 0)) {
        out << "P3: body " << body_name(BodyIndex(body)) << " is reachable twice in the tree of "
            << FrameText(root) << "\n";
      }
    });
    const TreeRecord* rec = RecordOf(root);
    if (rec) {
      if (rec->body_counts.size() != counts.size()) out << "body set size mismatch at " << FrameText(root) << "\n";
      counts.ForEach([&](std::uint32_t body, std::uint32_t c) {
        const std::uint32_t* stored = rec->body_counts.Find(body);
        if (!stored || *stored != c) out << "body count mismatch at " << FrameText(root) << "\n";
      });
      if (!rec->twists.CheckInvariants()) out << "twist forest broken at " << FrameText(root) << "\n";
    } else if (size != 1) {
      out << "tree of " << FrameText(root) << " has no record\n";
    }
  }
  std::size_t live = 0;
  for (std::uint32_t i = 0; i < twist_edges_.size(); ++i) {
    const TwistEdge& te = twist_edges_[i];
    if (!te.alive) continue;
    ++live;
    const TreeRecord* rec = RecordOf(te.head);
    if (!rec || !rec->twists.FindEdge(i)) out << "twist edge " << i << " missing from its tree's TG\n";
    if (te.tail == body_of(te.head)) out << "W2 broken\n";
    if (frames_[te.head.value()].twist_edge != i) out << "W1 bookkeeping broken\n";
  }
  if (live != num_twist_edges_) out << "twist edge count mismatch\n";
  return out.str();
}

template <coord::Backend B>
std::size_t SceneGraph<B>::ApproximateBytesExcludingNames() const noexcept {
  std::size_t bytes = sizeof(*this);
  bytes += frames_.capacity() * sizeof(FrameNode) + bodies_.capacity() * sizeof(BodyNode);
  bytes += X_PF_.capacity() * sizeof(PoseValue<B>);
  bytes += forest_.ApproximateBytes();
  bytes += trees_.size() * 2 * sizeof(std::uint32_t);
  bytes += record_of_rep_.ApproximateBytes();
  for (const TreeRecord& r : records_) bytes += r.body_counts.ApproximateBytes() + r.twists.ApproximateBytes();
  bytes += twist_edges_.capacity() * sizeof(TwistEdge);
  bytes += (frame_of_name_.capacity() + body_of_name_.capacity()) * sizeof(std::uint32_t);
  return bytes;
}

// ====================================================================== real-time path

template <coord::Backend B>
Expected<PoseHandle, BuildError> SceneGraph<B>::FindPoseEdge(std::string_view of,
                                                            std::string_view wrt) const {
  const std::string what = "handle of the pose of {" + std::string(of) + "} wrt {" + std::string(wrt) + "}";
  const FrameIndex h = FindFrame(of), t = FindFrame(wrt);
  if (!h.is_valid() || !t.is_valid()) {
    return Unexpected{Reject(ErrorCode::kUnknownFrame, what,
                             "frame {" + std::string(h.is_valid() ? wrt : of) + "} does not exist")
                          .error()};
  }
  if (forest_.parent(h) != t) {
    return Unexpected{Reject(ErrorCode::kNoSuchEdge, what,
                             "there is no pose edge " + FrameText(t) + " -> " + FrameText(h))
                          .error()};
  }
  if (body_of(h) == body_of(t)) {
    return Unexpected{Reject(ErrorCode::kConstantPoseChange, what,
                             FrameText(h) + " and " + FrameText(t) +
                                 " are fixed to one body: their pose is constant")
                          .error()};
  }
  return PoseHandle{h, X_PF_[h.value()].epoch()};
}

template <coord::Backend B>
Expected<TwistHandle, BuildError> SceneGraph<B>::FindTwistEdge(std::string_view point,
                                                              std::string_view ref_body) const {
  const std::string what = "handle of the twist of " + std::string(point) + " wrt " + std::string(ref_body);
  const FrameIndex h = FindFrame(point);
  if (!h.is_valid()) {
    return Unexpected{
        Reject(ErrorCode::kUnknownFrame, what, "frame {" + std::string(point) + "} does not exist").error()};
  }
  const BodyIndex D = FindBody(ref_body);
  if (!D.is_valid()) {
    return Unexpected{
        Reject(ErrorCode::kUnknownBody, what, "body " + std::string(ref_body) + " does not exist").error()};
  }
  const std::uint32_t slot = frames_[h.value()].twist_edge;
  if (slot == kNone || twist_edges_[slot].tail != D) {
    return Unexpected{Reject(ErrorCode::kNoSuchEdge, what,
                             "there is no twist edge " + std::string(ref_body) + " -> " + FrameText(h))
                          .error()};
  }
  return TwistHandle{slot, twist_edges_[slot].value.epoch()};
}

namespace {
// The rotation of a real-time pose update, validated (and normalized) without allocating.
inline auto ValidateRotation(const Eigen::Quaterniond& q) noexcept { return coord::ValidateQuaternion(q); }
inline auto ValidateRotation(const Eigen::Matrix3d& R) noexcept { return coord::ValidateRotationMatrix(R); }
}  // namespace

template <coord::Backend B>
template <class R>
ErrorCode SceneGraph<B>::SetPoseImpl(PoseHandle edge, const R& rotation,
                                     const Eigen::Vector3d& p_ThHo_T) noexcept {
  if (!edge.child.is_valid() || edge.child.value() >= X_PF_.size() ||
      X_PF_[edge.child.value()].epoch() != edge.epoch) {
    return ErrorCode::kNoSuchEdge;
  }
  auto p = coord::ValidateVector(p_ThHo_T, coord::ValueRole::kPosition);
  if (!p) return p.error().code;
  auto M = ValidateRotation(rotation);
  if (!M) return M.error().code;
  if constexpr (std::is_same_v<R, Eigen::Quaterniond>) {
    X_PF_[edge.child.value()].Store(B::MakePose(B::FromQuaternion(*M), *p));
  } else {
    X_PF_[edge.child.value()].Store(B::MakePose(B::FromMatrix(*M), *p));
  }
  return ErrorCode::kOk;
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPose(PoseHandle edge, const Eigen::Quaterniond& q_TH,
                                 const Eigen::Vector3d& p_ThHo_T) noexcept {
  return SetPoseImpl(edge, q_TH, p_ThHo_T);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetPose(PoseHandle edge, const Eigen::Matrix3d& R_TH,
                                 const Eigen::Vector3d& p_ThHo_T) noexcept {
  return SetPoseImpl(edge, R_TH, p_ThHo_T);
}

template <coord::Backend B>
ErrorCode SceneGraph<B>::SetTwist(TwistHandle edge, const Eigen::Vector3d& v_linear,
                                  const Eigen::Vector3d& w_angular) noexcept {
  if (edge.slot >= twist_edges_.size() || !twist_edges_[edge.slot].alive ||
      twist_edges_[edge.slot].value.epoch() != edge.epoch) {
    return ErrorCode::kNoSuchEdge;
  }
  auto v = coord::ValidateVector(v_linear, coord::ValueRole::kLinearVelocity);
  if (!v) return v.error().code;
  auto w = coord::ValidateVector(w_angular, coord::ValueRole::kAngularVelocity);
  if (!w) return w.error().code;
  twist_edges_[edge.slot].value.Store(TwistNumbers{*v, *w});
  return ErrorCode::kOk;
}

template <coord::Backend B>
Expected<CompiledPose<B>, QueryError> SceneGraph<B>::CompilePose(const PoseSpec& spec) const {
  auto checked = GetPose(spec);  // every check of the one-shot query, once
  if (!checked) return Unexpected{checked.error()};
  const semantics::PoseSemantics& q = checked->semantics;
  const FrameIndex e = FrameOfName(q.point.id()), a = FrameOfName(q.orientation.id());
  const FrameIndex f = FrameOfName(q.ref_point.id()), b = FrameOfName(q.ref_orientation.id());
  const FrameIndex r = FrameOfName(q.coordinate_frame.id());
  CompiledPose<B> c;
  c.graph_ = this;
  c.semantics_ = q;
  c.ab_ = c.AddBasic(a, b);
  if ((c.change_ref_point_ = f != b)) c.fb_ = c.AddBasic(f, b);
  if ((c.change_point_ = e != a)) c.ea_ = c.AddBasic(e, a);
  if ((c.change_frame_ = r != b)) c.br_ = c.AddBasic(b, r);
  return c;
}

template <coord::Backend B>
Expected<CompiledPosition<B>, QueryError> SceneGraph<B>::CompilePosition(const PoseSpec& spec) const {
  auto checked = GetPosition(spec);
  if (!checked) return Unexpected{checked.error()};
  const semantics::PositionSemantics& q = checked->semantics;
  const FrameIndex e = FrameOfName(q.point.id()), f = FrameOfName(q.ref_point.id());
  const FrameIndex r = FrameOfName(q.coordinate_frame.id());
  CompiledPosition<B> c;
  c.graph_ = this;
  c.semantics_ = q;
  c.ef_ = c.AddBasic(e, f);
  if ((c.change_frame_ = r != f)) c.fr_ = c.AddBasic(f, r);
  return c;
}

template <coord::Backend B>
Expected<CompiledOrientation<B>, QueryError> SceneGraph<B>::CompileOrientation(
    const PoseSpec& spec) const {
  auto checked = GetOrientation(spec);
  if (!checked) return Unexpected{checked.error()};
  const semantics::OrientationSemantics& q = checked->semantics;
  const FrameIndex a = FrameOfName(q.orientation.id()), b = FrameOfName(q.ref_orientation.id());
  const FrameIndex r = FrameOfName(q.coordinate_frame.id());
  CompiledOrientation<B> c;
  c.graph_ = this;
  c.semantics_ = q;
  c.ab_ = c.AddBasic(a, b);
  if ((c.change_frame_ = r != b)) c.br_ = c.AddBasic(b, r);
  return c;
}

template <coord::Backend B>
Expected<CompiledTwist<B>, QueryError> SceneGraph<B>::CompileTwist(const TwistSpec& spec) const {
  TwistSpec s = spec;
  if (s.point.empty()) s.point = s.coordinate_frame;  // angular velocity: any point will do
  auto checked = GetTwist(s);
  if (!checked) return Unexpected{checked.error()};
  const semantics::TwistSemantics& q = checked->semantics;
  const FrameIndex e = FrameOfName(q.point.id()), r = FrameOfName(q.coordinate_frame.id());
  const BodyIndex C = BodyOfName(q.body.id()), D = BodyOfName(q.ref_body.id());
  CompiledTwist<B> c;
  c.graph_ = this;
  c.semantics_ = q;
  if (C == D) return c;
  const TreeRecord* rec = RecordOf(e);
  SEMGRAPH_DEMAND(rec != nullptr);
  const TwistForest& tg = rec->twists;
  std::uint32_t x = C.value(), y = D.value();
  while (tg.depth(x) > tg.depth(y)) x = tg.parent(x);
  while (tg.depth(y) > tg.depth(x)) y = tg.parent(y);
  while (x != y) {
    x = tg.parent(x);
    y = tg.parent(y);
  }
  // C up to the common ancestor as stored/inverted; D's side is subtracted (inverse twist).
  const auto walk = [&](std::uint32_t from, bool negate) {
    for (std::uint32_t body = from; body != x; body = tg.parent(body)) {
      const std::uint32_t slot = tg.parent_edge(body);
      const TwistEdge& te = twist_edges_[slot];
      const FrameIndex h = te.head;
      typename CompiledTwist<B>::Step step{};
      step.slot = slot;
      step.epoch = te.value.epoch();
      step.invert = (body_of(h).value() != body) != negate;
      if ((step.move_point = h != e)) step.eh = c.AddBasic(e, h);
      if ((step.change_frame = h != r)) step.hr = c.AddBasic(h, r);
      c.steps_.push_back(step);
    }
  };
  walk(C.value(), false);
  walk(D.value(), true);
  return c;
}

template class SceneGraph<coord::QuaternionBackend>;
template class SceneGraph<coord::HomogeneousBackend>;

}  // namespace semgraph::core
