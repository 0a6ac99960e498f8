// scene_ops_fuzzer: random operation sequences on SceneGraph<B>, checked op by op against the
// naive ReferenceModel (tests/reference) by Differential<B> (support/scene_differential.h: same
// accept/reject and error code, Dump() unchanged by rejections and queries, CheckInvariants()
// empty, same topology and stored values, same query answers one-shot and compiled, kept
// compiled queries invalidated exactly when an edge they use is removed). On any disagreement
// the whole op sequence is printed in scene-script notation and the harness aborts.
//
// Input format (every byte string is a valid input; see support/op_reader.h):
//   byte 0            bit 0: also run the sequence on the homogeneous backend (the quaternion
//                     backend always runs); the rest of the input is decoded once per backend.
//                     Time options: bit 1 linear interpolation (else screw), bit 2 duplicate
//                     stamps rejected (else replaced), bit 3 a 1 s window and 3 samples per edge
//   then ops          one op-code byte (% 20), then the op's arguments (names, value choices);
//                     13 and 14 are extended ops, one more byte (% 12): 0-3 repairing adds,
//                     4 joint, 5 joint states by name, 6 joint group made / set, 7 Jacobian,
//                     8 stamped pose, 9 stamped twist, 10-11 a query under a time policy;
//                     17 an add with a covariance (pose, restated pose, twist, updated twist;
//                     valid, asymmetric, NaN/Inf/huge, negative eigenvalue; both orders; the
//                     body convention); 16 a wrench op (add, update, the reverse of a stored
//                     pair, removal, query of one pair, its reaction or a net wrench, one-shot
//                     or compiled and kept, a handle kept, SetWrench through a kept handle);
//                     15 an acceleration op (a twist with an acceleration, AddAcceleration with
//                     every error class, twist handles with SetAcceleration / SetTwist, queries
//                     of the three kinds one-shot, compiled, and compiled and kept; stamped: a
//                     twist sample with an acceleration, AddAcceleration and SetAcceleration at
//                     a sample's stamp or a wrong one, queries under every time policy; stamped
//                     joint states with qddot by name and by the real-time group setters)
// Name space: 6 bodies A..F and 12 frames a..l, so collisions are frequent; about 1 name in 32
// is special: empty, a control character, 300 bytes, 256 bytes (invalid), 255 bytes (valid),
// or a frame named like a body. Frame arguments often come from the tree of an earlier
// argument (via the model), so that queries and conversions mostly succeed.
// Values come from small tables (unit rotations, positions from 1e-324 to 1e6, twists), each
// with a modifier: -q, |q| off by 4e-7 (accepted, normalized) or 1e-3 (invalid_rotation), zero
// quaternion, NaN, Inf, matrix form (exact, off-orthonormal by 3e-7, reflection, skewed, NaN),
// and changes of 1e-9 (within the constant-pose tolerance) or 1e-3 / 1e-4 rad (outside it).
// Re-adding an existing edge uses the stored value with such a modifier.
//
// Scope: the model's (edge-form pose adds; twist adds in the point's frame or another frame of
// its tree; their repair; joints; stamped adds and time policies:
// tests/reference/reference_model.h). Caps: at most kMaxOps ops per backend run. Debugging:
// SEMGRAPH_FUZZ_TRACE=1 prints every input's op sequence (e.g. with the replay main).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "support/op_reader.h"
#include "support/scene_differential.h"

namespace semgraph::fuzz {
namespace {

#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
constexpr std::size_t kMaxOps = 96;
#else
constexpr std::size_t kMaxOps = 256;
#endif

const char* const kBodies[] = {"A", "B", "C", "D", "E", "F"};
const char* const kFrames[] = {"a", "b", "c", "d", "e", "f", "g", "h", "i", "j", "k", "l"};

// Special names: index 0-3 invalid, 4 valid but long, 5 a name used by the other pool.
std::string SpecialName(std::uint32_t which, bool frame) {
  switch (which % 6) {
    case 0:
      return "";
    case 1:
      return frame ? "bad\x01name" : "\x7f";
    case 2:
      return std::string(300, frame ? 'x' : 'X');
    case 3:
      return std::string(256, frame ? 'n' : 'N');
    case 4:
      return std::string(255, frame ? 'y' : 'Y');
    default:
      return frame ? "A" : "a";
  }
}

Eigen::Quaterniond Rpy(double roll, double pitch, double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

const std::vector<Eigen::Quaterniond>& Rotations() {
  static const std::vector<Eigen::Quaterniond> table = {
      Eigen::Quaterniond::Identity(),
      Eigen::Quaterniond(std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)),  // 90 deg about z
      Eigen::Quaterniond(0.0, 1.0, 0.0, 0.0),                        // 180 deg about x (w = 0)
      Rpy(0.2, -0.1, 0.3),
      Rpy(0.1, 0.4, -0.6),
      Eigen::Quaterniond(0.5, 0.5, 0.5, 0.5),  // 120 deg about (1,1,1)
      Rpy(0.0, 0.35, 3.14159265358979 * 0.75),
      Rpy(0.0, 0.01, 0.0),
  };
  return table;
}

const Eigen::Vector3d kPositions[] = {
    {0.0, 0.0, 0.0},  {1.0, 0.0, 0.5}, {0.5, 0.2, 1.1},  {-0.3, 2.0, 0.7},
    {0.02, 0.0, 0.2}, {1.2, 0.4, 0.9}, {1e6, -2e6, 3e5}, {-0.0, 5e-324, -1.0},
};
const Eigen::Vector3d kVelocities[] = {
    {0.0, 0.0, 0.0},     {0.2, 0.1, 0.1},   {0.05, 0.1, 0.2},
    {0.04, -0.03, 0.02}, {0.0, 0.15, -0.1}, {3.0, -1.0, 2.0},
};

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

RotationInput AsQuaternion(const Eigen::Quaterniond& q) {
  RotationInput r;
  r.q = q;
  return r;
}
RotationInput AsMatrix(const Eigen::Matrix3d& R) {
  RotationInput r;
  r.is_matrix = true;
  r.R = R;
  return r;
}

// A rotation: `base` with one of 16 modifiers (see the file comment).
RotationInput ModifyRotation(const Eigen::Quaterniond& base, std::uint32_t modifier,
                             std::uint32_t component) {
  Eigen::Quaterniond q = base;
  Eigen::Matrix3d R = base.toRotationMatrix();
  switch (modifier % 16) {
    case 4:
      return AsQuaternion(Eigen::Quaterniond(-q.coeffs()));
    case 5:
      return AsQuaternion(Eigen::Quaterniond(q.coeffs() * (1.0 + 4e-7)));
    case 6:
      return AsQuaternion(Eigen::Quaterniond(q.coeffs() * (1.0 + 1e-3)));
    case 7:
      return AsQuaternion(Eigen::Quaterniond(0.0, 0.0, 0.0, 0.0));
    case 8:
      q.coeffs()[component % 4] = kNaN;
      return AsQuaternion(q);
    case 9:
      q.coeffs()[component % 4] = component & 4 ? -kInf : kInf;
      return AsQuaternion(q);
    case 10:
      return AsMatrix(R);
    case 11:
      R(component % 3, (component / 3) % 3) += 3e-7;
      return AsMatrix(R);
    case 12:
      return AsMatrix(-R);
    case 13:
      R(component % 3, (component / 3) % 3) += 1e-3;
      return AsMatrix(R);
    case 14:
      R(component % 3, (component / 3) % 3) = kNaN;
      return AsMatrix(R);
    case 15:
      return AsQuaternion(q *
                          Eigen::Quaterniond(Eigen::AngleAxisd(1e-9, Eigen::Vector3d::UnitX())));
    default:
      return AsQuaternion(q);
  }
}

Eigen::Vector3d ModifyVector(Eigen::Vector3d v, std::uint32_t modifier, std::uint32_t component) {
  switch (modifier % 12) {
    case 5:
      return v + Eigen::Vector3d::Constant(1e-9);
    case 6:
      return v + Eigen::Vector3d(1e-3, 0.0, 0.0);
    case 7:
      v[component % 3] = kNaN;
      return v;
    case 8:
      v[component % 3] = kInf;
      return v;
    case 9:
      v[component % 3] = -kInf;
      return v;
    default:
      return v;
  }
}

template <coord::Backend B>
class Fuzzer {
 public:
  Fuzzer(const std::uint8_t* data, std::size_t size, const reference::TimeOptions& time)
      : in_(data, size), d_(time) {}

