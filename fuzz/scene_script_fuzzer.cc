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
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "semgraph/core/scene_graph.h"
#include "semgraph/script_reader.h"
#include "semgraph/script_runner.h"
#include "semgraph/base/error_code.h"
#include "support/op_reader.h"

namespace semgraph::fuzz {
namespace {

using script::ReadScript;
using script::Representation;

constexpr int kExitOk = 0, kExitOpFailed = 1, kExitMalformed = 2;

[[noreturn]] void Fail(const std::string& why, std::string_view script) {
  std::fprintf(stderr, "\n==== scene_script_fuzzer FAILED ====\n%s\n---- script ----\n%.*s\n==== end ====\n",
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
      const std::string head = "{\"op\": " + std::to_string(i) + ", \"ok\": " + (outcome.ok ? "true" : "false");
      if (outcome.json.rfind(head, 0) != 0 || outcome.json.back() != '}' ||
          outcome.json.find('\n') != std::string::npos) {
        Fail("op " + std::to_string(i) + " printed a malformed JSON line: " + outcome.json, text);
      }
      all_ok = all_ok && outcome.ok;
      if (lines) lines->push_back(std::move(outcome));
    }
    if (!graph.CheckInvariants().empty()) Fail("CheckInvariants() after the script", text);
  };
  if (script->representation == Representation::kHomogeneous) {
    run(core::SceneGraph<coord::HomogeneousBackend>());
  } else {
    run(core::SceneGraph<coord::QuaternionBackend>());
  }
  return all_ok ? kExitOk : kExitOpFailed;
}

// ------------------------------------------------------------------ mode 1: generated scripts

const char* const kBodies[] = {"A", "B", "C", "D"};
const char* const kFrames[] = {"a", "b", "c", "d", "e", "f", "g", "h"};
const double kNumbers[] = {0.0, 1.0, -0.5, 0.2, 0.3, 1.25, -2.0, 0.1};

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
        op.yaml = "{op: frame, name: " + Quote(op.s[0]) + (op.s[1].empty() ? "" : ", body: " + Quote(op.s[1])) + "}";
        break;
      case 2: case 3: {
        op.kind = GenOp::kPose;
        op.s[0] = Frame(), op.s[1] = in_.Bool() ? Body() : "", op.s[2] = Frame(), op.s[3] = in_.Bool() ? Body() : "";
        op.coord = in_.OneIn(4) ? Frame() : "";
        op.yaml = "{op: pose, of: " + Quote(op.s[0]) + (op.s[1].empty() ? "" : ", body: " + Quote(op.s[1])) +
                  ", wrt: " + Quote(op.s[2]) + (op.s[3].empty() ? "" : ", ref_body: " + Quote(op.s[3])) +
                  (op.coord.empty() ? "" : ", coord: " + Quote(op.coord));
        if (in_.Bool()) op.yaml += ", position: " + Vector(op.pos);
        op.rotation_form = static_cast<int>(in_.Below(4));
        if (op.rotation_form == 1) {
          const double* q = Unit(in_.Below(4));
          for (int i = 0; i < 4; ++i) op.rot[i] = in_.OneIn(16) ? Number() : q[i];
          op.yaml += ", rotation: {quaternion: [" + Text(op.rot[0]) + ", " + Text(op.rot[1]) + ", " +
                     Text(op.rot[2]) + ", " + Text(op.rot[3]) + "]}";
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
        op.yaml += "}";
        break;
      }
      case 4:
        op.kind = GenOp::kTwist;
        op.s[0] = Frame(), op.s[1] = in_.Bool() ? Body() : "", op.s[2] = Body();
        op.coord = in_.Bool() ? op.s[0] : Frame();
        op.yaml = "{op: twist, point: " + Quote(op.s[0]) + (op.s[1].empty() ? "" : ", body: " + Quote(op.s[1])) +
                  ", ref_body: " + Quote(op.s[2]) + ", coord: " + Quote(op.coord);
        if (in_.Bool()) op.yaml += ", linear: " + Vector(op.lin);
        if (in_.Bool()) op.yaml += ", angular: " + Vector(op.ang);
        op.yaml += "}";
        break;
      case 5:
        if (in_.Bool()) {
          op.kind = GenOp::kRemovePose;
          op.s[0] = Frame(), op.s[1] = Frame();
          op.yaml = "{op: remove, kind: pose, of: " + Quote(op.s[0]) + ", wrt: " + Quote(op.s[1]) + "}";
        } else {
          op.kind = GenOp::kRemoveTwist;
          op.s[0] = Frame(), op.s[1] = Body();
          op.yaml = "{op: remove, kind: twist, point: " + Quote(op.s[0]) + ", ref_body: " + Quote(op.s[1]) + "}";
        }
        break;
      default: {
        op.kind = GenOp::kQuery;
        op.query = static_cast<script::QueryKind>(in_.Below(6));
        const char* kinds[] = {"pose", "position", "orientation", "twist", "linear_velocity", "angular_velocity"};
        op.yaml = std::string("{op: query, kind: ") + kinds[static_cast<int>(op.query)];
        if (op.query <= script::QueryKind::kOrientation) {
          // of: X, wrt: Y (the shorthand), point/orientation and coord overrides sometimes.
          op.s[0] = Frame(), op.s[1] = Frame();
          op.coord = in_.OneIn(3) ? Frame() : "";
          if (op.query == script::QueryKind::kPose) op.yaml += ", of: " + Quote(op.s[0]) + ", wrt: " + Quote(op.s[1]);
          if (op.query == script::QueryKind::kPosition) op.yaml += ", point: " + Quote(op.s[0]) + ", ref_point: " + Quote(op.s[1]);
          if (op.query == script::QueryKind::kOrientation) {
            op.yaml += ", orientation: " + Quote(op.s[0]) + ", ref_orientation: " + Quote(op.s[1]);
          }
          // Position and orientation queries have no shorthand: coord is required (it may be
          // the empty name, an op error). Pose queries take it from wrt unless overridden.
          const bool needs_coord = op.query != script::QueryKind::kPose;
          if (needs_coord && op.coord.empty()) op.coord = op.s[1];
          if (needs_coord || !op.coord.empty()) op.yaml += ", coord: " + Quote(op.coord);
        } else {
          op.s[0] = Frame(), op.s[1] = in_.Bool() || op.query == script::QueryKind::kAngularVelocity ? Body() : "",
          op.s[2] = Body(), op.coord = Frame();
          if (op.query != script::QueryKind::kAngularVelocity) op.yaml += ", point: " + Quote(op.s[0]);
          // The angular velocity has no point to take the body from: body is required there.
          if (!op.s[1].empty() || op.query == script::QueryKind::kAngularVelocity) {
            op.yaml += ", body: " + Quote(op.s[1]);
          }
          op.yaml += ", ref_body: " + Quote(op.s[2]) + ", coord: " + Quote(op.coord);
        }
        op.yaml += "}";
      }
    }
    return op;
  }

 private:
  static const double* Unit(std::uint32_t i) {
    static const double q[4][4] = {{1, 0, 0, 0}, {0.5, 0.5, 0.5, 0.5}, {0, 0, 1, 0}, {0.6, 0, 0.8, 0}};
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

  static Eigen::Vector3d V(const double* v) { return {v[0], v[1], v[2]}; }
  template <class R>
  void Take(const R& r) {
    ok = r.has_value();
    code = ok ? base::ErrorCode::kOk : r.error().code;
  }
  void Push(const Eigen::Vector3d& v) { numbers.insert(numbers.end(), {v.x(), v.y(), v.z()}); }
  void Push(const Eigen::Quaterniond& q) { numbers.insert(numbers.end(), {q.w(), q.x(), q.y(), q.z()}); }

  Direct(core::SceneGraph<B>& g, const GenOp& op) {
    switch (op.kind) {
      case GenOp::kBody: Take(g.AddBody(op.s[0])); break;
      case GenOp::kFrame: Take(g.AddFrame(op.s[0], op.s[1])); break;
      case GenOp::kPose: {
        core::PoseSpec spec = core::PoseSpec::Of(op.s[0], op.s[1]).RelativeTo(op.s[2], op.s[3]);
        if (!op.coord.empty()) spec.coordinate_frame = op.coord;
        const Eigen::Vector3d p = V(op.pos);
        if (op.rotation_form == 0) Take(g.AddPose(spec, Eigen::Quaterniond::Identity(), p));
        if (op.rotation_form == 1) Take(g.AddPose(spec, Eigen::Quaterniond(op.rot[0], op.rot[1], op.rot[2], op.rot[3]), p));
        if (op.rotation_form == 2) {
          const Eigen::Quaterniond q = Eigen::AngleAxisd(op.rot[2], Eigen::Vector3d::UnitZ()) *
                                       Eigen::AngleAxisd(op.rot[1], Eigen::Vector3d::UnitY()) *
                                       Eigen::AngleAxisd(op.rot[0], Eigen::Vector3d::UnitX());
          Take(g.AddPose(spec, q, p));
        }
        if (op.rotation_form == 3) {
          Eigen::Matrix3d R;
          for (int i = 0; i < 9; ++i) R(i / 3, i % 3) = op.rot[i];
          Take(g.AddPose(spec, R, p));
        }
        break;
      }
      case GenOp::kTwist:
        Take(g.AddTwist(core::TwistSpec::Of(op.s[0], op.s[1]).RelativeTo(op.s[2]).ExpressedIn(op.coord),
                        V(op.lin), V(op.ang)));
        break;
      case GenOp::kRemovePose: Take(g.RemovePose(op.s[0], op.s[1])); break;
      case GenOp::kRemoveTwist: Take(g.RemoveTwist(op.s[0], op.s[1])); break;
      case GenOp::kQuery: Query(g, op); break;
    }
  }

  void Query(const core::SceneGraph<B>& g, const GenOp& op) {
    core::PoseSpec ps = core::PoseSpec::Of(op.s[0]).RelativeTo(op.s[1]);
    if (!op.coord.empty()) ps.coordinate_frame = op.coord;
    // (string_view on both sides: a std::string temporary here would leave the spec dangling.)
    const std::string_view point =
        op.query == script::QueryKind::kAngularVelocity ? std::string_view() : std::string_view(op.s[0]);
    const core::TwistSpec ts = core::TwistSpec::Of(point, op.s[1]).RelativeTo(op.s[2]).ExpressedIn(op.coord);
    switch (op.query) {
      case script::QueryKind::kPose: {
        const auto r = g.GetPose(ps);
        Take(r);
        if (ok) Push(B::TranslationOf(r->value)), Push(B::ToQuaternion(B::RotationOf(r->value)));
        break;
      }
      case script::QueryKind::kPosition: {
        const auto r = g.GetPosition(ps);
        Take(r);
        if (ok) Push(r->value);
        break;
      }
      case script::QueryKind::kOrientation: {
        const auto r = g.GetOrientation(ps);
        Take(r);
        if (ok) Push(B::ToQuaternion(r->value));
        break;
      }
      case script::QueryKind::kTwist: {
        const auto r = g.GetTwist(ts);
        Take(r);
        if (ok) Push(r->linear), Push(r->angular);
        break;
      }
      case script::QueryKind::kLinearVelocity: {
        const auto r = g.GetLinearVelocity(ts);
        Take(r);
        if (ok) Push(r->value);
        break;
      }
      case script::QueryKind::kAngularVelocity: {
        const auto r = g.GetAngularVelocity(ts);
        Take(r);
        if (ok) Push(r->value);
        break;
      }
      case script::QueryKind::kJacobian: {  // the script prints the rows in order (v, then w)
        const auto r = g.GetJacobian(ts);
        Take(r);
        for (Eigen::Index row = 0; ok && row < 6; ++row) {
          for (Eigen::Index c = 0; c < r->J.cols(); ++c) numbers.push_back(r->J(row, c));
        }
        break;
      }
    }
  }
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

std::string JsonErrorCode(const std::string& json) {
  const std::string key = "\"error\": \"";
  const std::size_t at = json.find(key);
  if (at == std::string::npos) return "";
  const std::size_t end = json.find('"', at + key.size());
  return json.substr(at + key.size(), end - at - key.size());
}

template <coord::Backend B>
void CompareWithApi(const std::vector<GenOp>& ops, const std::vector<script::OpOutcome>& lines,
                    std::string_view text) {
  core::SceneGraph<B> graph;
  for (std::size_t i = 0; i < ops.size(); ++i) {
    const Direct<B> d(graph, ops[i]);
    const script::OpOutcome& line = lines[i];
    const std::string where = "op " + std::to_string(i) + " (" + ops[i].yaml + "): tool printed " + line.json;
    if (d.ok != line.ok) {
      // The tool reports a non-finite query result as invalid_number (JSON has no Inf/NaN).
      const bool non_finite = d.ok && JsonErrorCode(line.json) == "invalid_number" &&
                              std::any_of(d.numbers.begin(), d.numbers.end(), [](double x) { return !std::isfinite(x); });
      if (!non_finite) Fail(where + ", the API says " + std::string(base::ToString(d.code)), text);
      continue;
    }
    if (!d.ok && JsonErrorCode(line.json) != base::ToString(d.code)) {
      Fail(where + ", the API says " + std::string(base::ToString(d.code)), text);
    }
    if (!d.ok) continue;
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
      if (printed[k] != e) Fail(where + ": number " + std::to_string(k) + " does not round-trip", text);
    }
  }
}

