// Query planners: name resolution and semantic checks, once per query. Contract: query_plan.h.
#include "semgraph/core/query_plan.h"

#include <optional>
#include <span>

#include "semgraph/base/demand.h"

namespace semgraph::core {

using base::Unexpected;
using semantics::Field;
using topology::SceneTopology;

namespace {

QueryError QError(ErrorCode code, Field field = Field::kPoint, NameId name = {}, NameId other = {},
                  NameId asked = {}) {
  QueryError e;
  e.code = code;
  e.field = field;
  e.name = name;
  e.other = other;
  e.asked = asked;
  return e;
}

// invalid_name for an optional body name that is given but invalid. O(|name|), no allocation.
std::optional<QueryError> InvalidBodyNames(std::string_view body,
                                           std::string_view ref_body) noexcept {
  if (!body.empty() && !semantics::ValidateName(body))
    return QError(ErrorCode::kInvalidName, Field::kBody);
  if (!ref_body.empty() && !semantics::ValidateName(ref_body)) {
    return QError(ErrorCode::kInvalidName, Field::kRefBody);
  }
  return std::nullopt;
}

// Query names, in the rules' order: every frame name and given body name valid (invalid_name),
// then every frame known (unknown_frame). Each distinct name is hashed once: Of(x).RelativeTo(y)
// repeats names. An interned name is valid by the table's invariant, so no name is validated
// unless a lookup fails; then the order decides what to report.
std::optional<QueryError> ResolveFrameNames(const SceneTopology& t,
                                            std::span<const std::string_view> fields,
                                            std::span<const Field> kinds, std::span<NameId> ids,
                                            std::string_view body,
                                            std::string_view ref_body) noexcept {
  // Same view (the builders copy one view into several fields) before same text.
  // Names often share a prefix and differ at the end: the last byte decides most mismatches.
  const auto same_name = [](std::string_view x, std::string_view y) {
    return x.size() == y.size() &&
           (x.data() == y.data() || (!x.empty() && x.back() == y.back() && x == y));
  };
  bool all_found = true;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    std::size_t same = i;
    for (std::size_t j = 0; j < i && same == i; ++j) {
      if (same_name(fields[j], fields[i])) same = j;
    }
    ids[i] = same < i ? ids[same] : t.names().Find(fields[i]);
    all_found &= t.FrameOfName(ids[i]).is_valid();
  }
  const auto unknown_body_name = [&](std::string_view n) {
    return !n.empty() && !t.names().Find(n).is_valid() && !semantics::ValidateName(n);
  };
  if (all_found && !unknown_body_name(body) && !unknown_body_name(ref_body)) return std::nullopt;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (!ids[i].is_valid() && !semantics::ValidateName(fields[i])) {
      return QError(ErrorCode::kInvalidName, kinds[i]);
    }
  }
  if (auto bad = InvalidBodyNames(body, ref_body)) return bad;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (!t.FrameOfName(ids[i]).is_valid())
      return QError(ErrorCode::kUnknownFrame, kinds[i], ids[i]);
  }
  return std::nullopt;
}

// A query's body: the given name (unknown_body if absent), or the body of `frame`.
std::optional<QueryError> ResolveBodyName(const SceneTopology& t, std::string_view body,
                                          NameId frame, Field field, NameId& id) noexcept {
  id = body.empty() ? t.body_name_id(t.body_of(t.FrameOfName(frame))) : t.names().Find(body);
  if (!t.BodyOfName(id).is_valid()) return QError(ErrorCode::kUnknownBody, field, id);
  return std::nullopt;
}

// The checks every pose-side query makes on its resolved ids, in order: unknown_frame per
// frame field, unknown_body per body, frame_body_mismatch per (frame, body) pair, no_pose_path
// per (frame, frame) pair. Fields are listed in the query's order.
struct FrameField {
  NameId id;
  Field field;
};
struct BodyCheck {
  int frame;  // index into the frame fields
  int body;   // 0: C, 1: D
};
struct PathCheck {
  int x, y;  // frame fields that must share a tree; reported as (x, y)
};