  void Run() {
    for (std::size_t n = 0; n < kMaxOps && !in_.empty(); ++n) Step();
    d_.SweepQueries(Differential<B>::Sweep::kLight);
    static const bool trace = std::getenv("SEMGRAPH_FUZZ_TRACE") != nullptr;
    if (trace) d_.PrintTrace(stdout);  // to see what an input decodes to
  }

 private:
  // ---------------------------------------------------------------- names

  std::string Body() {
    const std::uint8_t b = in_.Byte();
    return b < 248 ? kBodies[b % 6] : SpecialName(b, false);
  }
  std::string Frame() {
    const std::uint8_t b = in_.Byte();
    return b < 248 ? kFrames[b % 12] : SpecialName(b, true);
  }
  // Often a frame of the pose tree of `anchor` (from the model), else any frame.
  std::string FrameNear(const std::string& anchor) {
    if (!in_.Bool()) return Frame();
    std::vector<std::string> tree;
    Tree(anchor, &tree);
    if (tree.empty()) return Frame();
    return tree[in_.Below(static_cast<std::uint32_t>(tree.size()))];
  }
  void Tree(const std::string& anchor, std::vector<std::string>* out) const {
    if (!d_.model().frames().count(anchor)) return;
    std::set<std::string> seen{anchor};
    std::vector<std::string> todo{anchor};
    while (!todo.empty()) {
      const std::string n = todo.back();
      todo.pop_back();
      out->push_back(n);
      for (const reference::PoseEdge& e : d_.model().poses()) {
        for (const std::string* next : {&e.head, &e.tail}) {
          if ((e.tail == n || e.head == n) && seen.insert(*next).second) todo.push_back(*next);
        }
      }
    }
  }
  // A body argument for `frame`: omitted, the frame's own body (when it exists), or any.
  std::string BodyFor(const std::string& frame) {
    switch (in_.Below(4)) {
      case 0:
        return "";
      case 1: {
        const auto it = d_.model().frames().find(frame);
        if (it != d_.model().frames().end()) return it->second;
        return Body();
      }
      default:
        return Body();
    }
  }

  // ---------------------------------------------------------------- values

  RotationInput Rotation() {
    const Eigen::Quaterniond& base = Rotations()[in_.Below(8)];
    const std::uint8_t modifier = in_.Byte();
    return ModifyRotation(base, modifier, modifier >> 4);
  }
  Eigen::Vector3d Position() {
    const Eigen::Vector3d& base = kPositions[in_.Below(8)];
    const std::uint8_t modifier = in_.Byte();
    return ModifyVector(base, modifier, modifier >> 4);
  }
  Eigen::Vector3d Velocity() {
    const Eigen::Vector3d& base = kVelocities[in_.Below(6)];
    const std::uint8_t modifier = in_.Byte();
    return ModifyVector(base, modifier, modifier >> 4);
  }

  // ---------------------------------------------------------------- ops

  void Step() {
    switch (in_.Byte() % 20) {
      case 0:
        d_.Body(Body());
        break;
      case 1: {
        const std::string name = Frame();
        d_.Frame(name, in_.OneIn(6) ? std::string() : Body());
        break;
      }
      case 2:
      case 3:
      case 4:
      case 5:
        AddPose();
        break;
      case 6:
        ReAddPose();
        break;
      case 7:
        RemovePose();
        break;
      case 8:
      case 9:
        AddTwist();
        break;
      case 10:
        ReAddTwist();
        break;
      case 11:
        RemoveTwist();
        break;
      case 17:
        WithCovariance();
        break;
      case 16:
        WrenchOp();
        break;
      case 15:
        AccelerationOp();
        break;
      case 13:
      case 14:
        Extended();
        break;
      case 18:
        d_.Keep(MakeQuery(static_cast<QueryKind>(in_.Below(6))));
        break;
      default:
        d_.Ask(MakeQuery(static_cast<QueryKind>(in_.Below(6))));
        break;
    }
  }

  // Wrenches (docs/dynamics.md §7): adds (new pairs, updates, the reverse of a stored pair),
  // removals, queries (one pair, its reaction, a net wrench; one-shot, or compiled and kept),
  // handles kept and SetWrench through them (also after their pair was removed). The point is often
  // a frame of `on`'s pose tree and the coordinate frame one of the point's, so that conversions
  // mostly succeed; the bodies are often those of the frames, so that storage frames vary.
  void WrenchOp() {
    // Every choice reads its bytes whether it is used or not (the decoding does not depend on
    // the model's state).
    const auto& stored = d_.model().wrenches();
    const std::uint32_t which = in_.Below(10);
    const std::uint8_t pick = in_.Byte();
    const bool reverse = in_.OneIn(3);
    std::string on = Body();
    const bool self = in_.OneIn(16);
    std::string by = Body();
    if (self) by = on;
    if (((which >= 3 && which <= 5) || which == 8) && !stored.empty()) {  // a stored pair
      const reference::WrenchEntry& w = stored[pick % stored.size()];
      on = reverse ? w.by : w.on;
      by = reverse ? w.on : w.by;
    }
    const std::string point = FrameNear(on.empty() ? std::string("a") : FrameOfBody(on));
    const std::string coord = in_.OneIn(3) ? point : FrameNear(point);
    if (which == 5) {
      d_.RemoveWrench(on, by);
      return;
    }
    if (which == 8) {
      d_.WrenchHandle(on, by);
      return;
    }
    if (which == 9) {  // a kept handle (picked by `pick`), a value in the stored form
      const Eigen::Vector3d f = Velocity();
      const Eigen::Vector3d m = Velocity();
      d_.SetWrenchByHandle(pick, f, m);
      return;
    }
    if (which == 6 || which == 7) {  // 7: compiled and kept
      const std::string query_by = in_.Bool() ? std::string() : by;
      if (which == 6) {
        d_.AskWrench(on, query_by, point, coord);
      } else {
        d_.KeepWrench(on, query_by, point, coord);
      }
      return;
    }
    const Eigen::Vector3d f = Velocity();
    const Eigen::Vector3d m = in_.OneIn(4) ? Position() : Velocity();
    d_.Wrench(on, by, point, coord, f, m);
  }
  // Op 15, accelerations (docs/dynamics.md §1): `which` (Below(10)) 0-1 a twist with an
  // acceleration (a new one as AddTwist, or a stored edge's update as ReAddTwist), 2-4
  // AddAcceleration (a stored edge's relation, often bent into an error: another body, the
  // reverse relation, a point or frame of another tree; joints' and stamped edges are stored
  // edges too), 5 a twist handle kept (FindTwistEdge; 1 in 3 a converting one, taking twists
  // in a frame of the head's tree), 6 SetAcceleration and 7 SetTwist (which clears the
  // acceleration) through a kept handle (7: a converting one when a Bool says so), 8 a query
  // (acceleration, linear or angular, one-shot and compiled), 9 the same compiled and kept.
  // Stamped (docs/dynamics.md §7.2): 10 a stamped twist sample with an acceleration (a stored
  // edge's next sample or one of its stamps, or a new edge), 11 AddAcceleration at a stamp (one
  // of a stamped edge's samples or a wrong one; the edge's relation bent as for 2-4), 12
  // SetAcceleration by a kept handle at a stamp, 13 an acceleration query under a time policy
  // (At with or without a horizon, Latest, LatestCommon, not_before); stamped joint states (their
  // samples carry qddot's acceleration): 14 SetJoints by name with a stamp (with qddot half the
  // time), 15 a real-time stamped setter of the kept group (or a group made).
  void AccelerationOp() {
    const std::uint32_t which = in_.Below(16);
    const auto& twists = d_.model().twists();
    const auto some_edge = [&]() -> const reference::TwistEdge* {
      const std::uint8_t pick = in_.Byte();  // read whether used or not
      return twists.empty() ? nullptr : &twists[pick % twists.size()];
    };
    switch (which) {
      case 0:
      case 1: {
        const reference::TwistEdge* t = which == 1 ? some_edge() : nullptr;
        const std::string point = t ? t->head : Frame();
        const std::string body =
            t ? (in_.Bool() ? std::string() : d_.model().frames().at(point)) : BodyFor(point);
        const std::string ref_body = t && !in_.OneIn(8) ? t->tail_body : Body();
        const std::string coord = TwistCoord(point);
        const Eigen::Vector3d v = Velocity();
        const Eigen::Vector3d w = Velocity();
        const Eigen::Vector3d a = AccelerationValue();
        d_.TwistWithAcceleration(point, body, ref_body, coord, v, w, a, AccelerationValue());
        return;
      }
      case 2:
      case 3:
      case 4:
        return AddAccelerationOp(some_edge());
      case 5: {
        const reference::TwistEdge* t = some_edge();
        const bool converting = in_.Below(3) == 2;
        const bool any = in_.OneIn(8);
        const std::string of = t && !any ? t->head : Frame();
        const std::string wrt = t && !in_.OneIn(8) ? t->tail_body : Body();
        if (converting) {
          d_.ConvertingTwistHandle(of, wrt, FrameNear(of));
        } else {
          d_.TwistHandle(of, wrt);
        }
        return;
      }
      case 6:
      case 7: {
        const std::uint8_t pick = in_.Byte();
        const bool converting = which == 7 && in_.Bool();
        const Eigen::Vector3d x = which == 6 ? AccelerationValue() : Velocity();
        const Eigen::Vector3d y = which == 6 ? AccelerationValue() : Velocity();
        if (converting) {
          d_.SetTwistConverted(pick, x, y);
        } else {
          d_.SetByTwistHandle(pick, which == 6, x, y);
        }
        return;
      }
      case 10:
        return StampedTwistWithAcceleration();
      case 11:
        return StampedAddAcceleration();
      case 12: {
        const std::uint8_t pick = in_.Byte();
        const Eigen::Vector3d a = AccelerationValue();
        const Eigen::Vector3d alpha = AccelerationValue();
        d_.SetByTwistHandle(pick, true, a, alpha, StampOfStampedEdge(nullptr));
        return;
      }
      case 14:
        return StampedJoints();
      case 15:
        return StampedGroup();
      default: {
        const reference::TwistEdge* t1 = some_edge();  // in this order (not as two arguments)
        const reference::TwistEdge* t2 = some_edge();
        const Query q = AccelerationQuery(t1, t2);
        if (which == 13) {
          focus_stamps_.clear();  // times around t1's samples when it is stamped
          if (t1 != nullptr) {
            for (const reference::TwistSample& x : t1->samples) focus_stamps_.push_back(x.t);
          }
          d_.AskAccelerationTimed(q, TimePolicy());
        } else if (which == 8) {
          d_.AskAcceleration(q);
        } else {
          d_.KeepAcceleration(q);
        }
        return;
      }
    }
  }

