// scene_script_fuzzer: the scene-script reader and runner (tools/semgraph, docs/scene-script.md)
// on arbitrary bytes, in memory. Must never crash, hang or leak; a malformed script must give
// the exit-2 result and a located error; a well-formed script must run.
//
// Input format: byte 0 chooses the mode, the rest is its input (support/op_reader.h).
//   mode 0 (byte 0 even)  raw: the rest is the script text. Whatever ReadScript() says is
//                         checked for consistency: an error has a 1-based line/column inside the
//                         text and a message, and the run's status is 2; a script runs, one JSON
//                         line per op, each shaped {"op": i, "ok": ...}, status 0 or 1 as the
//                         ops succeed.
//   mode 1 (byte 0 odd)   structured: the rest decodes into a WELL-FORMED script (ops of every
//                         kind over bodies A..D and frames a..h, names sometimes empty or with a
//                         control character, numbers sometimes .nan/.inf, rotations in every
//                         form) that ReadScript() must accept. It is run twice, through the tool
//                         (ApplyOp) and directly through the SceneGraph API, and each op's
//                         ok/error code and query numbers must agree. Then one MALFORMED variant
//                         (unknown op, missing or mistyped field, wrong array length, a field of
//                         another op, two rotation forms, unknown representation, broken YAML,
//                         ...) is spliced in at a decoded position and must give status 2.
//                         Time (docs/scene-script.md, Time): a `time` map sometimes (mode,
//                         duplicate policy, window), stamps on pose and twist ops (sometimes
//                         NaN or out of range), and on queries `at` (a time or latest_common),
//                         `max_extrapolation` (sometimes negative), `not_before`, time travel
//                         (`ref_at` + `fixed`) and `source`; the API side makes the same timed
//                         calls, and the time keys printed ("time", "ref_time", "oldest",
//                         "newest", "extrapolated") must equal its TimeReport. Misplaced and
//                         malformed time fields are among the malformed variants.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "semgraph/base/error_code.h"
#include "semgraph/core/scene_graph.h"
#include "semgraph/core/scene_graph_debug.h"
#include "semgraph/script_reader.h"
#include "semgraph/script_runner.h"
#include "support/op_reader.h"

namespace semgraph::fuzz {
namespace {

using script::ReadScript;
using script::Representation;

constexpr int kExitOk = 0, kExitOpFailed = 1, kExitMalformed = 2;

[[noreturn]] void Fail(const std::string& why, std::string_view script) {
  std::fprintf(
      stderr, "\n==== scene_script_fuzzer FAILED ====\n%s\n---- script ----\n%.*s\n==== end ====\n",
      why.c_str(), static_cast<int>(script.size()), script.data());
  std::fflush(stderr);
  std::abort();
}

// `semgraph run` in memory: the exit status, and the JSON lines in *lines.
int RunScript(std::string_view text, std::vector<script::OpOutcome>* lines) {
  const auto script = ReadScript(text);
  if (!script) {
    const script::ScriptError& e = script.error();
    if (e.location.line < 1 || e.location.column < 1 || e.message.empty()) {
      Fail("a script error without a 1-based location or a message: " + e.message, text);
    }
    const std::string formatted = script::FormatScriptError("fuzz.yaml", e);
    if (formatted.rfind("fuzz.yaml:" + std::to_string(e.location.line) + ":", 0) != 0) {
      Fail("FormatScriptError does not start with FILE:LINE: " + formatted, text);
    }
    return kExitMalformed;
  }
  bool all_ok = true;
  const auto run = [&](auto graph) {
    for (std::size_t i = 0; i < script->ops.size(); ++i) {
      script::OpOutcome outcome = script::ApplyOp(graph, script->ops[i], i);
      const std::string head =
          "{\"op\": " + std::to_string(i) + ", \"ok\": " + (outcome.ok ? "true" : "false");
      if (outcome.json.rfind(head, 0) != 0 || outcome.json.back() != '}' ||
          outcome.json.find('\n') != std::string::npos) {
        Fail("op " + std::to_string(i) + " printed a malformed JSON line: " + outcome.json, text);
      }
      all_ok = all_ok && outcome.ok;
      if (lines) lines->push_back(std::move(outcome));
    }
    if (!CheckInvariants(graph).empty()) Fail("CheckInvariants() after the script", text);
  };
  const core::TimeOptions time = script::TimeOptionsOf(script->time);
  if (script->representation == Representation::kHomogeneous) {
    run(*core::SceneGraph<coord::HomogeneousBackend>::Create(time));
  } else {
    run(*core::SceneGraph<coord::QuaternionBackend>::Create(time));
  }
  return all_ok ? kExitOk : kExitOpFailed;
}

// ------------------------------------------------------------------ mode 1: generated scripts

const char* const kBodies[] = {"A", "B", "C", "D"};
const char* const kFrames[] = {"a", "b", "c", "d", "e", "f", "g", "h"};
const double kNumbers[] = {0.0, 1.0, -0.5, 0.2, 0.3, 1.25, -2.0, 0.1};
// Times (seconds): mostly a few stamps apart, sometimes invalid (NaN, beyond 9.2e9 s).
const double kTimes[] = {0.0, 0.1, 0.25, 0.5, 1.0, 0.2, 0.3, 2.0};

// One generated op: its YAML line, and how to apply it directly with the API.
struct GenOp {
  std::string yaml;
  enum Kind { kBody, kFrame, kPose, kTwist, kRemovePose, kRemoveTwist, kQuery } kind = kBody;
  script::QueryKind query = script::QueryKind::kPose;
  std::string s[4];  // names, by kind
  std::string coord;
  int rotation_form = 0;  // 0 none, 1 quaternion, 2 rpy, 3 matrix
  double rot[9] = {};
  double pos[3] = {}, lin[3] = {}, ang[3] = {};
  // Time: the stamp of a pose/twist op; a query's fields (docs/scene-script.md, Time).
  std::optional<double> stamp, at, horizon, not_before, ref_at;
  bool latest_common = false, poses = false;
  std::string fixed;
};

class Generator {
 public:
  explicit Generator(OpReader& in) : in_(in) {}