std::optional<QueryError> CheckResolved(const SceneTopology& t, std::span<const FrameField> frames,
                                        std::span<FrameIndex> out, NameId C_id, NameId D_id,
                                        std::span<const BodyCheck> body_checks,
                                        std::span<const PathCheck> path_checks) noexcept {
  for (std::size_t i = 0; i < frames.size(); ++i) {
    out[i] = t.FrameOfName(frames[i].id);
    if (!out[i].is_valid()) return QError(ErrorCode::kUnknownFrame, frames[i].field, frames[i].id);
  }
  const BodyIndex bodies[2] = {t.BodyOfName(C_id), t.BodyOfName(D_id)};
  if (!bodies[0].is_valid()) return QError(ErrorCode::kUnknownBody, Field::kBody, C_id);
  if (!bodies[1].is_valid()) return QError(ErrorCode::kUnknownBody, Field::kRefBody, D_id);
  for (const BodyCheck& c : body_checks) {
    const FrameIndex x = out[c.frame];
    const BodyIndex body = bodies[c.body];
    if (t.body_of(x) != body) {
      return QError(ErrorCode::kFrameBodyMismatch, frames[c.frame].field, t.frame_name_id(x),
                    t.body_name_id(t.body_of(x)), t.body_name_id(body));
    }
  }
  for (const PathCheck& c : path_checks) {
    if (out[c.x] != out[c.y] && !t.SameTree(out[c.x], out[c.y])) {
      return QError(ErrorCode::kNoPosePath, frames[c.x].field, t.frame_name_id(out[c.x]),
                    t.frame_name_id(out[c.y]));
    }
  }
  return std::nullopt;
}

}  // namespace

BasicPath<ForestChain> PlanBasic(const SceneTopology& t, FrameIndex a, FrameIndex b) noexcept {
  // Invalid only for a reader racing a topology change: the evaluation's walk then fails, and
  // the answer is thrown away (optimistic_read.h). Callers checked SameTree(a, b).
  const FrameIndex c = t.forest().CommonAncestor(a, b);
  return BasicPath<ForestChain>{{a, c}, {b, c}};
}

PoseSteps<ForestChain> PlanPoseSteps(const SceneTopology& t, FrameIndex e, FrameIndex a,
                                     FrameIndex f, FrameIndex b, FrameIndex r) noexcept {
  PoseSteps<ForestChain> s = PlanChanges(t, e, a, f, b, r);
  s.ab = PlanBasic(t, a, b);
  return s;
}

PoseSteps<ForestChain> PlanChanges(const SceneTopology& t, FrameIndex e, FrameIndex a, FrameIndex f,
                                   FrameIndex b, FrameIndex r) noexcept {
  PoseSteps<ForestChain> s;
  if ((s.change_ref_point = f != b)) s.fb = PlanBasic(t, f, b);
  if ((s.change_point = e != a)) s.ea = PlanBasic(t, e, a);
  if ((s.change_frame = r != b)) s.br = PlanBasic(t, b, r);
  return s;
}

// ====================================================================== by ids

Expected<PosePlan, QueryError> PlanPose(const SceneTopology& t,
                                        const semantics::PoseSemantics& q) noexcept {
  const FrameField frames[] = {{q.point.id(), Field::kPoint},
                               {q.orientation.id(), Field::kOrientation},
                               {q.ref_point.id(), Field::kRefPoint},
                               {q.ref_orientation.id(), Field::kRefOrientation},
                               {q.coordinate_frame.id(), Field::kCoordinateFrame}};
  const BodyCheck bodies[] = {{0, 0}, {1, 0}, {2, 1}, {3, 1}};
  const PathCheck paths[] = {{1, 3}, {0, 1}, {2, 3}, {4, 3}};
  FrameIndex x[5];
  if (auto e = CheckResolved(t, frames, x, q.body.id(), q.ref_body.id(), bodies, paths))
    return Unexpected{*e};
  const FrameIndex e = x[0], a = x[1], f = x[2], b = x[3], r = x[4];
  return PosePlan{q, PlanPoseSteps(t, e, a, f, b, r)};
}

Expected<PositionPlan, QueryError> PlanPosition(const SceneTopology& t,
                                                const semantics::PositionSemantics& q) noexcept {
  const FrameField frames[] = {{q.point.id(), Field::kPoint},
                               {q.ref_point.id(), Field::kRefPoint},
                               {q.coordinate_frame.id(), Field::kCoordinateFrame}};
  const BodyCheck bodies[] = {{0, 0}, {1, 1}};
  const PathCheck paths[] = {{0, 1}, {2, 1}};
  FrameIndex x[3];
  if (auto e = CheckResolved(t, frames, x, q.body.id(), q.ref_body.id(), bodies, paths))
    return Unexpected{*e};
  const FrameIndex e = x[0], f = x[1], r = x[2];
  return PositionPlan{q, PlanPoseSteps(t, e, e, f, f, r)};
}