  // The stamped edges of the model (pointers into its twists).
  std::vector<const reference::TwistEdge*> StampedTwistEdges() const {
    std::vector<const reference::TwistEdge*> out;
    for (const reference::TwistEdge& t : d_.model().twists()) {
      if (t.stamped) out.push_back(&t);
    }
    return out;
  }
  // A stamp for an acceleration on `t` (null: a stamped edge picked by input): mostly one of its
  // samples', else one just off it, the edge's next stamp, or one from the table.
  std::int64_t StampOfStampedEdge(const reference::TwistEdge* t) {
    const std::uint8_t pick = in_.Byte();
    const std::uint32_t how = in_.Below(8);
    if (t == nullptr) {
      const auto stamped = StampedTwistEdges();
      if (!stamped.empty()) t = stamped[pick % stamped.size()];
    }
    if (t == nullptr || t->samples.empty() || how == 7) return StampChoice();
    const std::int64_t s = t->samples[in_.Below(static_cast<std::uint32_t>(t->samples.size()))].t;
    if (how == 5) return s + 1;
    if (how == 6) return NextStamp(t->samples.back().t);
    return s;
  }

  // A stamp for a stamped joint state: mostly the next (or one of the samples') of a joint with
  // samples, else one from the table (a joint's first stamped state).
  std::int64_t JointStamp() {
    const auto& joints = d_.model().joints();
    const std::uint8_t pick = in_.Byte();
    const std::uint32_t how = in_.Below(4);
    const reference::Joint* j = joints.empty() ? nullptr : &joints[pick % joints.size()];
    if (j == nullptr || j->samples.empty() || how == 3) return StampChoice();
    if (how == 2) return j->samples[in_.Below(static_cast<std::uint32_t>(j->samples.size()))].t;
    return NextStamp(j->samples.back().t);
  }

  // Op 15/14: stamped joint states by name (positions, velocities, and q'' half the time).
  void StampedJoints() {
    typename Differential<B>::JointValues positions, velocities, accelerations;
    for (std::uint32_t n = in_.Below(4); n > 0; --n) {
      const std::string name = SomeJoint();
      positions.emplace_back(name, JointValueFor(name));
    }
    for (std::uint32_t n = in_.Below(3); n > 0; --n) {
      const std::string name = SomeJoint();
      velocities.emplace_back(name, JointValueFor(name));
    }
    for (std::uint32_t n = in_.Bool() ? in_.Below(3) + 1 : 0; n > 0; --n) {
      const std::string name = SomeJoint();
      accelerations.emplace_back(name, JointValueFor(std::string()));
    }
    d_.SetJoints(positions, velocities, accelerations, JointStamp());
  }

  // Op 15/15: a real-time stamped setter of the kept group (1 in 4: a group made instead).
  void StampedGroup() {
    if (in_.OneIn(4) || !d_.has_group()) {
      std::vector<std::string> names;
      for (std::uint32_t n = 1 + in_.Below(4); n > 0; --n) names.push_back(SomeJoint());
      d_.MakeGroup(names);
      return;
    }
    const int which = static_cast<int>(in_.Below(5));
    std::vector<double> values;
    for (const std::string& name : d_.GroupJoints()) {
      values.push_back(JointValueFor(name));
      values.push_back(JointValueFor(std::string()));  // a velocity from the table
      values.push_back(JointValueFor(std::string()));  // an acceleration from the table
    }
    d_.SetGroupStamped(which, values, JointStamp());
  }

  // Op 15/10: a stamped twist with an acceleration: on a stored stamped edge (its next stamp or
  // one of its samples: a duplicate, same or other acceleration), or as a new edge (any names).
  void StampedTwistWithAcceleration() {
    const auto stamped = StampedTwistEdges();
    const std::uint8_t pick = in_.Byte();
    const reference::TwistEdge* t =
        stamped.empty() || in_.OneIn(4) ? nullptr : stamped[pick % stamped.size()];
    const std::string point = t ? t->head : Frame();
    const std::string body = t ? std::string() : BodyFor(point);
    const std::string ref_body = t && !in_.OneIn(8) ? t->tail_body : Body();
    const std::string coord = TwistCoord(point);
    std::int64_t stamp = 0;
    if (t == nullptr) {
      stamp = StampChoice();
    } else if (in_.Bool()) {
      stamp = t->samples[in_.Below(static_cast<std::uint32_t>(t->samples.size()))].t;
    } else {
      stamp = NextStamp(t->samples.back().t);
    }
    // Restating a sample: often its own twist (then only the acceleration decides).
    Eigen::Vector3d v = Velocity(), w = Velocity();
    if (t != nullptr && coord == point && in_.Bool()) {
      for (const reference::TwistSample& x : t->samples) {
        if (x.t == stamp) v = x.v, w = x.w;
      }
    }
    const Eigen::Vector3d a = AccelerationValue();
    d_.StampedTwistWithAcceleration(point, body, ref_body, coord, v, w, a, AccelerationValue(),
                                    stamp);
  }

