// Script runner: one scene-graph call per op, one JSON line per outcome. Contract:
// script_runner.h; output format: spec/scene-script.md.
#include "semgraph/script_runner.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "semgraph/base/error_code.h"

namespace semgraph::tools {

namespace {

// Length of the valid UTF-8 sequence starting at s[i] (1-4), or 0 if it is not valid (stray
// continuation byte, truncated, overlong, surrogate, above U+10FFFF).
std::size_t Utf8SequenceLength(std::string_view s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b0 = byte(i);
  std::size_t length = 0;
  std::uint32_t min_code = 0;  // below it the sequence is overlong
  std::uint32_t code = 0;
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    length = 2;
    min_code = 0x80;
    code = b0 & 0x1Fu;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    length = 3;
    min_code = 0x800;
    code = b0 & 0x0Fu;
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    length = 4;
    min_code = 0x10000;
    code = b0 & 0x07u;
  } else {
    return 0;
  }
  if (i + length > s.size()) return 0;
  for (std::size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0u) != 0x80u) return 0;
    code = (code << 6) | (byte(i + k) & 0x3Fu);
  }
  if (code < min_code || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return length;
}

// One named result array of a successful query.
struct ResultField {
  std::string_view key;
  std::vector<double> values;
};

OpOutcome Success(std::size_t index, std::initializer_list<ResultField> fields = {}) {
  for (const ResultField& f : fields) {
    for (const double v : f.values) {
      if (!std::isfinite(v)) {
        // Defensive: JSON has no Inf/NaN, and the graph's input bounds should prevent this.
        return OpOutcome{false, "{\"op\": " + std::to_string(index) +
                                    ", \"ok\": false, \"error\": \"invalid_number\", "
                                    "\"message\": " +
                                    JsonString("the " + std::string(f.key) +
                                               " of the result is not finite (overflow)") +
                                    "}"};
      }
    }
  }
  std::string json = "{\"op\": " + std::to_string(index) + ", \"ok\": true";
  for (const ResultField& f : fields) {
    json += ", \"" + std::string(f.key) + "\": [";
    for (std::size_t i = 0; i < f.values.size(); ++i) {
      if (i > 0) json += ',';
      json += JsonNumber(f.values[i]);
    }
    json += ']';
  }
  return OpOutcome{true, json + "}"};
}

OpOutcome Failure(std::size_t index, base::ErrorCode code, std::string_view message) {
  return OpOutcome{false, "{\"op\": " + std::to_string(index) + ", \"ok\": false, \"error\": " +
                              JsonString(base::ToString(code)) +
                              ", \"message\": " + JsonString(message) + "}"};
}

OpOutcome FromBuild(std::size_t index, const core::BuildResult& result) {
  if (result) return Success(index);
  return Failure(index, result.error().code, result.error().message);
}

std::vector<double> Values(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// [w, x, y, z] with w >= 0; for w == 0 the first nonzero of x, y, z is made positive, so that
// the printed text does not depend on which of q and -q a computation produced.
std::vector<double> Values(const Eigen::Quaterniond& q) {
  std::vector<double> c = {q.w(), q.x(), q.y(), q.z()};
  for (const double component : c) {
    if (component == 0.0) continue;
    if (component < 0.0) {
      for (double& x : c) x = -x;
    }
    break;
  }
  return c;
}

Eigen::Vector3d ToVector(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

core::PoseSpec PoseSpecOf(const SemanticNames& n) {
  core::PoseSpec s;
  s.point = n.point;
  s.orientation = n.orientation;
  s.body = n.body;
  s.ref_point = n.ref_point;
  s.ref_orientation = n.ref_orientation;
  s.ref_body = n.ref_body;
  s.coordinate_frame = n.coord;
  return s;
}

core::TwistSpec TwistSpecOf(const SemanticNames& n) {
  core::TwistSpec s;
  s.point = n.point;
  s.body = n.body;
  s.ref_body = n.ref_body;
  s.coordinate_frame = n.coord;
  return s;
}

template <coord::Backend B>
OpOutcome AddPose(core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index) {
  const core::PoseSpec spec = PoseSpecOf(op.names);
  const Eigen::Vector3d p = ToVector(op.position);
  const RotationValue& r = op.rotation;
  switch (r.form) {
    case RotationForm::kIdentity:
      return FromBuild(index, graph.AddPose(spec, Eigen::Quaterniond::Identity(), p));
    case RotationForm::kQuaternion:
      // Passed as written: normalizing here would hide invalid_rotation.
      return FromBuild(index, graph.AddPose(spec,
                                            Eigen::Quaterniond(r.quaternion[0], r.quaternion[1],
                                                               r.quaternion[2], r.quaternion[3]),
                                            p));
    case RotationForm::kRpy: {
      // R = Rz(yaw) Ry(pitch) Rx(roll); a non-finite angle gives a non-finite quaternion, which
      // the graph reports as invalid_number.
      const Eigen::Quaterniond q = Eigen::AngleAxisd(r.rpy[2], Eigen::Vector3d::UnitZ()) *
                                   Eigen::AngleAxisd(r.rpy[1], Eigen::Vector3d::UnitY()) *
                                   Eigen::AngleAxisd(r.rpy[0], Eigen::Vector3d::UnitX());
      return FromBuild(index, graph.AddPose(spec, q, p));
    }
    case RotationForm::kMatrix: {
      Eigen::Matrix3d R;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) R(i, j) = r.matrix[i][j];
      }
      return FromBuild(index, graph.AddPose(spec, R, p));
    }
  }
  base::DemandFailed("valid RotationForm", __FILE__, __LINE__);
}