// Malformed variants of a script line (docs/scene-script.md: exit 2).
const char* const kMalformedOps[] = {
    "{op: frobnicate, name: a}",                                         // unknown op
    "{op: body}",                                                        // missing field
    "{op: body, name: [A]}",                                             // mistyped field
    "{op: pose, of: a, body: A, wrt: b, ref_body: B, position: [1, 2]}",  // wrong length
    "{op: pose, of: a, body: A, wrt: b, ref_body: B, position: [1, x, 3]}",  // not a number
    "{op: pose, of: a, wrt: b, rotation: {quaternion: [1, 0, 0, 0], rpy: [0, 0, 0]}}",  // two forms
    "{op: pose, of: a, wrt: b, rotation: {}}",                           // no form
    "{op: body, name: A, position: [0, 0, 0]}",                          // field of another op
    "{op: remove, of: a, wrt: b}",                                       // remove without kind
    "{op: query, kind: acceleration, point: a, ref_body: B, coord: a}",  // unknown query kind
    "{op: twist, point: a, ref_body: B}",                                // coord missing
    "{op: pose, of: a, wrt: b, position: [0, 0, 0",                     // broken flow sequence
    "[op, body]",                                                        // op not a map
};

void Structured(OpReader& in) {
  Generator gen(in);
  const bool homogeneous = in.Bool();
  std::vector<GenOp> ops;
  const std::size_t n = in.Below(24);
  for (std::size_t i = 0; i < n && !in.empty(); ++i) ops.push_back(gen.Op());
  const std::string header = homogeneous ? "representation: homogeneous\nops:\n" : "ops:\n";
  std::string text = header;
  if (ops.empty()) text += "  []\n";
  for (const GenOp& op : ops) text += "  - " + op.yaml + "\n";

  std::vector<script::OpOutcome> lines;
  const int status = RunScript(text, &lines);
  if (status == kExitMalformed) Fail("a well-formed generated script was rejected as malformed", text);
  if (lines.size() != ops.size()) Fail("not one output line per op", text);
  if (homogeneous) {
    CompareWithApi<coord::HomogeneousBackend>(ops, lines, text);
  } else {
    CompareWithApi<coord::QuaternionBackend>(ops, lines, text);
  }

  // One malformed line spliced in: the whole script is malformed.
  const std::size_t at = in.Below(static_cast<std::uint32_t>(ops.size() + 1));
  std::string bad = header;
  for (std::size_t i = 0; i <= ops.size(); ++i) {
    if (i == at) bad += std::string("  - ") + kMalformedOps[in.Below(std::size(kMalformedOps))] + "\n";
    if (i < ops.size()) bad += "  - " + ops[i].yaml + "\n";
  }
  if (in.OneIn(8)) bad = "representation: octonion\n" + bad.substr(header.size() - 5);  // unknown representation
  if (RunScript(bad, nullptr) != kExitMalformed) Fail("a malformed script was not rejected with status 2", bad);
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