  // Op 15/11: AddAcceleration at a stamp, on a stamped edge's relation (bent by `how` as in
  // AddAccelerationOp: a point elsewhere in the tree, another body, the inverse relation), or
  // on any edge (a timeless one: stamp_mismatch).
  void StampedAddAcceleration() {
    const auto stamped = StampedTwistEdges();
    const std::uint8_t pick = in_.Byte();
    const std::uint32_t how = in_.Below(8);
    const std::uint32_t body_choice = in_.Below(4);
    const auto& twists = d_.model().twists();
    const reference::TwistEdge* t = nullptr;
    if (!stamped.empty() && how != 7) t = stamped[pick % stamped.size()];
    if (t == nullptr && !twists.empty()) t = &twists[pick % twists.size()];
    if (t == nullptr) {
      const std::string point = Frame();
      const std::string body = BodyFor(point);
      const std::string ref_body = Body();
      const std::string coord = TwistCoord(point);
      const Eigen::Vector3d a = AccelerationValue();
      d_.Acceleration(point, body, ref_body, coord, a, AccelerationValue(), StampChoice());
      return;
    }
    const reference::TwistEdge edge = *t;
    const std::string H = d_.model().frames().at(edge.head);
    const std::string point = how < 3 ? edge.head : FrameNear(edge.head);
    std::string body = body_choice == 0 ? std::string() : H;
    if (body_choice == 3 && in_.OneIn(4)) body = Body();
    std::string ref_body = edge.tail_body;
    if (how == 5) body = edge.tail_body, ref_body = H;  // the inverse relation, against the edge
    if (how == 6 && in_.OneIn(2)) ref_body = Body();
    const std::string coord = TwistCoord(point);
    const std::int64_t stamp = StampOfStampedEdge(&edge);
    const Eigen::Vector3d a = AccelerationValue();
    const Eigen::Vector3d alpha = AccelerationValue();
    // Restating a sample's acceleration as stored (edge form, at the head): the same again.
    if (how == 0 && body_choice != 3 && coord == point) {
      for (const reference::TwistSample& x : edge.samples) {
        if (x.t == stamp && x.has_A && in_.Bool()) {
          d_.Acceleration(point, body, ref_body, coord, x.a, x.alpha, stamp);
          return;
        }
      }
    }
    d_.Acceleration(point, body, ref_body, coord, a, alpha, stamp);
  }

  // An acceleration value: a small table (zero, gravity, a spin-up, a large one: 2e12 is over
  // the library's 1e12 bound, invalid_number) with ModifyVector's modifiers (NaN, Inf, 1e-9)
  // when the modifier byte is >= 128 (else exact: an op takes up to four vectors).
  Eigen::Vector3d AccelerationValue() {
    static const Eigen::Vector3d kTable[] = {
        {0.0, 0.0, 0.0},   {0.5, -0.2, 0.1}, {-1.0, 2.0, 0.3}, {0.0, 0.0, -9.81},
        {0.01, 0.02, 0.0}, {4.0, -3.0, 2.0}, {0.0, 0.7, 0.0},  {2e12, 0.0, 1.0},
    };
    const Eigen::Vector3d& base = kTable[in_.Below(8)];
    const std::uint8_t modifier = in_.Byte();
    return modifier < 128 ? base : ModifyVector(base, modifier, modifier >> 4);
  }

  // AddAcceleration on stored edge t's relation (or on random names), bent by `how`.
  void AddAccelerationOp(const reference::TwistEdge* t) {
    const std::uint32_t how = in_.Below(8);
    const std::uint32_t body_choice = in_.Below(4);
    if (t == nullptr || how == 7) {  // random names: mostly errors
      const std::string point = Frame();
      const std::string body = BodyFor(point);
      const std::string ref_body = Body();
      const std::string coord = TwistCoord(point);
      const Eigen::Vector3d a = AccelerationValue();
      d_.Acceleration(point, body, ref_body, coord, a, AccelerationValue());
      return;
    }
    const reference::TwistEdge edge = *t;
    const std::string H = d_.model().frames().at(edge.head);
    // The point: the head, or a frame of its tree (on any body: the point of H at e).
    const std::string point = how < 3 ? edge.head : FrameNear(edge.head);
    std::string body = body_choice == 0 ? std::string() : H;  // empty: the point's body
    if (body_choice == 3) body = Body();
    std::string ref_body = edge.tail_body;
    if (how == 5) body = edge.tail_body, ref_body = H;  // the inverse relation, against the edge
    if (how == 6) ref_body = Body();
    const std::string coord = TwistCoord(point);
    const Eigen::Vector3d a = AccelerationValue();
    d_.Acceleration(point, body, ref_body, coord, a, AccelerationValue());
  }

  // An acceleration query between bodies of stored edges t1 (the moving body's side) and t2,
  // at a frame of t1's tree; a random one (MakeQuery) when there are no edges or 1 time in 8.
  Query AccelerationQuery(const reference::TwistEdge* t1, const reference::TwistEdge* t2) {
    static const QueryKind kKinds[] = {QueryKind::kTwist, QueryKind::kLinearVelocity,
                                       QueryKind::kAngularVelocity};
    const QueryKind kind = kKinds[in_.Below(3)];
    if (t1 == nullptr || in_.OneIn(8)) return MakeQuery(kind);
    const reference::TwistEdge a = *t1, b = *t2;
    const auto& frames = d_.model().frames();
    Query q;
    q.kind = kind;
    const std::string C = in_.Bool() ? frames.at(a.head) : a.tail_body;
    const std::string D = in_.Bool() ? frames.at(b.head) : b.tail_body;
    q.point = FrameNear(a.head);
    q.body = kind != QueryKind::kAngularVelocity && in_.OneIn(4) ? std::string() : C;
    q.ref_body = D;
    q.coord = in_.Bool() ? q.point : FrameNear(q.point);
    if (kind == QueryKind::kAngularVelocity) q.point.clear();
    return q;
  }

  // A frame of `body` in the model (one of them, by input), or `body` itself as a name. Reads
  // one byte either way (the decoding does not depend on the model's state).
  std::string FrameOfBody(const std::string& body) {
    const std::uint8_t pick = in_.Byte();
    std::vector<std::string> frames;
    for (const auto& [frame, b] : d_.model().frames()) {
      if (b == body) frames.push_back(frame);
    }
    if (frames.empty()) return body;
    return frames[pick % frames.size()];
  }

  void AddPose() {
    const std::string head = Frame();
    const std::string head_body = BodyFor(head);
    const std::string tail = in_.OneIn(16) ? head : Frame();
    const std::string tail_body = BodyFor(tail);
    const RotationInput rotation = Rotation();
    d_.Pose(head, head_body, tail, tail_body, rotation, Position());
  }

  // An existing edge again (tail -> head, or reversed) with its stored value, modified.
  void ReAddPose() {
    const auto& poses = d_.model().poses();
    if (poses.empty()) return AddPose();
    const reference::PoseEdge e = poses[in_.Below(static_cast<std::uint32_t>(poses.size()))];
    const Eigen::Quaterniond q(e.X_TH.R);
    Eigen::Vector3d p = e.X_TH.p;
    RotationInput rotation = AsQuaternion(q);
    switch (in_.Below(8)) {
      case 1:
        rotation = AsQuaternion(Eigen::Quaterniond(-q.coeffs()));
        break;
      case 2:
        rotation = AsMatrix(e.X_TH.R);
        break;
      case 3:
        rotation = ModifyRotation(q, 15, 0);
        p += Eigen::Vector3d::Constant(1e-9);
        break;
      case 4:
        p += Eigen::Vector3d(0.0, 1e-3, 0.0);
        break;
      case 5:
        rotation =
            AsQuaternion(q * Eigen::Quaterniond(Eigen::AngleAxisd(1e-4, Eigen::Vector3d::UnitZ())));
        break;
      case 6:
        rotation = Rotation(), p = Position();
        break;
      case 7:  // the reverse edge
        d_.Pose(e.tail, BodyFor(e.tail), e.head, BodyFor(e.head), AsMatrix(e.X_TH.R.transpose()),
                -(e.X_TH.R.transpose() * e.X_TH.p));
        return;
      default:
        break;
    }
    d_.Pose(e.head, in_.Bool() ? std::string() : d_.model().frames().at(e.head), e.tail,
            in_.Bool() ? std::string() : d_.model().frames().at(e.tail), rotation, p);
  }