  std::string Name(const char* const* pool, std::uint32_t n) {
    const std::uint8_t b = in_.Byte();
    if (b >= 250) return b & 1 ? "" : "x\x01y";
    return pool[b % n];
  }
  std::string Frame() { return Name(kFrames, 8); }
  std::string Body() { return Name(kBodies, 4); }
  static std::string Quote(const std::string& s) {
    std::string out = "\"";
    for (unsigned char c : s) {
      char buf[8];
      if (c < 0x20 || c == '"' || c == '\\') {
        std::snprintf(buf, sizeof(buf), "\\x%02x", c);
        out += buf;
      } else {
        out += static_cast<char>(c);
      }
    }
    return out + "\"";
  }
  double Number() {
    const std::uint8_t b = in_.Byte();
    if (b == 255) return std::nan("");
    if (b >= 253) return b == 254 ? INFINITY : -INFINITY;
    return kNumbers[b % 8] * (1 + (b >> 3) % 3);
  }
  static std::string Text(double x) {
    if (std::isnan(x)) return ".nan";
    if (std::isinf(x)) return x > 0 ? ".inf" : "-.inf";
    char buf[40];
    std::snprintf(buf, sizeof(buf), "%.17g", x);
    return buf;
  }
  double Time() {
    const std::uint8_t b = in_.Byte();
    if (b == 255) return std::nan("");
    if (b == 254) return 1e10;  // beyond 9.2e9 s
    return kTimes[b % 8] * (1 + (b >> 3) % 2);
  }
  std::string TimeField(const char* key, std::optional<double>* out) {
    *out = Time();
    return std::string(", ") + key + ": " + Text(**out);
  }
  // The time fields of a query of kind k (each sometimes).
  std::string QueryTime(GenOp& op) {
    std::string y;
    const bool pose_kind = op.query <= script::QueryKind::kOrientation;
    const bool travel = pose_kind && in_.OneIn(4);
    if (travel || in_.OneIn(2)) {
      if (!travel && in_.OneIn(4)) {
        op.latest_common = true;
        y += ", at: latest_common";
      } else {
        y += TimeField("at", &op.at);
      }
    }
    if (travel) {
      y += TimeField("ref_at", &op.ref_at);
      op.fixed = Frame();
      y += ", fixed: " + Quote(op.fixed);
    }
    if (in_.OneIn(3)) {
      op.horizon = in_.OneIn(6) ? -0.1 : Time();
      y += ", max_extrapolation: " + Text(*op.horizon);
    }
    if (in_.OneIn(5)) y += TimeField("not_before", &op.not_before);
    if (!pose_kind && op.query != script::QueryKind::kJacobian && in_.OneIn(3)) {
      op.poses = in_.Bool();
      y += op.poses ? ", source: poses" : ", source: twists";
    }
    return y;
  }
  std::string Stamp(GenOp& op) { return in_.OneIn(2) ? TimeField("stamp", &op.stamp) : ""; }

  std::string Vector(double* v) {
    for (int i = 0; i < 3; ++i) v[i] = Number();
    return "[" + Text(v[0]) + ", " + Text(v[1]) + ", " + Text(v[2]) + "]";
  }