template <coord::Backend B>
OpOutcome Query(const core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index) {
  const SemanticNames& n = op.names;
  switch (op.query_kind) {
    case QueryKind::kPose: {
      const core::PoseSpec spec = PoseSpecOf(n);
      const auto X = graph.GetPose(spec);
      if (!X) return Failure(index, X.error().code, graph.Describe(X.error(), spec));
      return Success(index, {{"position", Values(B::TranslationOf(X->value))},
                             {"quaternion", Values(B::ToQuaternion(B::RotationOf(X->value)))}});
    }
    case QueryKind::kPosition: {
      const core::PoseSpec spec = PoseSpecOf(n);
      const auto p = graph.GetPosition(spec);
      if (!p) return Failure(index, p.error().code, graph.Describe(p.error(), spec));
      return Success(index, {{"position", Values(p->value)}});
    }
    case QueryKind::kOrientation: {
      const core::PoseSpec spec = PoseSpecOf(n);
      const auto R = graph.GetOrientation(spec);
      if (!R) return Failure(index, R.error().code, graph.Describe(R.error(), spec));
      return Success(index, {{"quaternion", Values(B::ToQuaternion(R->value))}});
    }
    case QueryKind::kTwist: {
      const core::TwistSpec spec = TwistSpecOf(n);
      const auto V = graph.GetTwist(spec);
      if (!V) return Failure(index, V.error().code, graph.Describe(V.error(), spec));
      return Success(index, {{"linear", Values(V->linear)}, {"angular", Values(V->angular)}});
    }
    case QueryKind::kLinearVelocity: {
      const core::TwistSpec spec = TwistSpecOf(n);
      const auto v = graph.GetLinearVelocity(spec);
      if (!v) return Failure(index, v.error().code, graph.Describe(v.error(), spec));
      return Success(index, {{"linear", Values(v->value)}});
    }
    case QueryKind::kAngularVelocity: {
      const core::TwistSpec spec = TwistSpecOf(n);
      const auto w = graph.GetAngularVelocity(spec);
      if (!w) return Failure(index, w.error().code, graph.Describe(w.error(), spec));
      return Success(index, {{"angular", Values(w->value)}});
    }
  }
  base::DemandFailed("valid QueryKind", __FILE__, __LINE__);
}

}  // namespace

std::string JsonString(std::string_view text) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string s;
  s.reserve(text.size() + 2);
  s += '"';
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x80) {
      const std::size_t length = Utf8SequenceLength(text, i);
      if (length == 0) {
        s += "\\ufffd";  // JSON text must be UTF-8; keep the position of the bad byte visible
        ++i;
      } else {
        s.append(text.substr(i, length));
        i += length;
      }
      continue;
    }
    switch (c) {
      case '"':
        s += "\\\"";
        break;
      case '\\':
        s += "\\\\";
        break;
      case '\b':
        s += "\\b";
        break;
      case '\f':
        s += "\\f";
        break;
      case '\n':
        s += "\\n";
        break;
      case '\r':
        s += "\\r";
        break;
      case '\t':
        s += "\\t";
        break;
      default:
        if (c < 0x20 || c == 0x7F) {
          s += "\\u00";
          s += kHex[c >> 4];
          s += kHex[c & 0xF];
        } else {
          s += static_cast<char>(c);
        }
    }
    ++i;
  }
  s += '"';
  return s;
}

std::string JsonNumber(double value) {
  if (value == 0.0) value = 0.0;  // -0 and 0 are one value; print both as 0
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

template <coord::Backend B>
OpOutcome ApplyOp(core::SceneGraph<B>& graph, const ScriptOp& op, std::size_t index) {
  const SemanticNames& n = op.names;
  switch (op.kind) {
    case OpKind::kBody:
      return FromBuild(index, graph.AddBody(op.name));
    case OpKind::kFrame:
      return FromBuild(index, graph.AddFrame(op.name, n.body));
    case OpKind::kPose:
      return AddPose(graph, op, index);
    case OpKind::kTwist:
      return FromBuild(index,
                       graph.AddTwist(TwistSpecOf(n), ToVector(op.linear), ToVector(op.angular)));
    case OpKind::kRemovePose:
      return FromBuild(index, graph.RemovePose(n.orientation, n.ref_orientation));
    case OpKind::kRemoveTwist:
      return FromBuild(index, graph.RemoveTwist(n.point, n.ref_body));
    case OpKind::kQuery:
      return Query(std::as_const(graph), op, index);
  }
  base::DemandFailed("valid OpKind", __FILE__, __LINE__);
}

template OpOutcome ApplyOp<coord::QuaternionBackend>(core::SceneGraph<coord::QuaternionBackend>&,
                                                     const ScriptOp&, std::size_t);
template OpOutcome ApplyOp<coord::HomogeneousBackend>(core::SceneGraph<coord::HomogeneousBackend>&,
                                                      const ScriptOp&, std::size_t);

}  // namespace semgraph::tools