  void RemovePose() {
    const auto& poses = d_.model().poses();
    if (!poses.empty() && in_.Bool()) {
      const reference::PoseEdge e = poses[in_.Below(static_cast<std::uint32_t>(poses.size()))];
      if (in_.OneIn(4)) {
        d_.RemovePose(e.tail, e.head);  // the wrong direction: no_such_edge
      } else {
        d_.RemovePose(e.head, e.tail);
      }
      return;
    }
    const std::string of = Frame();
    d_.RemovePose(of, FrameNear(of));
  }

  // The coordinate frame of a twist on `point`: the point's frame, one of its tree, or any.
  std::string TwistCoord(const std::string& point) {
    switch (in_.Below(8)) {
      case 0:
      case 1:
      case 2:
      case 3:
        return point;
      case 7:
        return Frame();
      default:
        return FrameNear(point);
    }
  }

  void AddTwist() {
    const std::string point = Frame();
    const std::string body = BodyFor(point);
    const std::string ref_body = Body();
    const std::string coord = TwistCoord(point);
    const Eigen::Vector3d v = Velocity();
    d_.Twist(point, body, ref_body, coord, v, Velocity());
  }

  void ReAddTwist() {
    const auto& twists = d_.model().twists();
    if (twists.empty()) return AddTwist();
    const reference::TwistEdge t = twists[in_.Below(static_cast<std::uint32_t>(twists.size()))];
    const std::string coord = TwistCoord(t.head);
    const Eigen::Vector3d v = Velocity();
    d_.Twist(t.head, in_.Bool() ? std::string() : d_.model().frames().at(t.head),
             in_.OneIn(4) ? Body() : t.tail_body, coord, v, Velocity());
  }

  void RemoveTwist() {
    const auto& twists = d_.model().twists();
    if (!twists.empty() && in_.Bool()) {
      const reference::TwistEdge t = twists[in_.Below(static_cast<std::uint32_t>(twists.size()))];
      d_.RemoveTwist(t.head, t.tail_body);
      return;
    }
    const std::string point = Frame();
    d_.RemoveTwist(point, Body());
  }

  // ---------------------------------------------------------------- covariances

  // A 6x6 covariance (docs/uncertainty.md §2) from a few bytes: S = s A A^T (symmetric PSD,
  // often rank-deficient) with A's entries from a seeded table and s from 1e-6 to 1e3; then a
  // kind: valid as is, zero, asymmetric by 1e-12 (within the tolerance: accepted, stored
  // symmetrized) or by 1e-3 max(1, max|S|) (invalid_covariance), a NaN / Inf / 2e12 entry
  // (invalid_number), a negative eigenvalue (e_k^T S e_k = -c: invalid_covariance). Order and
  // convention from one more byte. No case lands within rounding of a bound.
  reference::CovarianceIn Covariance() {
    static const double kScales[] = {1e-6, 1e-2, 1.0, 1e3};
    const std::uint32_t seed = in_.Byte();
    const double scale = kScales[in_.Below(4)];
    Eigen::Matrix<double, 6, 6> A;
    for (int i = 0; i < 36; ++i) {
      const std::uint32_t h = (seed * 2654435761u + static_cast<std::uint32_t>(i) * 40503u) >> 7;
      A(i / 6, i % 6) = (h % 5 == 0) ? 0.0 : static_cast<double>(static_cast<int>(h % 17) - 8) / 8;
    }
    reference::CovarianceIn c;
    c.S = scale * A * A.transpose();
    c.S = 0.5 * (c.S + c.S.transpose());
    const std::uint32_t kind = in_.Byte();
    const int i = static_cast<int>((kind >> 3) % 6), j = static_cast<int>((kind >> 5) % 6);
    const double big = 1e-3 * std::max(1.0, c.S.cwiseAbs().maxCoeff());
    switch (kind % 8) {
      case 3:
        c.S.setZero();
        break;
      case 4:
        if (i != j) c.S(i, j) += (kind & 0x80) ? big : 1e-12;
        break;
      case 5: {
        static const double kBad[] = {std::numeric_limits<double>::quiet_NaN(),
                                      std::numeric_limits<double>::infinity(),
                                      -std::numeric_limits<double>::infinity(), 2e12};
        c.S(i, j) = kBad[(kind >> 1) % 4];
        break;
      }
      case 6:
        c.S(i, i) = -big;  // the rest of row and column i kept: e_i^T S e_i = -big
        break;
      default:
        break;
    }
    const std::uint8_t form = in_.Byte();
    c.angular_linear = (form & 1u) != 0;
    c.body = (form & 6u) == 6u;  // 1 in 4 (a twist then: invalid_covariance)
    return c;
  }

  // Op 17: an add with a covariance: a new pose edge, an existing one restated or updated (a
  // constant one with the same covariance: accepted; another: constant_pose_change), a twist,
  // an existing twist edge updated (in its frame or converted from another).
  void WithCovariance() {
    const std::uint32_t which = in_.Below(6);
    const auto& poses = d_.model().poses();
    const auto& twists = d_.model().twists();
    if (which == 2 && !poses.empty()) {
      const reference::PoseEdge e = poses[in_.Below(static_cast<std::uint32_t>(poses.size()))];
      reference::CovarianceIn c;
      c.S = e.S;  // the stored one (edge form): a restatement, or changed by 1e-6 relative
      if (in_.Bool()) c.S(0, 0) += 1e-6 * std::max(1.0, e.S.cwiseAbs().maxCoeff());
      if (in_.Bool()) c = Covariance();
      const std::string head_body = BodyFor(e.head), tail_body = BodyFor(e.tail);
      d_.Pose(e.head, head_body, e.tail, tail_body, AsQuaternion(Eigen::Quaterniond(e.X_TH.R)),
              e.X_TH.p, &c);
      return;
    }
    if (which == 5 && !twists.empty()) {
      const reference::TwistEdge t = twists[in_.Below(static_cast<std::uint32_t>(twists.size()))];
      const reference::CovarianceIn c = Covariance();
      const std::string coord = TwistCoord(t.head);
      const Eigen::Vector3d v = Velocity();
      const Eigen::Vector3d w = Velocity();
      const std::string body = BodyFor(t.head);  // (read in this order: see Extended)
      d_.Twist(t.head, body, t.tail_body, coord, v, w, &c);
      return;
    }
    if (which < 3) {
      const std::string head = Frame();
      const std::string head_body = BodyFor(head);
      const std::string tail = Frame();
      const std::string tail_body = BodyFor(tail);
      const RotationInput rotation = Rotation();
      const Eigen::Vector3d p = Position();
      const reference::CovarianceIn c = Covariance();
      d_.Pose(head, head_body, tail, tail_body, rotation, p, &c);
      return;
    }
    const std::string point = Frame();
    const std::string body = BodyFor(point);
    const std::string ref_body = Body();
    const std::string coord = TwistCoord(point);
    const Eigen::Vector3d v = Velocity();
    const Eigen::Vector3d w = Velocity();
    const reference::CovarianceIn c = Covariance();
    d_.Twist(point, body, ref_body, coord, v, w, &c);
  }

  // ---------------------------------------------------------------- extended ops (one more byte)