  GenOp Op() {
    GenOp op;
    switch (in_.Below(8)) {
      case 0:
        op.kind = GenOp::kBody;
        op.s[0] = Body();
        op.yaml = "{op: body, name: " + Quote(op.s[0]) + "}";
        break;
      case 1:
        op.kind = GenOp::kFrame;
        op.s[0] = Frame();
        op.s[1] = in_.OneIn(5) ? "" : Body();
        op.yaml = "{op: frame, name: " + Quote(op.s[0]) +
                  (op.s[1].empty() ? "" : ", body: " + Quote(op.s[1])) + "}";
        break;
      case 2:
      case 3: {
        op.kind = GenOp::kPose;
        op.s[0] = Frame(), op.s[1] = in_.Bool() ? Body() : "", op.s[2] = Frame(),
        op.s[3] = in_.Bool() ? Body() : "";
        op.coord = in_.OneIn(4) ? Frame() : "";
        op.yaml = "{op: pose, of: " + Quote(op.s[0]) +
                  (op.s[1].empty() ? "" : ", body: " + Quote(op.s[1])) +
                  ", wrt: " + Quote(op.s[2]) +
                  (op.s[3].empty() ? "" : ", ref_body: " + Quote(op.s[3])) +
                  (op.coord.empty() ? "" : ", coord: " + Quote(op.coord));
        if (in_.Bool()) op.yaml += ", position: " + Vector(op.pos);
        op.rotation_form = static_cast<int>(in_.Below(4));
        if (op.rotation_form == 1) {
          const double* q = Unit(in_.Below(4));
          for (int i = 0; i < 4; ++i) op.rot[i] = in_.OneIn(16) ? Number() : q[i];
          op.yaml += ", rotation: {quaternion: [" + Text(op.rot[0]) + ", " + Text(op.rot[1]) +
                     ", " + Text(op.rot[2]) + ", " + Text(op.rot[3]) + "]}";
        } else if (op.rotation_form == 2) {
          op.yaml += ", rotation: {rpy: " + Vector(op.rot) + "}";
        } else if (op.rotation_form == 3) {
          const double* q = Unit(in_.Below(4));
          const Eigen::Matrix3d R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
          op.yaml += ", rotation: {matrix: [";
          for (int i = 0; i < 3; ++i) {
            op.yaml += std::string(i ? ", [" : "[");
            for (int j = 0; j < 3; ++j) {
              op.rot[3 * i + j] = in_.OneIn(16) ? Number() : R(i, j);
              op.yaml += (j ? ", " : "") + Text(op.rot[3 * i + j]);
            }
            op.yaml += "]";
          }
          op.yaml += "]}";
        }
        op.yaml += Stamp(op) + "}";
        break;
      }
      case 4:
        op.kind = GenOp::kTwist;
        op.s[0] = Frame(), op.s[1] = in_.Bool() ? Body() : "", op.s[2] = Body();
        op.coord = in_.Bool() ? op.s[0] : Frame();
        op.yaml = "{op: twist, point: " + Quote(op.s[0]) +
                  (op.s[1].empty() ? "" : ", body: " + Quote(op.s[1])) +
                  ", ref_body: " + Quote(op.s[2]) + ", coord: " + Quote(op.coord);
        if (in_.Bool()) op.yaml += ", linear: " + Vector(op.lin);
        if (in_.Bool()) op.yaml += ", angular: " + Vector(op.ang);
        op.yaml += Stamp(op) + "}";
        break;
      case 5:
        if (in_.Bool()) {
          op.kind = GenOp::kRemovePose;
          op.s[0] = Frame(), op.s[1] = Frame();
          op.yaml =
              "{op: remove, kind: pose, of: " + Quote(op.s[0]) + ", wrt: " + Quote(op.s[1]) + "}";
        } else {
          op.kind = GenOp::kRemoveTwist;
          op.s[0] = Frame(), op.s[1] = Body();
          op.yaml = "{op: remove, kind: twist, point: " + Quote(op.s[0]) +
                    ", ref_body: " + Quote(op.s[1]) + "}";
        }
        break;
      default: {
        op.kind = GenOp::kQuery;
        op.query = static_cast<script::QueryKind>(in_.Below(7));
        const char* kinds[] = {"pose",    "position",        "orientation",
                               "twist",   "linear_velocity", "angular_velocity",
                               "jacobian"};
        op.yaml = std::string("{op: query, kind: ") + kinds[static_cast<int>(op.query)];
        if (op.query <= script::QueryKind::kOrientation) {
          // of: X, wrt: Y (the shorthand), point/orientation and coord overrides sometimes.
          op.s[0] = Frame(), op.s[1] = Frame();
          op.coord = in_.OneIn(3) ? Frame() : "";
          if (op.query == script::QueryKind::kPose)
            op.yaml += ", of: " + Quote(op.s[0]) + ", wrt: " + Quote(op.s[1]);
          if (op.query == script::QueryKind::kPosition)
            op.yaml += ", point: " + Quote(op.s[0]) + ", ref_point: " + Quote(op.s[1]);
          if (op.query == script::QueryKind::kOrientation) {
            op.yaml += ", orientation: " + Quote(op.s[0]) + ", ref_orientation: " + Quote(op.s[1]);
          }
          // Position and orientation queries have no shorthand: coord is required (it may be
          // the empty name, an op error). Pose queries take it from wrt unless overridden.
          const bool needs_coord = op.query != script::QueryKind::kPose;
          if (needs_coord && op.coord.empty()) op.coord = op.s[1];
          if (needs_coord || !op.coord.empty()) op.yaml += ", coord: " + Quote(op.coord);
        } else {
          op.s[0] = Frame(),
          op.s[1] = in_.Bool() || op.query == script::QueryKind::kAngularVelocity ? Body() : "",
          op.s[2] = Body(), op.coord = Frame();
          if (op.query != script::QueryKind::kAngularVelocity)
            op.yaml += ", point: " + Quote(op.s[0]);
          // The angular velocity has no point to take the body from: body is required there.
          if (!op.s[1].empty() || op.query == script::QueryKind::kAngularVelocity) {
            op.yaml += ", body: " + Quote(op.s[1]);
          }
          op.yaml += ", ref_body: " + Quote(op.s[2]) + ", coord: " + Quote(op.coord);
        }
        op.yaml += QueryTime(op) + "}";
      }
    }
    return op;
  }