Expected<OrientationPlan, QueryError> PlanOrientation(
    const SceneTopology& t, const semantics::OrientationSemantics& q) noexcept {
  const FrameField frames[] = {{q.orientation.id(), Field::kOrientation},
                               {q.ref_orientation.id(), Field::kRefOrientation},
                               {q.coordinate_frame.id(), Field::kCoordinateFrame}};
  const BodyCheck bodies[] = {{0, 0}, {1, 1}};
  const PathCheck paths[] = {{0, 1}, {2, 1}};
  FrameIndex x[3];
  if (auto e = CheckResolved(t, frames, x, q.body.id(), q.ref_body.id(), bodies, paths))
    return Unexpected{*e};
  const FrameIndex a = x[0], b = x[1], r = x[2];
  return OrientationPlan{q, PlanPoseSteps(t, a, a, b, b, r)};
}

Expected<TwistPlan, QueryError> PlanTwist(const SceneTopology& t,
                                          const semantics::TwistSemantics& q) noexcept {
  const FrameField frames[] = {{q.point.id(), Field::kPoint},
                               {q.coordinate_frame.id(), Field::kCoordinateFrame}};
  const PathCheck paths[] = {{1, 0}};
  FrameIndex x[2];
  if (auto e = CheckResolved(t, frames, x, q.body.id(), q.ref_body.id(), {}, paths))
    return Unexpected{*e};
  TwistPlan plan;
  plan.point = x[0];
  plan.frame = x[1];
  plan.body = t.BodyOfName(q.body.id());
  plan.ref_body = t.BodyOfName(q.ref_body.id());
  plan.semantics =
      semantics::TwistSemantics{t.FrameSem(plan.point).origin(), t.BodySem(plan.body),
                                t.BodySem(plan.ref_body), t.FrameSem(plan.frame).axes()};
  if (plan.body == plan.ref_body) return plan;  // zero twist
  const topology::TreeRecord* rec = t.RecordOf(plan.point);
  if (!rec || !rec->twists.Connected(plan.body, plan.ref_body)) {
    return Unexpected{
        QError(ErrorCode::kNoTwistPath, Field::kBody, q.body.id(), q.ref_body.id(), q.point.id())};
  }
  // Youngest common ancestor of C and D in the rooted TG, by depth. Bounded: a concurrent
  // writer (docs/realtime.md) may show a reader thread inconsistent depths or parents; the
  // answer is then kNoTwistPath, which the reader's validation discards. A consistent forest
  // takes at most num_bodies() steps a side.
  const topology::TwistForest& tg = rec->twists;
  BodyIndex c = plan.body, d = plan.ref_body;
  std::size_t budget = 2 * tg.num_bodies();
  while (tg.depth(c) > tg.depth(d) && budget-- > 0) c = tg.parent(c);
  while (tg.depth(d) > tg.depth(c) && budget-- > 0) d = tg.parent(d);
  while (c != d && budget-- > 0) {
    c = tg.parent(c);
    d = tg.parent(d);
  }
  if (c != d) {
    return Unexpected{
        QError(ErrorCode::kNoTwistPath, Field::kBody, q.body.id(), q.ref_body.id(), q.point.id())};
  }
  plan.ancestor = c;
  plan.tg = &tg;
  return plan;
}

// ====================================================================== by names

Expected<PosePlan, QueryError> PlanPose(const SceneTopology& t, const PoseSpec& spec) noexcept {
  // Frame-to-frame fast path, PoseSpec::Of(a).RelativeTo(b) with no bodies named: two names, one
  // basic pose. Any failure takes the general path below, which reports in the rules' order.
  if (spec.point.data() == spec.orientation.data() &&
      spec.point.size() == spec.orientation.size() &&
      spec.ref_point.data() == spec.ref_orientation.data() &&
      spec.ref_point.size() == spec.ref_orientation.size() &&
      spec.coordinate_frame.data() == spec.ref_orientation.data() &&
      spec.coordinate_frame.size() == spec.ref_orientation.size() && spec.body.empty() &&
      spec.ref_body.empty()) {
    const NameId a_id = t.names().Find(spec.orientation),
                 b_id = t.names().Find(spec.ref_orientation);
    const FrameIndex a = t.FrameOfName(a_id), b = t.FrameOfName(b_id);
    if (a.is_valid() && b.is_valid() && (a == b || t.SameTree(a, b))) {
      const semantics::Body C = t.BodyOfSem(a), D = t.BodyOfSem(b);
      PosePlan plan;
      plan.semantics = semantics::PoseSemantics{
          semantics::Point(a_id),           semantics::OrientationFrame(a_id), C,
          semantics::Point(b_id),           semantics::OrientationFrame(b_id), D,
          semantics::OrientationFrame(b_id)};
      plan.steps.ab = PlanBasic(t, a, b);
      return plan;
    }
  }
  const std::string_view fields[] = {spec.point, spec.orientation, spec.ref_point,
                                     spec.ref_orientation, spec.coordinate_frame};
  const Field kinds[] = {Field::kPoint, Field::kOrientation, Field::kRefPoint,
                         Field::kRefOrientation, Field::kCoordinateFrame};
  NameId ids[5], C, D;
  if (auto e = ResolveFrameNames(t, fields, kinds, ids, spec.body, spec.ref_body))
    return Unexpected{*e};
  if (auto e = ResolveBodyName(t, spec.body, ids[1], Field::kBody, C)) return Unexpected{*e};
  if (auto e = ResolveBodyName(t, spec.ref_body, ids[3], Field::kRefBody, D)) return Unexpected{*e};
  return PlanPose(
      t, semantics::PoseSemantics{semantics::Point(ids[0]), semantics::OrientationFrame(ids[1]),
                                  semantics::Body(C), semantics::Point(ids[2]),
                                  semantics::OrientationFrame(ids[3]), semantics::Body(D),
                                  semantics::OrientationFrame(ids[4])});
}