  void Extended() {
    switch (in_.Byte() % 12) {
      case 0:
        RepairPose();
        break;
      case 1:
        RepairPoseConflict();
        break;
      case 2:
        RepairPoseDetermined();
        break;
      case 3:
        RepairTwist();
        break;
      case 4:
        AddJoint();
        break;
      case 5:
        SetJoints();
        break;
      case 6:
        Group();
        break;
      case 7:
        d_.AskJacobian(JacobianQuery());
        break;
      case 8:
        StampedPose();
        break;
      case 9:
        StampedTwist();
        break;
      default: {
        const Query q = TimedQuery();  // (reads in this order: a function's arguments have none)
        d_.AskTimed(q, TimePolicy());
        break;
      }
    }
  }

  // ---------------------------------------------------------------- time

  // Stamps (ns): around 1-3 s, a nanosecond apart, far ahead (beyond the 10 s window of the
  // first ones) and negative.
  std::int64_t StampChoice() {
    static const std::int64_t kStamps[] = {1000000000,  1500000000, 2000000000, 2500000000,
                                           3000000000,  1000000001, 1250000000, 12000000000,
                                           -1000000000, 0,          2000000000, 3000000000,
                                           1750000000,  4000000000, 2000000001, 500000000};
    return kStamps[in_.Below(16)];
  }

  // The next sample's stamp after an edge's newest: in order (0.5 s, 1 ns later), the same
  // stamp (a duplicate), out of order, beyond the window (12 s), or from the table.
  std::int64_t NextStamp(std::int64_t newest) {
    switch (in_.Below(8)) {
      case 0:
      case 1:
        return newest + 500000000;
      case 2:
        return newest + 1;
      case 3:
        return newest;
      case 4:
        return newest - 250000000;
      case 5:
        return newest + 12000000000;
      case 6:
        return newest + 300000000;
      default:
        return StampChoice();
    }
  }

  // A query time relative to a stamped edge's samples: at one, between two, just outside.
  std::int64_t TimeNear(const std::vector<std::int64_t>& stamps) {
    const std::int64_t a = stamps[in_.Below(static_cast<std::uint32_t>(stamps.size()))];
    const std::int64_t b = stamps[in_.Below(static_cast<std::uint32_t>(stamps.size()))];
    switch (in_.Below(6)) {
      case 0:
        return a;
      case 1:
        return a + (b - a) / 4;
      case 2:
        return a + (b - a) / 2;
      case 3:
        return stamps.back() + 200000000;
      case 4:
        return stamps.front() - 100000000;
      default:
        return a + 1;
    }
  }

  // A query through a stamped edge (a pose across it, or a twist at its head), or any query.
  Query TimedQuery() {
    struct Focus {
      std::string head, tail;
      std::vector<std::int64_t> stamps;
    };
    std::vector<Focus> edges;
    for (const reference::PoseEdge& e : d_.model().poses()) {
      if (!e.stamped) continue;
      edges.push_back({e.head, e.tail, {}});
      for (const reference::PoseSample& x : e.samples) edges.back().stamps.push_back(x.t);
    }
    for (const reference::TwistEdge& t : d_.model().twists()) {
      if (!t.stamped) continue;
      edges.push_back({t.head, std::string(), {}});
      for (const reference::TwistSample& x : t.samples) edges.back().stamps.push_back(x.t);
    }
    focus_stamps_.clear();
    if (edges.empty() || in_.OneIn(4)) return MakeQuery(static_cast<QueryKind>(in_.Below(6)));
    const Focus& focus = edges[in_.Below(static_cast<std::uint32_t>(edges.size()))];
    focus_stamps_ = focus.stamps;  // TimePolicy picks times around these
    const std::string& head = focus.head;
    Query q;
    q.kind = static_cast<QueryKind>(in_.Below(6));
    q.point = q.orientation = head;
    q.ref_point = q.ref_orientation =
        !focus.tail.empty() && in_.Bool() ? focus.tail : FrameNear(head);
    q.coord = in_.Bool() ? q.ref_orientation : FrameNear(head);
    if (q.kind == QueryKind::kTwist || q.kind == QueryKind::kLinearVelocity ||
        q.kind == QueryKind::kAngularVelocity) {
      q.body = d_.model().frames().at(head);
      q.ref_body = Body();
      for (const reference::TwistEdge& t : d_.model().twists()) {
        if (t.head == head && in_.Bool()) q.ref_body = t.tail_body;
      }
      if (q.kind == QueryKind::kAngularVelocity) q.point.clear();
    }
    if (q.kind == QueryKind::kPosition) q.orientation.clear(), q.ref_orientation.clear();
    if (q.kind == QueryKind::kOrientation) q.point.clear(), q.ref_point.clear();
    return q;
  }

  reference::TimeQuery TimePolicy() {
    static const std::int64_t kTimes[] = {1000000000, 1250000000,  1750000000, 2000000000,
                                          3500000000, 12000000000, 0,          2600000000};
    static const std::int64_t kHorizons[] = {0, 0, 0, 500000000, 2000000000, -1, 0, 100000000};
    reference::TimeQuery p;
    switch (in_.Below(4)) {
      case 0:
        p.kind = reference::TimeQuery::Kind::kLatest;
        break;
      case 1:
        p.kind = reference::TimeQuery::Kind::kLatestCommon;
        break;
      default: {
        p.kind = reference::TimeQuery::Kind::kAt;
        std::vector<std::vector<std::int64_t>> histories;
        if (!focus_stamps_.empty() && !in_.OneIn(4)) histories.push_back(focus_stamps_);
        for (const reference::PoseEdge& e : d_.model().poses()) {
          if (e.stamped) histories.emplace_back();
          for (const reference::PoseSample& x : e.samples) histories.back().push_back(x.t);
        }
        for (const reference::TwistEdge& e : d_.model().twists()) {
          if (e.stamped) histories.emplace_back();
          for (const reference::TwistSample& x : e.samples) histories.back().push_back(x.t);
        }
        if (!histories.empty() && !in_.OneIn(4)) {
          p.t = TimeNear(histories[focus_stamps_.empty()
                                       ? in_.Below(static_cast<std::uint32_t>(histories.size()))
                                       : 0]);
        } else {
          p.t = in_.OneIn(3) ? StampChoice() : kTimes[in_.Below(8)];
        }
        p.horizon = kHorizons[in_.Below(8)];
        break;
      }
    }
    if (in_.OneIn(4)) p.not_before = StampChoice();
    return p;
  }

  // A stamped sample: mostly of an existing edge (its next sample), else a new edge.
  void StampedPose() {
    const auto& poses = d_.model().poses();
    const std::int64_t stamp = StampChoice();
    std::vector<const reference::PoseEdge*> stamped;  // mostly a stamped edge's next sample
    for (const reference::PoseEdge& x : poses) {
      if (x.stamped) stamped.push_back(&x);
    }
    if (poses.empty() || (stamped.empty() ? !in_.OneIn(4) : in_.OneIn(4))) {
      const std::string head = Frame();
      const std::string head_body = BodyFor(head);
      const std::string tail = Frame();
      const std::string tail_body = BodyFor(tail);
      const RotationInput rotation = Rotation();
      const Eigen::Vector3d p = Position();
      d_.StampedPose(head, head_body, tail, tail_body, rotation, p, stamp);
      return;
    }
    const reference::PoseEdge e =
        !stamped.empty() && !in_.OneIn(4)
            ? *stamped[in_.Below(static_cast<std::uint32_t>(stamped.size()))]
            : poses[in_.Below(static_cast<std::uint32_t>(poses.size()))];
    const std::int64_t next = e.stamped ? NextStamp(e.samples.back().t) : stamp;
    RotationInput rotation = AsQuaternion(Eigen::Quaterniond(e.X_TH.R));
    Eigen::Vector3d p = e.X_TH.p;
    switch (in_.Below(6)) {
      case 0:
        break;  // the same value (a no-op at an existing stamp)
      case 1:
        p += Eigen::Vector3d(0.1, -0.05, 0.02);
        break;
      case 2:
        rotation = AsQuaternion(rotation.q * Rpy(0.05, 0.3, -0.2));
        break;
      case 3:
        rotation = AsQuaternion(rotation.q * Rpy(0.0, 0.0, 2.0)),
        p += Eigen::Vector3d(0.0, 0.3, 0.0);
        break;
      default:
        rotation = Rotation(), p = Position();
        break;
    }
    d_.StampedPose(e.head, in_.Bool() ? std::string() : d_.model().frames().at(e.head), e.tail,
                   std::string(), rotation, p, next);
  }