 private:
  static const double* Unit(std::uint32_t i) {
    static const double q[4][4] = {
        {1, 0, 0, 0}, {0.5, 0.5, 0.5, 0.5}, {0, 0, 1, 0}, {0.6, 0, 0.8, 0}};
    return q[i % 4];
  }
  OpReader& in_;
};

// The op applied directly: ok, error code and the query's numbers (as the tool prints them).
template <coord::Backend B>
struct Direct {
  bool ok = true;
  base::ErrorCode code = base::ErrorCode::kOk;
  std::vector<double> numbers;
  core::TimeReport time;  // a query's, as the tool must print it

  static Eigen::Vector3d V(const double* v) { return {v[0], v[1], v[2]}; }
  template <class R>
  void Take(const R& r) {
    ok = r.has_value();
    code = ok ? base::ErrorCode::kOk : r.error().code;
  }
  void Push(const Eigen::Vector3d& v) { numbers.insert(numbers.end(), {v.x(), v.y(), v.z()}); }
  void Push(const Eigen::Quaterniond& q) {
    numbers.insert(numbers.end(), {q.w(), q.x(), q.y(), q.z()});
  }

  Direct(core::SceneGraph<B>& g, const GenOp& op) {
    switch (op.kind) {
      case GenOp::kBody:
        Take(g.AddBody(op.s[0]));
        break;
      case GenOp::kFrame:
        Take(g.AddFrame(op.s[0], op.s[1]));
        break;
      case GenOp::kPose: {
        core::PoseSpec spec = core::PoseSpec::Of(op.s[0], op.s[1]).RelativeTo(op.s[2], op.s[3]);
        if (!op.coord.empty()) spec.coordinate_frame = op.coord;
        const Eigen::Vector3d p = V(op.pos);
        std::optional<core::Stamp> st;
        if (op.stamp && !(st = core::StampFromSeconds(*op.stamp))) {
          // An invalid stamp is invalid_number, after invalid_name: the add's order, which a
          // NaN position reproduces without changing anything.
          Take(
              g.AddPose(spec, Eigen::Quaterniond::Identity(), Eigen::Vector3d(std::nan(""), 0, 0)));
          break;
        }
        const auto add = [&](const auto& R) {
          return st ? g.AddPose(spec, R, p, *st) : g.AddPose(spec, R, p);
        };
        if (op.rotation_form == 0) Take(add(Eigen::Quaterniond::Identity()));
        if (op.rotation_form == 1)
          Take(add(Eigen::Quaterniond(op.rot[0], op.rot[1], op.rot[2], op.rot[3])));
        if (op.rotation_form == 2) {
          const Eigen::Quaterniond q = Eigen::AngleAxisd(op.rot[2], Eigen::Vector3d::UnitZ()) *
                                       Eigen::AngleAxisd(op.rot[1], Eigen::Vector3d::UnitY()) *
                                       Eigen::AngleAxisd(op.rot[0], Eigen::Vector3d::UnitX());
          Take(add(q));
        }
        if (op.rotation_form == 3) {
          Eigen::Matrix3d R;
          for (int i = 0; i < 9; ++i) R(i / 3, i % 3) = op.rot[i];
          Take(add(R));
        }
        break;
      }
      case GenOp::kTwist: {
        const core::TwistSpec spec =
            core::TwistSpec::Of(op.s[0], op.s[1]).RelativeTo(op.s[2]).ExpressedIn(op.coord);
        std::optional<core::Stamp> st;
        if (op.stamp && !(st = core::StampFromSeconds(*op.stamp))) {
          Take(g.AddTwist(spec, Eigen::Vector3d(std::nan(""), 0, 0), Eigen::Vector3d::Zero()));
          break;
        }
        Take(st ? g.AddTwist(spec, V(op.lin), V(op.ang), *st)
                : g.AddTwist(spec, V(op.lin), V(op.ang)));
        break;
      }
      case GenOp::kRemovePose:
        Take(g.RemovePose(op.s[0], op.s[1]));
        break;
      case GenOp::kRemoveTwist:
        Take(g.RemoveTwist(op.s[0], op.s[1]));
        break;
      case GenOp::kQuery:
        Query(g, op);
        break;
    }
  }