Expected<PositionPlan, QueryError> PlanPosition(const SceneTopology& t,
                                                const PoseSpec& spec) noexcept {
  const std::string_view fields[] = {spec.point, spec.ref_point, spec.coordinate_frame};
  const Field kinds[] = {Field::kPoint, Field::kRefPoint, Field::kCoordinateFrame};
  NameId ids[3], C, D;
  if (auto e = ResolveFrameNames(t, fields, kinds, ids, spec.body, spec.ref_body))
    return Unexpected{*e};
  if (auto e = ResolveBodyName(t, spec.body, ids[0], Field::kBody, C)) return Unexpected{*e};
  if (auto e = ResolveBodyName(t, spec.ref_body, ids[1], Field::kRefBody, D)) return Unexpected{*e};
  return PlanPosition(t, semantics::PositionSemantics{semantics::Point(ids[0]), semantics::Body(C),
                                                      semantics::Point(ids[1]), semantics::Body(D),
                                                      semantics::OrientationFrame(ids[2])});
}

Expected<OrientationPlan, QueryError> PlanOrientation(const SceneTopology& t,
                                                      const PoseSpec& spec) noexcept {
  const std::string_view fields[] = {spec.orientation, spec.ref_orientation, spec.coordinate_frame};
  const Field kinds[] = {Field::kOrientation, Field::kRefOrientation, Field::kCoordinateFrame};
  NameId ids[3], C, D;
  if (auto e = ResolveFrameNames(t, fields, kinds, ids, spec.body, spec.ref_body))
    return Unexpected{*e};
  if (auto e = ResolveBodyName(t, spec.body, ids[0], Field::kBody, C)) return Unexpected{*e};
  if (auto e = ResolveBodyName(t, spec.ref_body, ids[1], Field::kRefBody, D)) return Unexpected{*e};
  return PlanOrientation(
      t, semantics::OrientationSemantics{semantics::OrientationFrame(ids[0]), semantics::Body(C),
                                         semantics::OrientationFrame(ids[1]), semantics::Body(D),
                                         semantics::OrientationFrame(ids[2])});
}

Expected<TwistPlan, QueryError> PlanTwist(const SceneTopology& t, const TwistSpec& spec) noexcept {
  if (!semantics::ValidateName(spec.point))
    return Unexpected{QError(ErrorCode::kInvalidName, Field::kPoint)};
  if (!semantics::ValidateName(spec.ref_body))
    return Unexpected{QError(ErrorCode::kInvalidName, Field::kRefBody)};
  if (!semantics::ValidateName(spec.coordinate_frame)) {
    return Unexpected{QError(ErrorCode::kInvalidName, Field::kCoordinateFrame)};
  }
  if (auto bad = InvalidBodyNames(spec.body, {})) return Unexpected{*bad};
  const NameId e = t.names().Find(spec.point), r = t.names().Find(spec.coordinate_frame);
  if (!t.FrameOfName(e).is_valid())
    return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kPoint, e)};
  if (!t.FrameOfName(r).is_valid())
    return Unexpected{QError(ErrorCode::kUnknownFrame, Field::kCoordinateFrame, r)};
  const NameId C =
      spec.body.empty() ? t.body_name_id(t.body_of(t.FrameOfName(e))) : t.names().Find(spec.body);
  const NameId D = t.names().Find(spec.ref_body);
  if (!t.BodyOfName(C).is_valid())
    return Unexpected{QError(ErrorCode::kUnknownBody, Field::kBody, C)};
  if (!t.BodyOfName(D).is_valid())
    return Unexpected{QError(ErrorCode::kUnknownBody, Field::kRefBody, D)};
  return PlanTwist(
      t, semantics::TwistSemantics{semantics::Point(e), semantics::Body(C), semantics::Body(D),
                                   semantics::OrientationFrame(r)});
}

}  // namespace semgraph::core