  void StampedTwist() {
    const auto& twists = d_.model().twists();
    const std::int64_t stamp = StampChoice();
    std::vector<const reference::TwistEdge*> stamped;
    for (const reference::TwistEdge& x : twists) {
      if (x.stamped) stamped.push_back(&x);
    }
    if (twists.empty() || (stamped.empty() ? !in_.OneIn(4) : in_.OneIn(4))) {
      const std::string point = Frame();
      const std::string body = BodyFor(point);
      const std::string ref_body = Body();
      const std::string coord = TwistCoord(point);
      const Eigen::Vector3d v = Velocity();
      d_.StampedTwist(point, body, ref_body, coord, v, Velocity(), stamp);
      return;
    }
    const reference::TwistEdge t =
        !stamped.empty() && !in_.OneIn(4)
            ? *stamped[in_.Below(static_cast<std::uint32_t>(stamped.size()))]
            : twists[in_.Below(static_cast<std::uint32_t>(twists.size()))];
    const std::string coord = TwistCoord(t.head);
    const Eigen::Vector3d v = Velocity();
    const Eigen::Vector3d w = Velocity();
    d_.StampedTwist(t.head, std::string(), t.tail_body, coord, v, w,
                    t.stamped ? NextStamp(t.samples.back().t) : stamp);
  }

  // ---------------------------------------------------------------- joints

  std::string JointName() {
    const std::uint8_t b = in_.Byte();
    static const char* const kJoints[] = {"j0", "j1", "j2", "j3"};
    return b < 248 ? kJoints[b % 4] : SpecialName(b, true);
  }
  // An existing joint's name (often), else any joint name.
  std::string SomeJoint() {
    const auto& joints = d_.model().joints();
    if (!joints.empty() && !in_.OneIn(4))
      return joints[in_.Below(static_cast<std::uint32_t>(joints.size()))].name;
    return JointName();
  }

  void AddJoint() {
    static const Eigen::Vector3d kAxes[] = {{1, 0, 0},        {0, 1, 0},  {0, 0, 1}, {1, 1, 0},
                                            {0.3, -0.2, 0.9}, {0, 0, -2}, {0, 0, 0}, {1e-13, 0, 0}};
    static const double kLimits[][2] = {{-1, 1}, {-3.2, 3.2},  {0, 0.5}, {0.2, 1.0},
                                        {1, -1}, {-0.5, -0.1}, {0, 0},   {-2, 2}};
    static const double kMultipliers[] = {1, -1, 0.5, 2, kNaN, 1, -0.25, 3};
    static const double kOffsets[] = {0, 0.1, -0.3, 0.25, 0, 0.1, -1.0, kInf};
    reference::JointInput in;
    in.name = JointName();
    in.type = static_cast<reference::JointType>(in_.Below(4));
    // The parent: often an existing joint's child (chains), else any frame.
    const auto& joints = d_.model().joints();
    in.parent = !joints.empty() && in_.Bool()
                    ? joints[in_.Below(static_cast<std::uint32_t>(joints.size()))].child
                    : Frame();
    in.parent_body = BodyFor(in.parent);
    in.child = in_.OneIn(16) ? in.parent : Frame();
    in.child_body = BodyFor(in.child);
    const std::uint8_t rotation = in_.Byte();
    in.q_origin = Rotations()[rotation % 8];
    if (rotation >= 224) {  // an invalid or non-unit origin now and then
      const RotationInput r = ModifyRotation(in.q_origin, rotation >> 2, rotation);
      in.q_origin = r.is_matrix ? Eigen::Quaterniond(r.R) : r.q;
    }
    in.p_origin = in_.OneIn(16) ? Position() : kPositions[in_.Below(6)];  // mostly finite
    in.axis = kAxes[in_.Below(8)];
    if (in_.OneIn(32)) in.axis.y() = kNaN;
    if (in_.OneIn(32)) in.lower = kNaN;
    const auto& limits = kLimits[in_.Below(8)];
    in.lower = limits[0];
    in.upper = limits[1];
    if (in_.OneIn(4)) {
      in.mimic = SomeJoint();
      in.multiplier = kMultipliers[in_.Below(8)];
      in.offset = kOffsets[in_.Below(8)];
    }
    d_.Joint(in);
  }

  // A joint value: near the joint's limits (inside, at the slack, outside) or from a table.
  double JointValueFor(const std::string& name) {
    static const double kValues[] = {0, 0.5, -0.7, 1.0, 3.0, -2.5, kNaN, kInf};
    const reference::Joint* j = nullptr;
    for (const reference::Joint& x : d_.model().joints()) {
      if (x.name == name) j = &x;
    }
    const std::uint8_t b = in_.Byte();
    if (!j || b < 128) return kValues[b % 8];
    switch (b % 8) {
      case 0:
        return j->lower;
      case 1:
        return j->upper;
      case 2:
        return j->upper + 5e-10;  // within the slack: accepted as given
      case 3:
        return j->upper + 2e-9;  // outside: joint_limit
      case 4:
        return j->lower - 2e-9;
      case 5:
        return 0.5 * (j->lower + j->upper);
      case 6:
        return j->lower + 0.3 * (j->upper - j->lower);
      default:
        return 40.0 + j->q;  // a wheel that turned (continuous)
    }
  }

  void SetJoints() {
    typename Differential<B>::JointValues positions, velocities;
    for (std::uint32_t n = in_.Below(4); n > 0; --n) {
      const std::string name = SomeJoint();
      positions.emplace_back(name, JointValueFor(name));
    }
    for (std::uint32_t n = in_.Below(3); n > 0; --n) {
      const std::string name = SomeJoint();
      velocities.emplace_back(name, JointValueFor(name));
    }
    typename Differential<B>::JointValues accelerations;  // q'': none most of the time
    for (std::uint32_t n = in_.OneIn(3) ? in_.Below(3) + 1 : 0; n > 0; --n) {
      const std::string name = SomeJoint();
      accelerations.emplace_back(name, JointValueFor(name));
    }
    d_.SetJoints(positions, velocities, accelerations);
  }

  // MakeJointGroup (names of existing joints, mostly) or a real-time set of the kept group.
  void Group() {
    if (in_.OneIn(3)) {
      std::vector<std::string> names;
      for (std::uint32_t n = 1 + in_.Below(4); n > 0; --n) names.push_back(SomeJoint());
      d_.MakeGroup(names);
      return;
    }
    const int which = static_cast<int>(in_.Below(3));
    if (!d_.has_group()) return;
    std::vector<double> values;
    for (const std::string& name : d_.GroupJoints()) {
      values.push_back(JointValueFor(name));
      values.push_back(JointValueFor(std::string()));  // a velocity from the table
    }
    d_.SetGroup(which, values);
  }

  // A twist query's arguments, pointed at joint children and parent bodies.
  Query JacobianQuery() {
    Query q = MakeQuery(QueryKind::kTwist);
    const auto& joints = d_.model().joints();
    if (!joints.empty() && in_.Bool()) {
      const reference::Joint& j = joints[in_.Below(static_cast<std::uint32_t>(joints.size()))];
      q.point = j.child;
      q.coord = FrameNear(j.child);
      const reference::Joint& k = joints[in_.Below(static_cast<std::uint32_t>(joints.size()))];
      q.ref_body = k.parent_body;
    }
    return q;
  }