  // The query's policy from its fields; false when a time is invalid (then the error is
  // invalid_number, after invalid_name).
  static bool PolicyOf(const GenOp& op, core::TimePolicy* policy,
                       std::optional<core::TimeTravel>* travel) {
    const auto ns = [](std::optional<double> x, std::int64_t* out) {
      if (!x) return true;
      const auto v = core::NanosecondsFromSeconds(*x);
      if (v) *out = *v;
      return v.has_value();
    };
    std::int64_t at = 0, ref_at = 0, not_before = 0, horizon = 0;
    if (!ns(op.at, &at) || !ns(op.ref_at, &ref_at) || !ns(op.not_before, &not_before)) return false;
    if (op.horizon && (*op.horizon < 0 || !ns(op.horizon, &horizon))) return false;
    std::optional<core::Stamp> nb;
    if (op.not_before) nb = core::Stamp::Nanoseconds(not_before);
    const core::Duration h = core::Duration::Nanoseconds(horizon);
    if (op.ref_at) {
      travel->emplace(core::Stamp::Nanoseconds(at), core::Stamp::Nanoseconds(ref_at), op.fixed, h,
                      nb);
    } else if (op.at) {
      *policy = core::At{core::Stamp::Nanoseconds(at), h, nb};
    } else if (op.latest_common) {
      *policy = core::LatestCommon{h, nb};
    } else {
      *policy = core::Latest{nb};
    }
    return true;
  }

  void Query(const core::SceneGraph<B>& g, const GenOp& op) {
    core::PoseSpec ps = core::PoseSpec::Of(op.s[0]).RelativeTo(op.s[1]);
    if (!op.coord.empty()) ps.coordinate_frame = op.coord;
    // (string_view on both sides: a std::string temporary here would leave the spec dangling.)
    const std::string_view point = op.query == script::QueryKind::kAngularVelocity
                                       ? std::string_view()
                                       : std::string_view(op.s[0]);
    const core::TwistSpec ts =
        core::TwistSpec::Of(point, op.s[1]).RelativeTo(op.s[2]).ExpressedIn(op.coord);
    core::TimePolicy policy = core::Latest{};
    std::optional<core::TimeTravel> travel;
    if (!PolicyOf(op, &policy, &travel)) {
      // The names first (a time travel's fixed frame among them), then invalid_number.
      const core::At probe{core::Stamp{}, core::Duration::Nanoseconds(-1)};
      const core::TimeTravel travel_probe{core::Stamp{}, core::Stamp{}, op.fixed,
                                          core::Duration::Nanoseconds(-1)};
      const auto pose_probe = [&](auto&& get) {
        if (op.ref_at) {
          Take(get(travel_probe));
        } else {
          Take(get(probe));
        }
      };
      if (op.query == script::QueryKind::kPose) {
        pose_probe([&](const auto& p) { return g.GetPose(ps, p); });
      } else if (op.query == script::QueryKind::kPosition) {
        pose_probe([&](const auto& p) { return g.GetPosition(ps, p); });
      } else if (op.query == script::QueryKind::kOrientation) {
        pose_probe([&](const auto& p) { return g.GetOrientation(ps, p); });
      } else if (op.query == script::QueryKind::kAngularVelocity) {
        Take(g.GetAngularVelocity(ts, probe));
      } else {
        Take(g.GetTwist(ts, probe));
      }
      return;
    }
    const core::TwistSource source =
        op.poses ? core::TwistSource::kPoses : core::TwistSource::kTwists;
    const bool timed =
        op.at || op.latest_common || op.not_before || op.horizon || op.ref_at || op.poses;
    const auto pose_call = [&](auto&& get) { return travel ? get(*travel) : get(policy); };
    switch (op.query) {
      case script::QueryKind::kPose: {
        const auto r = pose_call([&](const auto& t) { return g.GetPose(ps, t); });
        Take(r);
        if (ok)
          Push(B::TranslationOf(r->value.value)),
              Push(B::ToQuaternion(B::RotationOf(r->value.value))), time = r->time;
        break;
      }
      case script::QueryKind::kPosition: {
        const auto r = pose_call([&](const auto& t) { return g.GetPosition(ps, t); });
        Take(r);
        if (ok) Push(r->value.value), time = r->time;
        break;
      }
      case script::QueryKind::kOrientation: {
        const auto r = pose_call([&](const auto& t) { return g.GetOrientation(ps, t); });
        Take(r);
        if (ok) Push(B::ToQuaternion(r->value.value)), time = r->time;
        break;
      }
      case script::QueryKind::kTwist: {
        const auto r = g.GetTwist(ts, policy, source);
        Take(r);
        if (ok) Push(r->value.linear), Push(r->value.angular), time = r->time;
        break;
      }
      case script::QueryKind::kLinearVelocity: {
        const auto r = g.GetLinearVelocity(ts, policy, source);
        Take(r);
        if (ok) Push(r->value.value), time = r->time;
        break;
      }
      case script::QueryKind::kAngularVelocity: {
        const auto r = g.GetAngularVelocity(ts, policy, source);
        Take(r);
        if (ok) Push(r->value.value), time = r->time;
        break;
      }
      case script::QueryKind::kJacobian: {  // the script prints the rows in order (v, then w)
        const auto r = g.GetJacobian(ts, policy);
        Take(r);
        for (Eigen::Index row = 0; ok && row < 6; ++row) {
          for (Eigen::Index c = 0; c < r->value.J.cols(); ++c)
            numbers.push_back(r->value.J(row, c));
        }
        if (ok) time = r->time;
        break;
      }
      case script::QueryKind::kWrench:  // not generated (Below(7)): wrenches are not fuzzed yet
      case script::QueryKind::kForce:
      case script::QueryKind::kMoment:
      case script::QueryKind::kAcceleration:  // nor accelerations
      case script::QueryKind::kLinearAcceleration:
      case script::QueryKind::kAngularAcceleration:
        break;
    }
    if (!timed && op.query != script::QueryKind::kJacobian) Untimed(g, op, ps, ts);
  }