  // A repair policy: the default most often, a strategy switched off, or another tolerance
  // (0, 1e-12: the rounding of a derived value decides; 1e-3: the 1e-3 changes sit on it).
  reference::RepairPolicy Policy() {
    reference::RepairPolicy p;
    const std::uint8_t b = in_.Byte();
    if (b < 160) return p;
    switch (b % 8) {
      case 0:
        p.invert = false;
        break;
      case 1:
        p.reroot = false;
        break;
      case 2:
        p.check_consistency = false;
        break;
      case 3:
        p.position_tolerance = p.angle_tolerance = 0.0;
        break;
      case 4:
        p.position_tolerance = p.angle_tolerance = 1e-12;
        break;
      case 5:
        p.position_tolerance = 1e-6, p.angle_tolerance = 2e-4;
        break;
      case 6:
        p.position_tolerance = p.angle_tolerance = 1e-3;
        break;
      default:
        p.position_tolerance = 2e-3, p.angle_tolerance = 1e-9;
        break;
    }
    return p;
  }

  // The repairing AddPose takes a quaternion: a matrix choice is passed as its quaternion.
  Eigen::Quaterniond QuaternionChoice() {
    const RotationInput r = Rotation();
    return r.is_matrix ? Eigen::Quaterniond(r.R) : r.q;
  }

  void RepairPose() {
    const std::string head = Frame();
    const std::string head_body = BodyFor(head);
    const std::string tail = in_.OneIn(16) ? head : FrameNear(head);
    const std::string tail_body = BodyFor(tail);
    const Eigen::Quaterniond q = QuaternionChoice();
    const Eigen::Vector3d p = Position();
    d_.PoseRepair(head, head_body, tail, tail_body, q, p, Policy());
  }

  // A frame that has a pose parent, posed wrt another frame: P1 -> invert (or re-root when the
  // other frame has a parent too), or a consistency check when both are in one tree.
  void RepairPoseConflict() {
    const auto& poses = d_.model().poses();
    if (poses.empty()) return RepairPose();
    const reference::PoseEdge e = poses[in_.Below(static_cast<std::uint32_t>(poses.size()))];
    const std::string tail = Frame();
    const Eigen::Quaterniond q = QuaternionChoice();
    const std::string head_body = in_.Bool() ? std::string() : d_.model().frames().at(e.head);
    const std::string tail_body = BodyFor(tail);
    const Eigen::Vector3d p = Position();
    d_.PoseRepair(e.head, head_body, tail, tail_body, q, p, Policy());
  }

  // A relation the graph already determines (both frames in one tree), with the derived value
  // exactly, or changed within / outside the tolerance.
  void RepairPoseDetermined() {
    const std::string head = Frame();
    const std::string tail = FrameNear(head);
    Query query;
    query.kind = QueryKind::kPose;
    query.point = query.orientation = head;
    query.ref_point = query.ref_orientation = query.coord = tail;
    const Answer derived = d_.model().Ask(query);
    if (derived.code != ErrorCode::kOk) return RepairPose();
    Eigen::Quaterniond q(derived.M);
    Eigen::Vector3d p = derived.p;
    switch (in_.Below(8)) {
      case 1:
        q = Eigen::Quaterniond(-q.coeffs());
        break;
      case 2:
        p += Eigen::Vector3d::Constant(1e-10);
        break;
      case 3:
        p += Eigen::Vector3d(0.0, 1e-3, 0.0);
        break;
      case 4:
        q = q * Eigen::Quaterniond(Eigen::AngleAxisd(1e-10, Eigen::Vector3d::UnitY()));
        break;
      case 5:
        q = q * Eigen::Quaterniond(Eigen::AngleAxisd(1e-4, Eigen::Vector3d::UnitZ()));
        break;
      case 6:
        q = QuaternionChoice(), p = Position();
        break;
      default:
        break;
    }
    const std::string head_body = BodyFor(head);
    const std::string tail_body = BodyFor(tail);
    d_.PoseRepair(head, head_body, tail, tail_body, q, p, Policy());
  }

  // A twist on a point that has a twist parent, wrt another body (W1 -> the inverse twist), or
  // a twist the graph already derives (W3 -> consistency), exact or changed.
  void RepairTwist() {
    const auto& twists = d_.model().twists();
    std::string point = Frame(), ref_body = Body();
    if (!twists.empty()) {
      const reference::TwistEdge& t = twists[in_.Below(static_cast<std::uint32_t>(twists.size()))];
      switch (in_.Below(4)) {
        case 0:
          point = t.head;
          break;  // W1 when ref_body is another body
        case 1:
        case 2: {  // a frame of t's tree, wrt a body t's edge joins: mostly W3
          point = FrameNear(t.head);
          const auto it = d_.model().frames().find(point);
          const std::string& H = d_.model().frames().at(t.head);
          ref_body = it != d_.model().frames().end() && it->second == t.tail_body ? H : t.tail_body;
          break;
        }
        default:
          break;
      }
    }
    const std::string body = BodyFor(point);
    const std::string coord = TwistCoord(point);
    Query query;
    query.kind = QueryKind::kTwist;
    query.point = point;
    query.ref_body = ref_body;
    query.coord = coord;
    const Answer derived = d_.model().Ask(query);
    Eigen::Vector3d v = derived.v, w = derived.w;
    switch (derived.code == ErrorCode::kOk ? in_.Below(6) : 5) {
      case 1:
        v += Eigen::Vector3d(1e-10, 0.0, 0.0);
        break;
      case 2:
        w += Eigen::Vector3d(0.0, 0.0, 1e-3);
        break;
      case 3:
        v += Eigen::Vector3d(0.0, 2e-3, 0.0);
        break;
      case 4:
      case 5:
        v = Velocity(), w = Velocity();
        break;
      default:
        break;
    }
    d_.TwistRepair(point, body, ref_body, coord, v, w, Policy());
  }

  Query MakeQuery(QueryKind kind) {
    Query q;
    q.kind = kind;
    switch (kind) {
      case QueryKind::kPose:
        q.orientation = Frame();
        q.point = in_.Bool() ? q.orientation : FrameNear(q.orientation);
        q.body = BodyFor(q.orientation);
        q.ref_orientation = FrameNear(q.orientation);
        q.ref_point = in_.Bool() ? q.ref_orientation : FrameNear(q.ref_orientation);
        q.ref_body = BodyFor(q.ref_orientation);
        q.coord = in_.Bool() ? q.ref_orientation : FrameNear(q.ref_orientation);
        break;
      case QueryKind::kPosition:
        q.point = Frame();
        q.body = BodyFor(q.point);
        q.ref_point = FrameNear(q.point);
        q.ref_body = BodyFor(q.ref_point);
        q.coord = in_.Bool() ? q.ref_point : FrameNear(q.ref_point);
        break;
      case QueryKind::kOrientation:
        q.orientation = Frame();
        q.body = BodyFor(q.orientation);
        q.ref_orientation = FrameNear(q.orientation);
        q.ref_body = BodyFor(q.ref_orientation);
        q.coord = in_.Bool() ? q.ref_orientation : FrameNear(q.ref_orientation);
        break;
      case QueryKind::kAngularVelocity:
        q.coord = Frame();
        q.body = in_.OneIn(8) ? std::string() : Body();
        q.ref_body = Body();
        break;
      default:
        q.point = Frame();
        q.body = in_.Bool() ? std::string() : Body();
        q.ref_body = Body();
        q.coord = in_.Bool() ? q.point : FrameNear(q.point);
        break;
    }
    return q;
  }

  OpReader in_;
  Differential<B> d_;
  std::vector<std::int64_t> focus_stamps_;  // the stamps of the edge the last timed query crosses
};

}  // namespace
}  // namespace semgraph::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool homogeneous = (data[0] & 1u) != 0;
  semgraph::reference::TimeOptions time;  // bits 1-3: the graph's time options
  time.linear = (data[0] & 2u) != 0;
  time.reject_duplicates = (data[0] & 4u) != 0;
  if (data[0] & 8u) time.window_ns = 1000000000, time.capacity = 3;  // 1 s, 3 samples: pruning
  semgraph::fuzz::Fuzzer<semgraph::coord::QuaternionBackend>(data + 1, size - 1, time).Run();
  if (homogeneous)
    semgraph::fuzz::Fuzzer<semgraph::coord::HomogeneousBackend>(data + 1, size - 1, time).Run();
  return 0;
}