  // A query without time fields: the untimed API must give the same code and numbers as the
  // timed one at the latest samples (the tool calls the timed one).
  void Untimed(const core::SceneGraph<B>& g, const GenOp& op, const core::PoseSpec& ps,
               const core::TwistSpec& ts) {
    Direct u;
    switch (op.query) {
      case script::QueryKind::kPose: {
        const auto r = g.GetPose(ps);
        u.Take(r);
        if (u.ok)
          u.Push(B::TranslationOf(r->value)), u.Push(B::ToQuaternion(B::RotationOf(r->value)));
        break;
      }
      case script::QueryKind::kPosition: {
        const auto r = g.GetPosition(ps);
        u.Take(r);
        if (u.ok) u.Push(r->value);
        break;
      }
      case script::QueryKind::kOrientation: {
        const auto r = g.GetOrientation(ps);
        u.Take(r);
        if (u.ok) u.Push(B::ToQuaternion(r->value));
        break;
      }
      case script::QueryKind::kTwist: {
        const auto r = g.GetTwist(ts);
        u.Take(r);
        if (u.ok) u.Push(r->linear), u.Push(r->angular);
        break;
      }
      case script::QueryKind::kLinearVelocity: {
        const auto r = g.GetLinearVelocity(ts);
        u.Take(r);
        if (u.ok) u.Push(r->value);
        break;
      }
      case script::QueryKind::kAngularVelocity: {
        const auto r = g.GetAngularVelocity(ts);
        u.Take(r);
        if (u.ok) u.Push(r->value);
        break;
      }
      case script::QueryKind::kJacobian:
      case script::QueryKind::kWrench:  // not generated
      case script::QueryKind::kForce:
      case script::QueryKind::kMoment:
      case script::QueryKind::kAcceleration:
      case script::QueryKind::kLinearAcceleration:
      case script::QueryKind::kAngularAcceleration:
        return;
    }
    untimed_differs = u.code != code || u.numbers.size() != numbers.size();
    for (std::size_t k = 0; !untimed_differs && k < numbers.size(); ++k) {
      untimed_differs =
          std::abs(u.numbers[k] - numbers[k]) > 1e-9 * std::max(1.0, std::abs(numbers[k]));
    }
  }
  bool untimed_differs = false;
  Direct() = default;
};

// The numbers of a JSON line, in order of appearance inside [...] arrays.
std::vector<double> JsonArrayNumbers(const std::string& json) {
  std::vector<double> out;
  bool in_array = false;
  for (std::size_t i = 0; i < json.size(); ++i) {
    if (json[i] == '"') {  // skip strings (messages may contain brackets)
      for (++i; i < json.size() && json[i] != '"'; ++i) {
        if (json[i] == '\\') ++i;
      }
      continue;
    }
    if (json[i] == '[') in_array = true;
    if (json[i] == ']') in_array = false;
    if (in_array && (json[i] == '-' || (json[i] >= '0' && json[i] <= '9'))) {
      char* end = nullptr;
      out.push_back(std::strtod(json.c_str() + i, &end));
      i = static_cast<std::size_t>(end - json.c_str()) - 1;
    }
  }
  return out;
}

// The number after "key": at the top level of a JSON line (nullopt when the key is absent).
std::optional<double> JsonKeyNumber(const std::string& json, const std::string& key) {
  const std::string k = "\"" + key + "\": ";
  const std::size_t at = json.find(k);
  if (at == std::string::npos) return std::nullopt;
  return std::strtod(json.c_str() + at + k.size(), nullptr);
}

std::string JsonErrorCode(const std::string& json) {
  const std::string key = "\"error\": \"";
  const std::size_t at = json.find(key);
  if (at == std::string::npos) return "";
  const std::size_t end = json.find('"', at + key.size());
  return json.substr(at + key.size(), end - at - key.size());
}

template <coord::Backend B>
void CompareWithApi(const std::vector<GenOp>& ops, const std::vector<script::OpOutcome>& lines,
                    std::string_view text, const core::TimeOptions& time) {
  core::SceneGraph<B> graph = *core::SceneGraph<B>::Create(time);
  for (std::size_t i = 0; i < ops.size(); ++i) {
    const Direct<B> d(graph, ops[i]);
    const script::OpOutcome& line = lines[i];
    const std::string where =
        "op " + std::to_string(i) + " (" + ops[i].yaml + "): tool printed " + line.json;
    if (d.ok != line.ok) {
      // The tool reports a non-finite query result as invalid_number (JSON has no Inf/NaN).
      const bool non_finite = d.ok && JsonErrorCode(line.json) == "invalid_number" &&
                              std::any_of(d.numbers.begin(), d.numbers.end(),
                                          [](double x) { return !std::isfinite(x); });
      if (!non_finite) Fail(where + ", the API says " + std::string(base::ToString(d.code)), text);
      continue;
    }
    if (!d.ok && JsonErrorCode(line.json) != base::ToString(d.code)) {
      Fail(where + ", the API says " + std::string(base::ToString(d.code)), text);
    }
    if (!d.ok) continue;
    if (d.untimed_differs)
      Fail(where + ": the untimed API disagrees with the timed one at the latest samples", text);
    if (ops[i].kind == GenOp::kQuery) {  // the time keys: exactly the report's
      const std::pair<const char*, const std::optional<core::Stamp>*> keys[] = {
          {"time", &d.time.time},
          {"ref_time", &d.time.ref_time},
          {"oldest", &d.time.oldest},
          {"newest", &d.time.newest}};
      for (const auto& [key, stamp] : keys) {
        const std::optional<double> printed = JsonKeyNumber(line.json, key);
        if (printed.has_value() != stamp->has_value() ||
            (printed && *printed != static_cast<double>((*stamp)->nanoseconds()) / 1e9)) {
          Fail(where + ": time key \"" + key + "\" differs from the API's report", text);
        }
      }
      if ((line.json.find("\"extrapolated\": true") != std::string::npos) != d.time.extrapolated) {
        Fail(where + ": \"extrapolated\" differs from the API's report", text);
      }
    }
    std::vector<double> printed = JsonArrayNumbers(line.json), expected = d.numbers;
    if (printed.size() != expected.size()) Fail(where + ": wrong number count", text);
    // Quaternions: the tool prints the representative with w >= 0 (first nonzero positive).
    const bool query = ops[i].kind == GenOp::kQuery;
    const bool quaternion_at_0 = query && ops[i].query == script::QueryKind::kOrientation;
    const bool quaternion_at_3 = query && ops[i].query == script::QueryKind::kPose;
    if (quaternion_at_0 || quaternion_at_3) {
      const std::size_t at = quaternion_at_0 ? 0 : 3;
      for (std::size_t k = at; k < at + 4; ++k) {
        if (expected[k] == 0.0) continue;
        if (expected[k] < 0.0) {
          for (std::size_t m = at; m < at + 4; ++m) expected[m] = -expected[m];
        }
        break;
      }
    }
    for (std::size_t k = 0; k < printed.size(); ++k) {
      const double e = expected[k] == 0.0 ? 0.0 : expected[k];
      if (printed[k] != e)
        Fail(where + ": number " + std::to_string(k) + " does not round-trip", text);
    }
  }
}

// Malformed variants of a script line (docs/scene-script.md: exit 2).
const char* const kMalformedOps[] = {
    "{op: frobnicate, name: a}",                                             // unknown op
    "{op: body}",                                                            // missing field
    "{op: body, name: [A]}",                                                 // mistyped field
    "{op: pose, of: a, body: A, wrt: b, ref_body: B, position: [1, 2]}",     // wrong length
    "{op: pose, of: a, body: A, wrt: b, ref_body: B, position: [1, x, 3]}",  // not a number
    "{op: pose, of: a, wrt: b, rotation: {quaternion: [1, 0, 0, 0], rpy: [0, 0, 0]}}",  // two forms
    "{op: pose, of: a, wrt: b, rotation: {}}",                                          // no form
    "{op: body, name: A, position: [0, 0, 0]}",                  // field of another op
    "{op: remove, of: a, wrt: b}",                               // remove without kind
    "{op: query, kind: jerk, point: a, ref_body: B, coord: a}",  // unknown query kind
    "{op: twist, point: a, ref_body: B}",                        // coord missing
    "{op: pose, of: a, wrt: b, position: [0, 0, 0",              // broken flow sequence
    "[op, body]",                                                // op not a map
    "{op: body, name: A, stamp: 1}",                             // a time field of another op
    "{op: query, kind: twist, point: a, ref_body: B, coord: a, ref_at: 1, fixed: a, at: 0}",  // travel
                                                                                              // on
                                                                                              // a
                                                                                              // twist
    "{op: query, kind: pose, of: a, wrt: b, source: poses}",     // source on a pose query
    "{op: query, kind: pose, of: a, wrt: b, at: 1, ref_at: 2}",  // ref_at without fixed
    "{op: query, kind: pose, of: a, wrt: b, at: latest_common, ref_at: 2, fixed: b}",  // travel
                                                                                       // needs a
                                                                                       // time
    "{op: query, kind: pose, of: a, wrt: b, at: soon}",   // at not a time
    "{op: pose, of: a, wrt: b, stamp: 1, repair: true}",  // repair takes no stamp
};

void Structured(OpReader& in) {
  Generator gen(in);
  const bool homogeneous = in.Bool();
  std::vector<GenOp> ops;
  const std::size_t n = in.Below(24);
  for (std::size_t i = 0; i < n && !in.empty(); ++i) ops.push_back(gen.Op());
  // The document's time map, sometimes (the graph options both sides use).
  script::TimeSettings settings;
  std::string time_map;
  if (in.OneIn(2)) {
    settings.linear = in.Bool();
    settings.reject_duplicates = in.Bool();
    time_map = std::string("time: {interpolation: ") + (settings.linear ? "linear" : "screw") +
               ", duplicate_stamp: " + (settings.reject_duplicates ? "reject" : "replace");
    if (in.Bool()) {
      settings.window_ns = 500000000;  // 0.5 s: some samples drop, some are too old
      time_map += ", window: 0.5";
    }
    time_map += "}\n";
  }
  const core::TimeOptions time = script::TimeOptionsOf(settings);
  const std::string header =
      time_map + (homogeneous ? "representation: homogeneous\nops:\n" : "ops:\n");
  std::string text = header;
  if (ops.empty()) text += "  []\n";
  for (const GenOp& op : ops) text += "  - " + op.yaml + "\n";

  std::vector<script::OpOutcome> lines;
  const int status = RunScript(text, &lines);
  if (status == kExitMalformed)
    Fail("a well-formed generated script was rejected as malformed", text);
  if (lines.size() != ops.size()) Fail("not one output line per op", text);
  if (homogeneous) {
    CompareWithApi<coord::HomogeneousBackend>(ops, lines, text, time);
  } else {
    CompareWithApi<coord::QuaternionBackend>(ops, lines, text, time);
  }

  // One malformed line spliced in: the whole script is malformed.
  const std::size_t at = in.Below(static_cast<std::uint32_t>(ops.size() + 1));
  std::string bad = header;
  for (std::size_t i = 0; i <= ops.size(); ++i) {
    if (i == at)
      bad += std::string("  - ") + kMalformedOps[in.Below(std::size(kMalformedOps))] + "\n";
    if (i < ops.size()) bad += "  - " + ops[i].yaml + "\n";
  }
  const std::uint32_t document = in.Below(8);
  if (document == 0)
    bad = "representation: octonion\n" + bad.substr(header.size() - 5);  // unknown representation
  if (document == 1)
    bad = "time: {window: 0}\n" + bad.substr(time_map.size());  // a window that is not positive
  if (RunScript(bad, nullptr) != kExitMalformed)
    Fail("a malformed script was not rejected with status 2", bad);
}

}  // namespace
}  // namespace semgraph::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  semgraph::fuzz::OpReader in(data + 1, size - 1);
  if (data[0] & 1u) {
    semgraph::fuzz::Structured(in);
  } else {
    semgraph::fuzz::RunScript(in.Rest(), nullptr);
  }
  return 0;
}
