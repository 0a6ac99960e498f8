// ReferenceModel: see reference_model.h. Every function is a literal transcription of a rule of
// docs/rules.md; nothing is incremental, nothing is cached.
#include "reference_model.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <numbers>
#include <tuple>

namespace semgraph::reference {
namespace {

constexpr double kRotationTolerance = 1e-6;  // docs/rules.md §5: |‖q‖ − 1|, max|MᵀM − I|
constexpr double kConstantTolerance = 1e-6;  // docs/rules.md §2 P4
constexpr double kPi = 3.14159265358979323846;

bool Finite(const Eigen::Vector3d& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}
// A number the library accepts in a vector (docs/rules.md: finite, |x| <= 1e12).
bool NumberOk(const Eigen::Vector3d& v) { return Finite(v) && v.cwiseAbs().maxCoeff() <= 1e12; }

// Union-find over strings, the naive way.
struct Partition {
  std::map<std::string, std::string> parent;
  std::string Find(const std::string& x) {
    if (!parent.count(x)) parent[x] = x;
    std::string r = x;
    while (parent[r] != r) r = parent[r];
    return r;
  }
  // False when a and b were already joined.
  bool Join(const std::string& a, const std::string& b) {
    const std::string ra = Find(a), rb = Find(b);
    if (ra == rb) return false;
    parent[ra] = rb;
    return true;
  }
};

// docs/rules.md §5: NaN/Inf anywhere -> invalid_number; improper rotation -> invalid_rotation;
// within tolerance -> normalized.
ErrorCode ValidateRotation(const RotationInput& in, Eigen::Matrix3d* R) {
  if (!in.is_matrix) {
    const double c[4] = {in.q.w(), in.q.x(), in.q.y(), in.q.z()};
    for (double x : c) {
      if (!std::isfinite(x)) return ErrorCode::kInvalidNumber;
    }
    const double norm = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + c[3] * c[3]);
    if (!(std::abs(norm - 1.0) <= kRotationTolerance)) return ErrorCode::kInvalidRotation;
    const Eigen::Quaterniond q(c[0] / norm, c[1] / norm, c[2] / norm, c[3] / norm);
    *R = q.toRotationMatrix();
    return ErrorCode::kOk;
  }
  for (int i = 0; i < 9; ++i) {
    if (!std::isfinite(in.R(i / 3, i % 3))) return ErrorCode::kInvalidNumber;
  }
  const double off = (in.R.transpose() * in.R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(off <= kRotationTolerance) || !(in.R.determinant() > 0.0))
    return ErrorCode::kInvalidRotation;
  Eigen::Matrix3d X = in.R;  // nearest rotation: Newton iteration of the polar decomposition
  for (int i = 0; i < 20; ++i) X = 0.5 * (X + X.inverse().transpose());
  *R = X;
  return ErrorCode::kOk;
}

// ============================================================ covariances (docs/uncertainty.md)

constexpr double kMaxMagnitude = 1e12;         // invalid_number: |x| above this
constexpr double kCovarianceTolerance = 1e-9;  // symmetry and eigenvalue bound, relative

double CovarianceTolerance(const Matrix6& S) {
  return kCovarianceTolerance * std::max(1.0, S.cwiseAbs().maxCoeff());
}
// invalid_number: every entry finite and at most 1e12 in magnitude.
bool CovarianceNumbersOk(const Matrix6& S) {
  for (int i = 0; i < 36; ++i) {
    if (!std::isfinite(S(i / 6, i % 6)) || std::abs(S(i / 6, i % 6)) > kMaxMagnitude) return false;
  }
  return true;
}
// invalid_covariance: asymmetric beyond tol, or an eigenvalue of the symmetric part below -tol.
bool CovarianceShapeOk(const Matrix6& S) {
  const double tol = CovarianceTolerance(S);
  for (int i = 0; i < 6; ++i) {
    for (int j = i + 1; j < 6; ++j) {
      if (std::abs(S(i, j) - S(j, i)) > tol) return false;
    }
  }
  return !(ReferenceModel::SmallestEigenvalue(0.5 * (S + S.transpose())) < -tol);
}
Eigen::Matrix3d Hat(const Eigen::Vector3d& w);  // [w]x, defined below
// J S J^T with J = [[A, B], [0, D]] written out block by block.
Matrix6 Propagate(const Eigen::Matrix3d& A, const Eigen::Matrix3d& B, const Eigen::Matrix3d& D,
                  const Matrix6& S) {
  Matrix6 J = Matrix6::Zero();
  J.topLeftCorner<3, 3>() = A;
  J.topRightCorner<3, 3>() = B;
  J.bottomRightCorner<3, 3>() = D;
  return J * S * J.transpose();
}
// A checked covariance in the edge form: linear first, symmetrized, the body convention turned
// into coordinates (delta = (R rho, R phi)). R: the value's rotation (poses; identity for twists).
Matrix6 EdgeForm(const CovarianceIn& c, const Eigen::Matrix3d& R) {
  Matrix6 S = c.S;
  if (c.angular_linear) {  // rows and columns (dtheta, dp) -> (dp, dtheta)
    Matrix6 T;
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) T((i + 3) % 6, (j + 3) % 6) = S(i, j);
    }
    S = T;
  }
  S = 0.5 * (S + S.transpose());
  if (c.body) S = Propagate(R, Eigen::Matrix3d::Zero(), R, S);
  return S;
}
// The covariance of X^-1 for X = (R, p) with coordinates perturbation (p + dp, Exp(dtheta) R):
// R'_true = R^T Exp(-dtheta) = Exp(-R^T dtheta) R^T, so dtheta' = -R^T dtheta; and
// p'_true = -R_true^T p_true = -R^T (I - [dtheta]x)(p + dp) = p' - R^T dp - R^T [p]x dtheta.
Matrix6 InverseCovariance(const Transform& X, const Matrix6& S) {
  const Eigen::Matrix3d Rt = X.R.transpose();
  return Propagate(-Rt, -Rt * Hat(X.p), -Rt, S);
}
// A restated constant pose's covariance (docs/uncertainty.md §2). AMBIGUITY, resolved like the
// library: "none = none" read literally: no covariance matches only a stored zero one.
bool SameCovariance(const Matrix6& stored, const CovarianceIn* given, const Matrix6& S) {
  if (given == nullptr) return stored.isZero(0.0);
  return (stored - S).cwiseAbs().maxCoeff() <= CovarianceTolerance(stored);
}

Transform Compose(const Transform& X_AB, const Transform& X_BC) {  // -> X_AC
  return {X_AB.R * X_BC.R, X_AB.R * X_BC.p + X_AB.p};
}
Transform Invert(const Transform& X_AB) {  // -> X_BA
  return {X_AB.R.transpose(), -(X_AB.R.transpose() * X_AB.p)};
}

// a - b saturated to int64 (windows near the ends of the stamp range).
std::int64_t SubSat(std::int64_t a, std::int64_t b) {
  std::int64_t r = 0;
  if (__builtin_sub_overflow(a, b, &r)) return b > 0 ? INT64_MIN : INT64_MAX;
  return r;
}

bool SamePose(const Transform& a, const Transform& b) {  // P4's tolerance
  return (a.R - b.R).cwiseAbs().maxCoeff() <= kConstantTolerance &&
         (a.p - b.p).norm() <= kConstantTolerance * std::max(1.0, a.p.norm());
}
bool SameTwist(const TwistSample& a, const Eigen::Vector3d& v, const Eigen::Vector3d& w) {
  return (a.v - v).norm() <= 1e-6 * std::max(1.0, a.v.norm()) &&
         (a.w - w).norm() <= 1e-6 * std::max(1.0, a.w.norm());
}
// A sample's acceleration against one given (null: none): both none, or each vector within
// 1e-6 max(1, |stored|) (the twist's tolerance).
bool SameSampleAcceleration(const TwistSample& x, const AccelerationIn* A) {
  if (x.has_A != (A != nullptr)) return false;
  if (A == nullptr) return true;
  return (x.a - A->a).norm() <= 1e-6 * std::max(1.0, x.a.norm()) &&
         (x.alpha - A->alpha).norm() <= 1e-6 * std::max(1.0, x.alpha.norm());
}
// The edge's record of a stamped edge: its newest sample's twist and acceleration.
void FromNewest(TwistEdge& t) {
  const TwistSample& n = t.samples.back();
  t.v = n.v, t.w = n.w;
  t.has_A = n.has_A, t.a = n.a, t.alpha = n.alpha;
}

// The stamp rules of an update (time.md §1-2): stamp_mismatch -> stamp_too_old -> duplicate_stamp.
template <class Sample, class Same>
ErrorCode CheckStamp(bool stamped, const std::vector<Sample>& samples,
                     std::optional<std::int64_t> stamp, const TimeOptions& o, Same&& same) {
  if (!stamp) return stamped ? ErrorCode::kStampMismatch : ErrorCode::kOk;
  if (!stamped) return ErrorCode::kStampMismatch;
  if (*stamp < SubSat(samples.back().t, o.window_ns)) return ErrorCode::kStampTooOld;
  for (const Sample& x : samples) {
    if (x.t == *stamp && !same(x) && o.reject_duplicates) return ErrorCode::kDuplicateStamp;
  }
  return ErrorCode::kOk;
}

// Inserts (an equal stamp: replaced unless the same value), drops the oldest over capacity and
// every sample older than newest - window.
template <class Sample, class Same>
void InsertSample(std::vector<Sample>& samples, const Sample& x, const TimeOptions& o,
                  Same&& same) {
  auto it =
      std::find_if(samples.begin(), samples.end(), [&](const Sample& y) { return y.t >= x.t; });
  if (it != samples.end() && it->t == x.t) {
    if (!same(*it)) *it = x;
  } else {
    samples.insert(it, x);
    if (samples.size() > o.capacity) samples.erase(samples.begin());
  }
  const std::int64_t keep_from = SubSat(samples.back().t, o.window_ns);
  while (samples.size() > 1 && samples.front().t < keep_from) samples.erase(samples.begin());
}

// The rotation angle of R in [0, pi]: atan2(|sin|, cos) from the skew part and the trace
// (accurate for small angles, unlike acos of the trace).
double RotationAngle(const Eigen::Matrix3d& R) {
  const Eigen::Vector3d s(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  return std::atan2(0.5 * s.norm(), 0.5 * (R.trace() - 1.0));
}

Eigen::Matrix3d Hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d W;
  W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return W;
}

// exp([w]x), Rodrigues; the series below 1e-4 rad.
Eigen::Matrix3d RotExp(const Eigen::Vector3d& w) {
  const double th = w.norm();
  const Eigen::Matrix3d W = Hat(w);
  if (th < 1e-4)
    return Eigen::Matrix3d::Identity() + (1.0 - th * th / 6.0) * W + (0.5 - th * th / 24.0) * W * W;
  return Eigen::Matrix3d::Identity() + std::sin(th) / th * W +
         (1.0 - std::cos(th)) / (th * th) * W * W;
}

// The rotation vector of R (angle in [0, pi]); *near_pi when the angle is within 1e-6 of pi,
// where the axis sign is not determined (the spec leaves interpolation there to the library).
Eigen::Vector3d RotLog(const Eigen::Matrix3d& R, bool* near_pi) {
  const Eigen::Vector3d s(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));  // 2 sin(th) u
  const double th = std::atan2(0.5 * s.norm(), 0.5 * (R.trace() - 1.0));
  if (th > kPi - 1e-6) *near_pi = true;
  if (th < 1e-4) return (0.5 + th * th / 12.0) * s;
  if (th < kPi - 1e-3) return th / (2.0 * std::sin(th)) * s;
  // Near pi: the axis from the symmetric part (R + I)/2 = u u^T (+ O(pi - th)), its sign from s.
  const Eigen::Matrix3d S = 0.5 * (R + Eigen::Matrix3d::Identity());
  int k = 0;
  S.diagonal().maxCoeff(&k);
  Eigen::Vector3d u = S.col(k).normalized();
  if (u.dot(s) < 0) u = -u;
  return th * u;
}

// SE(3) Exp of the screw twist (v, w) (time.md's convention: X^-1 dX = ([w]x, v)).
Transform SE3Exp(const Eigen::Vector3d& v, const Eigen::Vector3d& w) {
  const double th = w.norm();
  const Eigen::Matrix3d W = Hat(w);
  Eigen::Matrix3d V;
  if (th < 1e-4) {
    V = Eigen::Matrix3d::Identity() + (0.5 - th * th / 24.0) * W +
        (1.0 / 6.0 - th * th / 120.0) * W * W;
  } else {
    V = Eigen::Matrix3d::Identity() + (1.0 - std::cos(th)) / (th * th) * W +
        (th - std::sin(th)) / (th * th * th) * W * W;
  }
  return Transform{RotExp(w), V * v};
}

// SE(3) Log: (v, w) with Exp(v, w) = X.
void SE3Log(const Transform& X, Eigen::Vector3d* v, Eigen::Vector3d* w, bool* near_pi) {
  *w = RotLog(X.R, near_pi);
  const double th = w->norm();
  const Eigen::Matrix3d W = Hat(*w);
  double c;
  if (th < 1e-4) {
    c = 1.0 / 12.0 + th * th / 720.0;
  } else {
    c = (1.0 - th * std::sin(th) / (2.0 * (1.0 - std::cos(th)))) / (th * th);
  }
  *v = (Eigen::Matrix3d::Identity() - 0.5 * W + c * W * W) * X.p;
}

// Whether x is within `margin` of the tolerance: the check may go either way by rounding.
bool NearTolerance(double x, double tolerance, double margin) {
  return std::abs(x - tolerance) <= margin;
}

}  // namespace

double ReferenceModel::SmallestEigenvalue(const Matrix6& S) {
  // Cyclic Jacobi (Numerical Recipes' rotation): A <- P^T A P zeroes A(p, q), until the
  // off-diagonal part is negligible; the diagonal is then the spectrum.
  Matrix6 A = 0.5 * (S + S.transpose());
  for (int sweep = 0; sweep < 60; ++sweep) {
    double off = 0.0;
    for (int i = 0; i < 6; ++i) {
      for (int j = i + 1; j < 6; ++j) off += A(i, j) * A(i, j);
    }
    if (off <= 1e-40 * std::max(A.squaredNorm(), 1e-300)) break;
    for (int p = 0; p < 6; ++p) {
      for (int q = p + 1; q < 6; ++q) {
        if (A(p, q) == 0.0) continue;
        const double theta = (A(q, q) - A(p, p)) / (2.0 * A(p, q));
        const double t =
            std::abs(theta) > 1e150
                ? 0.5 / theta
                : (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        Matrix6 P = Matrix6::Identity();
        P(p, p) = c;
        P(q, q) = c;
        P(p, q) = s;
        P(q, p) = -s;
        A = P.transpose() * A * P;
        A(p, q) = A(q, p) = 0.0;
      }
    }
  }
  return A.diagonal().minCoeff();
}

bool ReferenceModel::ValidName(const std::string& name) {
  if (name.empty() || name.size() > 255) return false;
  for (unsigned char c : name) {
    if (c < 0x20 || c >= 0x7F) return false;
  }
  return true;
}

// ============================================================ invariants, from scratch

std::map<std::string, std::string> ReferenceModel::Trees(const State& s) {
  Partition trees;
  for (const auto& [frame, body] : s.frames) trees.Find(frame);
  for (const PoseEdge& e : s.poses) trees.Join(e.tail, e.head);
  std::map<std::string, std::string> label;  // root -> smallest member
  for (const auto& [frame, body] : s.frames) {
    const std::string r = trees.Find(frame);
    if (!label.count(r) || frame < label[r]) label[r] = frame;
  }
  std::map<std::string, std::string> tree;
  for (const auto& [frame, body] : s.frames) tree[frame] = label[trees.Find(frame)];
  return tree;
}

ReferenceModel::Rule ReferenceModel::Violation(const State& s) {
  // P1: a frame is the head of at most one pose edge.
  std::map<std::string, int> parents;
  for (const PoseEdge& e : s.poses) {
    if (++parents[e.head] > 1) return Rule::kP1;
  }
  // P2: no cycle in the undirected pose graph (self edges included).
  Partition forest;
  for (const PoseEdge& e : s.poses) {
    if (!forest.Join(e.tail, e.head)) return Rule::kP2;
  }
  // P3: per pose tree, the frames of one body are connected through same-body edges only.
  const std::map<std::string, std::string> tree = Trees(s);
  Partition same_body;
  for (const PoseEdge& e : s.poses) {
    if (s.frames.at(e.tail) == s.frames.at(e.head)) same_body.Join(e.tail, e.head);
  }
  std::map<std::pair<std::string, std::string>, std::set<std::string>> pieces;  // (tree, body)
  for (const auto& [frame, body] : s.frames)
    pieces[{tree.at(frame), body}].insert(same_body.Find(frame));
  for (const auto& [key, set] : pieces) {
    if (set.size() > 1) return Rule::kP3;
  }
  // W3: per pose tree P, TG(P) is a forest (no cycle, no parallel edge).
  std::map<std::string, Partition> tg;  // tree -> partition of bodies
  for (const TwistEdge& t : s.twists) {
    if (!tg[tree.at(t.head)].Join(t.tail_body, s.frames.at(t.head))) return Rule::kW3;
  }
  return Rule::kNone;
}

// ============================================================ nodes

ErrorCode ReferenceModel::AddBody(const std::string& name) {
  if (!ValidName(name)) return ErrorCode::kInvalidName;
  if (s_.bodies.count(name)) return ErrorCode::kDuplicateBody;
  s_.bodies.insert(name);
  return ErrorCode::kOk;
}

ErrorCode ReferenceModel::AddFrame(const std::string& name, const std::string& body) {
  if (!ValidName(name) || (!body.empty() && !ValidName(body))) return ErrorCode::kInvalidName;
  if (body.empty()) return ErrorCode::kFrameWithoutBody;
  if (s_.frames.count(name)) return ErrorCode::kDuplicateFrame;
  if (!s_.bodies.count(body)) return ErrorCode::kUnknownBody;
  PutFrame(s_, name, body);
  return ErrorCode::kOk;
}

// ============================================================ pose edges

ErrorCode ReferenceModel::AddPose(const std::string& head, const std::string& head_body,
                                  const std::string& tail, const std::string& tail_body,
                                  const RotationInput& rotation, const Eigen::Vector3d& p,
                                  std::optional<std::int64_t> stamp, const CovarianceIn* cov) {
  // invalid_name (bodies are optional).
  if (!ValidName(head) || !ValidName(tail)) return ErrorCode::kInvalidName;
  if ((!head_body.empty() && !ValidName(head_body)) ||
      (!tail_body.empty() && !ValidName(tail_body))) {
    return ErrorCode::kInvalidName;
  }
  // invalid_number (anywhere) -> invalid_rotation.
  bool finite = Finite(p);
  if (rotation.is_matrix) {
    finite = finite && rotation.R.allFinite();
  } else {
    finite = finite && std::isfinite(rotation.q.w()) && std::isfinite(rotation.q.x()) &&
             std::isfinite(rotation.q.y()) && std::isfinite(rotation.q.z());
  }
  if (!finite) return ErrorCode::kInvalidNumber;
  if (cov && !CovarianceNumbersOk(cov->S)) return ErrorCode::kInvalidNumber;
  Eigen::Matrix3d R;
  if (const ErrorCode c = ValidateRotation(rotation, &R); c != ErrorCode::kOk) return c;
  if (cov && !CovarianceShapeOk(cov->S)) return ErrorCode::kInvalidCovariance;
  const Matrix6 S = cov ? EdgeForm(*cov, R) : Matrix6::Zero();
  // Node resolution, one frame at a time: the head (orientation frame), then the tail. (The
  // spec does not order frame_body_mismatch and frame_without_body of DIFFERENT frames; see
  // the header.)
  const bool head_exists = s_.frames.count(head) > 0, tail_exists = s_.frames.count(tail) > 0;
  for (const auto& [frame, body, exists] :
       {std::tuple{head, head_body, head_exists}, std::tuple{tail, tail_body, tail_exists}}) {
    if (exists && !body.empty() && s_.frames.at(frame) != body)
      return ErrorCode::kFrameBodyMismatch;
    if (!exists && body.empty()) return ErrorCode::kFrameWithoutBody;
  }
  if (head == tail) return ErrorCode::kSelfEdge;
  // The existing edge tail -> head: constant (same body) or updated (different bodies).
  for (PoseEdge& e : s_.poses) {
    if (e.tail != tail || e.head != head) continue;
    if (JointOfChild(s_, head)) return ErrorCode::kJointEdge;  // driven by its joint's state only
    if (s_.frames.at(head) == s_.frames.at(tail)) {
      const bool same_R = (e.X_TH.R - R).cwiseAbs().maxCoeff() <= kConstantTolerance;
      const bool same_p =
          (e.X_TH.p - p).norm() <= kConstantTolerance * std::max(1.0, e.X_TH.p.norm());
      return same_R && same_p && SameCovariance(e.S, cov, S)
                 ? ErrorCode::kOk
                 : ErrorCode::kConstantPoseChange;  // (a stamp is ignored)
    }
    const Transform X{R, p};
    const auto same = [&](const PoseSample& x) { return SamePose(x.X, X); };
    if (const ErrorCode c = CheckStamp(e.stamped, e.samples, stamp, time_, same);
        c != ErrorCode::kOk)
      return c;
    if (!stamp) {
      e.X_TH = X;
      e.S = S;
      return ErrorCode::kOk;
    }
    InsertSample(e.samples, PoseSample{*stamp, X}, time_, same);
    e.X_TH = e.samples.back().X;
    return ErrorCode::kOk;
  }
  // Tentatively: create the missing nodes (docs/rules.md §1), add the edge, check every invariant.
  State next = s_;
  if (!head_exists) {
    next.bodies.insert(head_body);
    PutFrame(next, head, head_body);
  }
  if (!tail_exists) {
    next.bodies.insert(tail_body);
    PutFrame(next, tail, tail_body);
  }
  next.poses.push_back(PoseEdge{tail, head, Transform{R, p}, false, {}, S});
  if (stamp && next.frames.at(head) != next.frames.at(tail)) {  // a stamped edge between bodies
    next.poses.back().stamped = true;
    next.poses.back().samples.push_back(PoseSample{*stamp, Transform{R, p}});
  }
  switch (Violation(next)) {
    case Rule::kP1:
      return ErrorCode::kMultiplePoseParents;
    case Rule::kP2:
      return ErrorCode::kPoseCycle;
    case Rule::kP3:
      return ErrorCode::kDuplicatePosePath;
    case Rule::kW3:
      return ErrorCode::kTwistMergeConflict;
    case Rule::kNone:
      break;
  }
  s_ = std::move(next);
  return ErrorCode::kOk;
}

ErrorCode ReferenceModel::RemovePose(const std::string& of, const std::string& wrt) {
  if (!ValidName(of) || !ValidName(wrt)) return ErrorCode::kInvalidName;
  if (!s_.frames.count(of) || !s_.frames.count(wrt)) return ErrorCode::kUnknownFrame;
  for (std::size_t i = 0; i < s_.poses.size(); ++i) {
    if (s_.poses[i].tail == wrt && s_.poses[i].head == of) {
      if (const Joint* j = JointOfChild(s_, of)) {  // the joint's pose edge: removes the joint
        for (const Joint& m : s_.joints) {
          if (m.master == j->name) return ErrorCode::kJointEdge;  // a live mimic follows it
        }
        const std::string name = j->name;
        s_.twists.erase(std::remove_if(s_.twists.begin(), s_.twists.end(),
                                       [&](const TwistEdge& t) { return t.head == of; }),
                        s_.twists.end());
        s_.joints.erase(std::remove_if(s_.joints.begin(), s_.joints.end(),
                                       [&](const Joint& x) { return x.name == name; }),
                        s_.joints.end());
      }
      s_.poses.erase(s_.poses.begin() + static_cast<std::ptrdiff_t>(i));
      return ErrorCode::kOk;
    }
  }
  return ErrorCode::kNoSuchEdge;
}

// ============================================================ repair (docs/repair.md)

std::vector<std::string> ReferenceModel::Reroot(const std::string& frame) {
  std::vector<std::size_t> path;  // indices of the edges frame..root, walked before changing any
  for (std::string x = frame;;) {
    std::size_t i = 0;
    while (i < s_.poses.size() && s_.poses[i].head != x) ++i;
    if (i == s_.poses.size()) break;
    path.push_back(i);
    x = s_.poses[i].tail;
  }
  std::vector<std::string> keys;
  for (const std::size_t i : path) {
    PoseEdge& e = s_.poses[i];
    keys.push_back(PoseKey(e.tail, e.head));
    e = PoseEdge{e.head, e.tail, Invert(e.X_TH), false, {}, InverseCovariance(e.X_TH, e.S)};
  }
  return keys;
}

RepairOutcome ReferenceModel::AddPoseRepair(const std::string& head, const std::string& head_body,
                                            const std::string& tail, const std::string& tail_body,
                                            const Eigen::Quaterniond& q, const Eigen::Vector3d& p,
                                            const RepairPolicy& policy) {
  RotationInput rotation;
  rotation.q = q;
  RepairOutcome out;
  out.code = AddPose(head, head_body, tail, tail_body, rotation, p);
  if (out.code != ErrorCode::kMultiplePoseParents && out.code != ErrorCode::kPoseCycle) return out;
  // Both codes come after every argument check: the rotation is valid, the head exists.
  Eigen::Matrix3d R;
  ValidateRotation(rotation, &R);
  const std::map<std::string, std::string> tree = Trees(s_);
  const bool determined =
      s_.frames.count(head) && s_.frames.count(tail) && tree.at(head) == tree.at(tail);
  if (determined) {
    if (!policy.check_consistency) return out;
    Transform X_TH;
    Find(head, tail, &X_TH);
    out.has_discrepancy = true;
    out.position = (X_TH.p - p).norm();
    out.angle = RotationAngle(X_TH.R.transpose() * R);
    double scale = 1.0 + p.norm();
    for (const PoseEdge& e : s_.poses) scale += e.X_TH.p.norm();
    out.borderline = NearTolerance(out.position, policy.position_tolerance, 1e-12 * scale) ||
                     NearTolerance(out.angle, policy.angle_tolerance, 1e-12);
    if (out.position <= policy.position_tolerance && out.angle <= policy.angle_tolerance) {
      out.code = ErrorCode::kOk;
      out.applied = RepairKind::kConsistent;
    }
    return out;
  }
  if (out.code != ErrorCode::kMultiplePoseParents || !policy.invert) return out;
  const Transform X_HT = Invert(Transform{R, p});
  RotationInput inverse;
  inverse.is_matrix = true;
  inverse.R = X_HT.R;
  const ErrorCode plain = out.code;
  const ErrorCode inverted = AddPose(tail, tail_body, head, head_body, inverse, X_HT.p);
  if (inverted == ErrorCode::kOk) {
    out.code = ErrorCode::kOk;
    out.applied = RepairKind::kInverted;
    return out;
  }
  if (inverted != ErrorCode::kMultiplePoseParents || !policy.reroot) return out;
  // A joint's pose edge has a direction (parent -> child), a stamped edge's history belongs to
  // it: a path through either is not reversed (docs/repair.md).
  for (std::string x = tail;;) {
    const auto e = std::find_if(s_.poses.begin(), s_.poses.end(),
                                [&](const PoseEdge& pe) { return pe.head == x; });
    if (e == s_.poses.end()) break;
    if (JointOfChild(s_, x) || e->stamped) return out;  // nor one with a stamped edge
    x = e->tail;
  }
  const State saved = s_;
  std::vector<std::string> keys = Reroot(tail);
  if (AddPose(tail, tail_body, head, head_body, inverse, X_HT.p) != ErrorCode::kOk) {
    s_ = saved;
    out.code = plain;
    return out;
  }
  out.code = ErrorCode::kOk;
  out.applied = RepairKind::kRerooted;
  out.reversed_edges = keys.size();
  out.reversed_keys = std::move(keys);
  return out;
}

RepairOutcome ReferenceModel::AddTwistRepair(
    const std::string& point, const std::string& body, const std::string& ref_body,
    const std::string& coord, const Eigen::Vector3d& v, const Eigen::Vector3d& w,
    const RepairPolicy& policy,
    const std::function<std::string(const std::vector<std::string>&)>& choose) {
  RepairOutcome out;
  out.code = AddTwist(point, body, ref_body, coord, v, w);
  if (out.code == ErrorCode::kDuplicateTwistPath) {
    if (!policy.check_consistency) return out;
    Query q;
    q.kind = QueryKind::kTwist;
    q.point = point;
    q.body = body;
    q.ref_body = ref_body;
    q.coord = coord;
    const Answer derived = Ask(q);
    if (derived.code != ErrorCode::kOk) return out;
    out.has_discrepancy = true;
    out.position = (derived.v - v).norm();
    out.angle = (derived.w - w).norm();
    double scale = 1.0 + v.norm() + w.norm();
    double lever = 1.0;
    for (const PoseEdge& e : s_.poses) lever += e.X_TH.p.norm();
    for (const TwistEdge& t : s_.twists) scale += t.v.norm() + t.w.norm() * lever;
    out.borderline = NearTolerance(out.position, policy.position_tolerance, 1e-12 * scale) ||
                     NearTolerance(out.angle, policy.angle_tolerance, 1e-12 * scale);
    if (out.position <= policy.position_tolerance && out.angle <= policy.angle_tolerance) {
      out.code = ErrorCode::kOk;
      out.applied = RepairKind::kConsistent;
    }
    return out;
  }
  if (out.code != ErrorCode::kMultipleTwistParents || !policy.invert) return out;
  // W1 comes after the conversion: the point and [coord] exist, in one tree.
  const std::string C = s_.frames.at(point);
  const std::map<std::string, std::string> tree = Trees(s_);
  std::vector<std::string> candidates;
  for (const auto& [frame, frame_body] : s_.frames) {
    if (frame_body != ref_body || tree.at(frame) != tree.at(point)) continue;
    bool has_parent = false;
    for (const TwistEdge& t : s_.twists) has_parent = has_parent || t.head == frame;
    if (!has_parent) candidates.push_back(frame);
  }
  if (candidates.empty()) return out;
  const std::string h = choose(candidates);
  if (std::find(candidates.begin(), candidates.end(), h) == candidates.end()) return out;
  // The twist of ref_body wrt C: -w, and at {h}: v_h = -v + (-w) x (p_h - p_e), all in [coord].
  Transform X_RE, X_RH;
  Find(point, coord, &X_RE);
  Find(h, coord, &X_RH);
  const Eigen::Vector3d w_inv = -w;
  const Eigen::Vector3d v_inv = -v + w_inv.cross(X_RH.p - X_RE.p);
  const ErrorCode plain = out.code;
  if (AddTwist(h, ref_body, C, coord, v_inv, w_inv) != ErrorCode::kOk) {
    out.code = plain;
    return out;
  }
  out.code = ErrorCode::kOk;
  out.applied = RepairKind::kInverted;
  return out;
}

// ============================================================ joints (docs/kinematics.md)

const Joint* ReferenceModel::JointOfChild(const State& s, const std::string& child) {
  for (const Joint& j : s.joints) {
    if (j.child == child) return &j;
  }
  return nullptr;
}

Transform ReferenceModel::JointPose(const Joint& j, double q) {
  Transform M;  // M(q)
  if (j.type == JointType::kRevolute || j.type == JointType::kContinuous) {
    Eigen::Matrix3d K;  // [u]x
    K << 0, -j.u.z(), j.u.y(), j.u.z(), 0, -j.u.x(), -j.u.y(), j.u.x(), 0;
    M.R = Eigen::Matrix3d::Identity() + std::sin(q) * K + (1.0 - std::cos(q)) * K * K;  // Rodrigues
  } else if (j.type == JointType::kPrismatic) {
    M.p = q * j.u;
  }
  return Compose(j.X_origin, M);
}

void ReferenceModel::Drive(State& s, const std::string& name) {
  for (Joint& j : s.joints) {
    if (j.name != name) continue;
    for (PoseEdge& e : s.poses) {
      if (e.head == j.child) e.X_TH = JointPose(j, j.q);
    }
    for (TwistEdge& t : s.twists) {
      if (t.head != j.child) continue;
      t.v.setZero();
      t.w.setZero();
      // The joint's acceleration in the edge form (at the child's origin, on the axis, in
      // [child]): revolute alpha = u q'', a = 0; prismatic a = u q'', alpha = 0. None given: none.
      t.has_A = j.has_qddot;
      t.a.setZero();
      t.alpha.setZero();
      if (j.type == JointType::kPrismatic) t.v = j.qdot * j.u, t.a = j.qddot * j.u;
      if (j.type == JointType::kRevolute || j.type == JointType::kContinuous) {
        t.w = j.qdot * j.u, t.alpha = j.qddot * j.u;
      }
    }
  }
  for (Joint& m : s.joints) {
    if (m.master != name) continue;
    for (const Joint& j : s.joints) {
      if (j.name != name) continue;
      m.q = m.multiplier * j.q + m.offset, m.qdot = m.multiplier * j.qdot;
      m.qddot = m.multiplier * j.qddot, m.has_qddot = j.has_qddot;
    }
    Drive(s, m.name);
  }
}

ErrorCode ReferenceModel::AddJoint(const JointInput& in) {
  for (const std::string* n :
       {&in.name, &in.parent, &in.parent_body, &in.child, &in.child_body, &in.mimic}) {
    const bool optional = n == &in.parent_body || n == &in.child_body || n == &in.mimic;
    if (!(optional && n->empty()) && !ValidName(*n)) return ErrorCode::kInvalidName;
  }
  if (!Finite(in.p_origin)) return ErrorCode::kInvalidNumber;
  RotationInput rotation;
  rotation.q = in.q_origin;
  Eigen::Matrix3d R;
  if (const ErrorCode c = ValidateRotation(rotation, &R); c != ErrorCode::kOk) return c;
  for (double x :
       {in.axis.x(), in.axis.y(), in.axis.z(), in.lower, in.upper, in.multiplier, in.offset}) {
    if (!std::isfinite(x)) return ErrorCode::kInvalidNumber;
  }
  Joint j;
  j.name = in.name;
  j.type = in.type;
  if (j.movable() && in.axis.norm() < 1e-12) return ErrorCode::kInvalidModel;
  if (j.limited() && !(in.lower <= in.upper)) return ErrorCode::kInvalidModel;
  const Joint* master = nullptr;
  if (!in.mimic.empty()) {
    if (!j.movable()) return ErrorCode::kInvalidModel;
    for (const Joint& m : s_.joints) {
      if (m.name == in.mimic) master = &m;
    }
    if (!master || !master->movable() || !master->master.empty()) return ErrorCode::kInvalidModel;
  }
  for (const Joint& other : s_.joints) {
    if (other.name == in.name) return ErrorCode::kDuplicateJoint;
  }
  const bool child_exists = s_.frames.count(in.child) > 0,
             parent_exists = s_.frames.count(in.parent) > 0;
  for (const auto& [frame, body, exists] : {std::tuple{in.child, in.child_body, child_exists},
                                            std::tuple{in.parent, in.parent_body, parent_exists}}) {
    if (exists && !body.empty() && s_.frames.at(frame) != body)
      return ErrorCode::kFrameBodyMismatch;
    if (!exists && body.empty()) return ErrorCode::kFrameWithoutBody;
  }
  if (in.parent == in.child) return ErrorCode::kSelfEdge;
  const std::string P = parent_exists ? s_.frames.at(in.parent) : in.parent_body;
  const std::string C = child_exists ? s_.frames.at(in.child) : in.child_body;
  if (P == C) return ErrorCode::kTwistSameBody;
  for (const PoseEdge& e : s_.poses) {
    if (e.tail == in.parent && e.head == in.child && JointOfChild(s_, in.child))
      return ErrorCode::kJointEdge;
  }
  j.parent = in.parent;
  j.child = in.child;
  j.parent_body = P;
  j.X_origin = Transform{R, in.p_origin};
  j.u = j.movable() ? Eigen::Vector3d(in.axis / in.axis.norm()) : Eigen::Vector3d::UnitX();
  j.lower = in.lower;
  j.upper = in.upper;
  if (master) {
    j.master = master->name;
    j.multiplier = in.multiplier;
    j.offset = in.offset;
    j.q = j.multiplier * master->q + j.offset;
    j.qdot = j.multiplier * master->qdot;
    j.qddot = j.multiplier * master->qddot, j.has_qddot = master->has_qddot;
  } else if (j.limited()) {
    j.q = std::clamp(0.0, j.lower, j.upper);
  }
  State next = s_;
  next.bodies.insert(P);
  next.bodies.insert(C);
  PutFrame(next, in.child, C);
  PutFrame(next, in.parent, P);
  next.poses.push_back(PoseEdge{in.parent, in.child, Transform{}, false, {}, Matrix6::Zero()});
  switch (Violation(next)) {
    case Rule::kP1:
      return ErrorCode::kMultiplePoseParents;
    case Rule::kP2:
      return ErrorCode::kPoseCycle;
    case Rule::kP3:
      return ErrorCode::kDuplicatePosePath;
    case Rule::kW3:
      return ErrorCode::kTwistMergeConflict;
    case Rule::kNone:
      break;
  }
  for (const TwistEdge& t : next.twists) {
    if (t.head == in.child) return ErrorCode::kMultipleTwistParents;
  }
  next.twists.push_back(TwistEdge{
      P, in.child, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), false, {}, Matrix6::Zero()});
  next.twists.back().serial = next.next_twist_serial++;
  if (Violation(next) != Rule::kNone) return ErrorCode::kDuplicateTwistPath;
  j.serial = next_serial_++;
  next.joints.push_back(j);
  Drive(next, j.name);
  s_ = std::move(next);
  return ErrorCode::kOk;
}

ErrorCode ReferenceModel::CheckJointValues(
    const std::vector<std::pair<std::string, double>>& positions,
    const std::vector<std::pair<std::string, double>>& velocities,
    const std::vector<std::pair<std::string, double>>& accelerations) const {
  const auto find = [&](const std::string& name) -> const Joint* {
    for (const Joint& j : s_.joints) {
      if (j.name == name) return &j;
    }
    return nullptr;
  };
  for (const auto* list : {&positions, &velocities, &accelerations}) {
    for (const auto& [name, value] : *list) {
      if (!std::isfinite(value)) return ErrorCode::kInvalidNumber;
    }
  }
  for (const auto* list : {&positions, &velocities, &accelerations}) {
    for (const auto& [name, value] : *list) {
      if (!find(name) || !find(name)->movable()) return ErrorCode::kUnknownJoint;
    }
  }
  for (const auto* list : {&positions, &velocities, &accelerations}) {
    for (const auto& [name, value] : *list) {
      if (!find(name)->master.empty()) return ErrorCode::kMimicJoint;
    }
  }
  for (const auto& [name, value] : positions) {
    const Joint* j = find(name);
    if (j->limited() && (value < j->lower - 1e-9 || value > j->upper + 1e-9))
      return ErrorCode::kJointLimit;
  }
  return ErrorCode::kOk;
}

ErrorCode ReferenceModel::SetJoints(
    const std::vector<std::pair<std::string, double>>& positions,
    const std::vector<std::pair<std::string, double>>& velocities,
    const std::vector<std::pair<std::string, double>>& accelerations) {
  const auto find = [&](const std::string& name) -> Joint* {
    for (Joint& j : s_.joints) {
      if (j.name == name) return &j;
    }
    return nullptr;
  };
  if (const ErrorCode code = CheckJointValues(positions, velocities, accelerations);
      code != ErrorCode::kOk) {
    return code;
  }
  for (const auto* list : {&positions, &velocities, &accelerations}) {
    for (const auto& [name, value] : *list) {
      if (!find(name)->samples.empty()) return ErrorCode::kStampMismatch;  // a stamped joint
    }
  }
  for (const auto& [name, value] : positions) find(name)->q = value, Drive(s_, name);
  for (const auto& [name, value] : velocities) find(name)->qdot = value, Drive(s_, name);
  for (const auto& [name, value] : accelerations) {
    find(name)->qddot = value, find(name)->has_qddot = true, Drive(s_, name);
  }
  for (const auto* list : {&positions, &velocities, &accelerations}) {
    for (const auto& [name, value] : *list) MarkTimeless(name);
  }
  return ErrorCode::kOk;
}

void ReferenceModel::MarkTimeless(const std::string& joint) {
  for (Joint& j : s_.joints) {
    if (j.name == joint || j.master == joint) j.timeless = true;
  }
}

namespace {
bool NearJointValue(double a, double stored) {
  return std::abs(a - stored) <= 1e-9 * std::max(1.0, std::abs(stored));
}
// A joint sample equals (q, qdot, qddot): a revolute angle modulo a full turn.
bool SameJointSample(const Joint& j, const Joint::Sample& x, double q, double qdot,
                     const double* qddot) {
  const bool same_q = j.type == JointType::kPrismatic
                          ? NearJointValue(q, x.q)
                          : std::abs(std::remainder(q - x.q, 2.0 * std::numbers::pi)) <=
                                1e-9 * std::max(1.0, std::abs(q));
  const bool same_qddot =
      x.has_qddot == (qddot != nullptr) &&
      (!qddot || std::abs(*qddot - x.qddot) <= 1e-6 * std::max(1.0, std::abs(x.qddot)));
  return same_q && NearJointValue(qdot, x.qdot) && same_qddot;
}
}  // namespace

ErrorCode ReferenceModel::CheckJointSample(const Joint& j, double q, double qdot,
                                           const double* qddot, std::int64_t s) const {
  if (j.timeless || j.samples.empty()) return ErrorCode::kStampMismatch;
  if (s < SubSat(j.samples.back().t, time_.window_ns)) return ErrorCode::kStampTooOld;
  for (const Joint::Sample& x : j.samples) {
    if (x.t == s && time_.reject_duplicates && !SameJointSample(j, x, q, qdot, qddot))
      return ErrorCode::kDuplicateStamp;
  }
  return ErrorCode::kOk;
}

void ReferenceModel::StoreJointSample(const std::string& joint, const double* q_given,
                                      const double* qdot_given, const double* qddot_given,
                                      std::int64_t s) {
  Joint* jp = nullptr;
  for (Joint& x : s_.joints) {
    if (x.name == joint) jp = &x;
  }
  Joint& j = *jp;
  Joint::Sample x;
  x.t = s;
  x.q = q_given ? *q_given : j.q;
  x.qdot = qdot_given ? *qdot_given : j.qdot;
  x.has_qddot = qddot_given != nullptr || j.has_qddot;
  x.qddot = qddot_given ? *qddot_given : j.has_qddot ? j.qddot : 0.0;
  const bool newest = j.samples.empty() || s >= j.samples.back().t;
  const auto same = [&](const Joint::Sample& y) {
    return SameJointSample(j, y, x.q, x.qdot, x.has_qddot ? &x.qddot : nullptr);
  };
  bool identical = false;  // the same sample again: a no-op that keeps the stored one (and q)
  for (const Joint::Sample& y : j.samples) identical = identical || (y.t == s && same(y));
  if (!identical) {
    InsertSample(j.samples, x, time_, same);
    if (newest) {
      j.q = x.q, j.qdot = x.qdot;
      if (x.has_qddot) j.qddot = x.qddot, j.has_qddot = true;
    }
  }
  // The edges' samples, made of the joint's (the same stamps, window and capacity).
  for (PoseEdge& e : s_.poses) {
    if (e.head != j.child) continue;
    e.stamped = true;
    e.samples.clear();
    for (const Joint::Sample& y : j.samples)
      e.samples.push_back(PoseSample{y.t, JointPose(j, y.q)});
    e.X_TH = e.samples.back().X;
  }
  for (TwistEdge& t : s_.twists) {
    if (t.head != j.child) continue;
    t.stamped = true;
    t.samples.clear();
    for (const Joint::Sample& y : j.samples) {
      TwistSample z;
      z.t = y.t;
      z.has_A = y.has_qddot;
      if (j.type == JointType::kPrismatic) z.v = y.qdot * j.u, z.a = y.qddot * j.u;
      if (j.type == JointType::kRevolute || j.type == JointType::kContinuous) {
        z.w = y.qdot * j.u, z.alpha = y.qddot * j.u;
      }
      t.samples.push_back(z);
    }
    FromNewest(t);
  }
  std::vector<std::string> mimics;
  for (const Joint& m : s_.joints) {
    if (m.master == joint) mimics.push_back(m.name);
  }
  const double qddot_value = x.has_qddot ? (qddot_given ? *qddot_given : x.qddot) : 0.0;
  for (const std::string& name : mimics) {
    const Joint* m = nullptr;
    for (const Joint& y : s_.joints) {
      if (y.name == name) m = &y;
    }
    const double qm = m->multiplier * x.q + m->offset, qdotm = m->multiplier * x.qdot,
                 qddotm = m->multiplier * qddot_value;
    StoreJointSample(name, &qm, &qdotm, x.has_qddot ? &qddotm : nullptr, s);
  }
}

ErrorCode ReferenceModel::SetJoints(
    const std::vector<std::pair<std::string, double>>& positions,
    const std::vector<std::pair<std::string, double>>& velocities,
    const std::vector<std::pair<std::string, double>>& accelerations, std::int64_t stamp) {
  if (const ErrorCode code = CheckJointValues(positions, velocities, accelerations);
      code != ErrorCode::kOk) {
    return code;
  }
  struct Given {
    std::string name;
    std::optional<double> q, qdot, qddot;
  };
  std::vector<Given> given;  // one sample per joint, in order of first mention
  const auto of = [&](const std::string& name) -> Given& {
    for (Given& g : given) {
      if (g.name == name) return g;
    }
    given.push_back(Given{name, {}, {}, {}});
    return given.back();
  };
  for (const auto& [name, value] : positions) of(name).q = value;
  for (const auto& [name, value] : velocities) of(name).qdot = value;
  for (const auto& [name, value] : accelerations) of(name).qddot = value;
  const auto joint = [&](const std::string& name) -> const Joint& {
    for (const Joint& j : s_.joints) {
      if (j.name == name) return j;
    }
    std::abort();
  };
  ErrorCode worst = ErrorCode::kOk;
  for (const Given& g : given) {
    const Joint& j = joint(g.name);
    const double q = g.q.value_or(j.q), qdot = g.qdot.value_or(j.qdot);
    const bool has_qddot = g.qddot.has_value() || j.has_qddot;
    const double qddot = g.qddot ? *g.qddot : j.has_qddot ? j.qddot : 0.0;
    std::vector<const Joint*> family = {&j};
    for (const Joint& m : s_.joints) {
      if (m.master == j.name) family.push_back(&m);
    }
    for (const Joint* k : family) {
      if (!k->timeless && k->samples.empty()) continue;  // its first sample: no rule
      const double m = k == &j ? 1.0 : k->multiplier, off = k == &j ? 0.0 : k->offset;
      const double qddotk = m * qddot;
      const ErrorCode code =
          CheckJointSample(*k, m * q + off, m * qdot, has_qddot ? &qddotk : nullptr, stamp);
      if (code != ErrorCode::kOk && (worst == ErrorCode::kOk || code < worst)) worst = code;
    }
  }
  if (worst != ErrorCode::kOk) return worst;
  for (const Given& g : given) {
    StoreJointSample(g.name, g.q ? &*g.q : nullptr, g.qdot ? &*g.qdot : nullptr,
                     g.qddot ? &*g.qddot : nullptr, stamp);
  }
  return ErrorCode::kOk;
}

ErrorCode ReferenceModel::SetGroup(const std::vector<std::uint64_t>& group, const double* q,
                                   const double* qdot, const double* qddot, std::int64_t stamp) {
  std::vector<const Joint*> joints;
  bool bad_number = false;
  for (std::size_t i = 0; i < group.size(); ++i) {
    bad_number = bad_number || (q && !std::isfinite(q[i])) || (qdot && !std::isfinite(qdot[i])) ||
                 (qddot && !std::isfinite(qddot[i]));
    const Joint* found = nullptr;
    for (const Joint& j : s_.joints) {
      if (j.serial == group[i]) found = &j;
    }
    joints.push_back(found);
  }
  if (bad_number) return ErrorCode::kInvalidNumber;
  for (const Joint* j : joints) {
    if (!j) return ErrorCode::kUnknownJoint;
  }
  for (std::size_t i = 0; i < group.size(); ++i) {
    if (q && joints[i]->limited() &&
        !(q[i] >= joints[i]->lower - 1e-9 && q[i] <= joints[i]->upper + 1e-9)) {
      return ErrorCode::kJointLimit;
    }
  }
  ErrorCode worst = ErrorCode::kOk;
  for (std::size_t i = 0; i < group.size(); ++i) {
    const Joint& j = *joints[i];
    const double qi = q ? q[i] : j.q, qdoti = qdot ? qdot[i] : j.qdot;
    const double* qddoti = qddot ? qddot + i : j.has_qddot ? &j.qddot : nullptr;
    std::vector<const Joint*> family = {&j};
    for (const Joint& m : s_.joints) {
      if (m.master == j.name) family.push_back(&m);
    }
    for (const Joint* k : family) {
      const double m = k == &j ? 1.0 : k->multiplier, off = k == &j ? 0.0 : k->offset;
      const double qddotk = qddoti ? m * *qddoti : 0.0;
      const ErrorCode code =
          CheckJointSample(*k, m * qi + off, m * qdoti, qddoti ? &qddotk : nullptr, stamp);
      if (code != ErrorCode::kOk && (worst == ErrorCode::kOk || code < worst)) worst = code;
    }
  }
  if (worst != ErrorCode::kOk) return worst;
  std::vector<std::string> names;
  for (const Joint* j : joints) names.push_back(j->name);
  for (std::size_t i = 0; i < names.size(); ++i) {
    StoreJointSample(names[i], q ? q + i : nullptr, qdot ? qdot + i : nullptr,
                     qddot ? qddot + i : nullptr, stamp);
  }
  return ErrorCode::kOk;
}

ErrorCode ReferenceModel::MakeGroup(const std::vector<std::string>& names,
                                    std::vector<std::uint64_t>* serials) const {
  serials->clear();
  for (const std::string& name : names) {
    const Joint* j = nullptr;
    for (const Joint& x : s_.joints) {
      if (x.name == name) j = &x;
    }
    if (!j || !j->movable()) return ErrorCode::kUnknownJoint;
    if (!j->master.empty()) return ErrorCode::kMimicJoint;
    if (std::find(serials->begin(), serials->end(), j->serial) != serials->end())
      return ErrorCode::kDuplicateJoint;
    serials->push_back(j->serial);
  }
  return ErrorCode::kOk;
}

ErrorCode ReferenceModel::SetGroup(const std::vector<std::uint64_t>& group, const double* q,
                                   const double* qdot) {
  std::vector<Joint*> joints;
  bool bad_number = false;
  for (std::size_t i = 0; i < group.size(); ++i) {
    bad_number = bad_number || (q && !std::isfinite(q[i])) || (qdot && !std::isfinite(qdot[i]));
    Joint* found = nullptr;
    for (Joint& j : s_.joints) {
      if (j.serial == group[i]) found = &j;
    }
    joints.push_back(found);
  }
  if (bad_number) return ErrorCode::kInvalidNumber;
  for (const Joint* j : joints) {
    if (!j) return ErrorCode::kUnknownJoint;
  }
  for (std::size_t i = 0; i < group.size(); ++i) {
    if (q && joints[i]->limited() &&
        !(q[i] >= joints[i]->lower - 1e-9 && q[i] <= joints[i]->upper + 1e-9)) {
      return ErrorCode::kJointLimit;
    }
  }
  for (const Joint* j : joints) {
    if (!j->samples.empty()) return ErrorCode::kStampMismatch;  // a stamped joint
  }
  for (std::size_t i = 0; i < group.size(); ++i) {
    if (q) joints[i]->q = q[i];
    if (qdot) joints[i]->qdot = qdot[i];
    Drive(s_, joints[i]->name);
    MarkTimeless(joints[i]->name);
  }
  return ErrorCode::kOk;
}

JacobianAnswer ReferenceModel::Jacobian(const Query& query) const {
  JacobianAnswer out;
  Query q = query;
  q.kind = QueryKind::kTwist;
  out.code = Ask(q).code;
  out.J.resize(6, 0);
  if (out.code != ErrorCode::kOk) return out;
  const std::string C = q.body.empty() ? s_.frames.at(q.point) : q.body;
  if (C == q.ref_body) return out;
  std::vector<std::pair<int, double>> path;
  TwistPath(q.point, C, q.ref_body, &path);
  Transform X_RE;
  Find(q.point, q.coord, &X_RE);
  std::vector<Eigen::Matrix<double, 6, 1>> columns;
  for (const auto& [index, sign] : path) {  // from D to C
    const TwistEdge& t = s_.twists[index];
    const Joint* j = JointOfChild(s_, t.head);
    if (!j || !j->movable()) continue;
    const std::string key = j->master.empty() ? j->name : j->master;
    const double factor = j->master.empty() ? 1.0 : j->multiplier;
    std::size_t c = std::find(out.joints.begin(), out.joints.end(), key) - out.joints.begin();
    if (c == out.joints.size()) {
      out.joints.push_back(key);
      columns.push_back(Eigen::Matrix<double, 6, 1>::Zero());
    }
    // The unit twist at {child} in [child], re-expressed in [r] and moved to e.
    Transform X_RH;
    Find(t.head, q.coord, &X_RH);
    Eigen::Vector3d v_h = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
    if (j->type == JointType::kPrismatic)
      v_h = X_RH.R * j->u;
    else
      w = X_RH.R * j->u;
    columns[c].head<3>() += factor * sign * (v_h + w.cross(X_RE.p - X_RH.p));
    columns[c].tail<3>() += factor * sign * w;
  }
  out.J.resize(6, static_cast<Eigen::Index>(columns.size()));
  for (std::size_t c = 0; c < columns.size(); ++c)
    out.J.col(static_cast<Eigen::Index>(c)) = columns[c];
  return out;
}

// ============================================================ twist edges

ErrorCode ReferenceModel::AddTwist(const std::string& point, const std::string& body,
                                   const std::string& ref_body, const std::string& coord,
                                   const Eigen::Vector3d& v, const Eigen::Vector3d& w,
                                   std::optional<std::int64_t> stamp, const CovarianceIn* cov,
                                   const AccelerationIn* acc) {
  if (!ValidName(point) || !ValidName(ref_body) || !ValidName(coord))
    return ErrorCode::kInvalidName;
  if (!body.empty() && !ValidName(body)) return ErrorCode::kInvalidName;
  if (!Finite(v) || !Finite(w)) return ErrorCode::kInvalidNumber;
  if (acc && (!NumberOk(acc->a) || !NumberOk(acc->alpha))) return ErrorCode::kInvalidNumber;
  if (cov && !CovarianceNumbersOk(cov->S)) return ErrorCode::kInvalidNumber;
  // A twist's covariance has no convention: body is refused as the library does.
  if (cov && (!CovarianceShapeOk(cov->S) || cov->body)) return ErrorCode::kInvalidCovariance;
  Matrix6 S = cov ? EdgeForm(*cov, Eigen::Matrix3d::Identity()) : Matrix6::Zero();
  const bool point_exists = s_.frames.count(point) > 0;
  if (point_exists && !body.empty() && s_.frames.at(point) != body)
    return ErrorCode::kFrameBodyMismatch;
  if (!point_exists && body.empty()) return ErrorCode::kFrameWithoutBody;
  const std::string C = point_exists ? s_.frames.at(point) : body;
  if (C == ref_body) return ErrorCode::kTwistSameBody;
  // Conversion to the screw twist at {point} in [point]: v_e = R_er v, w_e = R_er w.
  Eigen::Vector3d v_e = v, w_e = w;
  Eigen::Vector3d a_e = acc ? acc->a : Eigen::Vector3d::Zero();
  Eigen::Vector3d alpha_e = acc ? acc->alpha : Eigen::Vector3d::Zero();
  if (coord != point) {
    Transform X_ER;
    if (!point_exists || !s_.frames.count(coord) || !Find(coord, point, &X_ER)) {
      return ErrorCode::kTwistNotConvertible;
    }
    if (stamp) {  // converted with the values at the stamp: the orientation of [r] wrt [e]
      Query o;
      o.kind = QueryKind::kOrientation;
      o.orientation = coord;
      o.ref_orientation = o.coord = point;
      TimeQuery at;
      at.kind = TimeQuery::Kind::kAt;
      at.t = *stamp;
      const TimedAnswer a = AskAt(o, at);
      if (a.answer.code == ErrorCode::kExtrapolation) return ErrorCode::kExtrapolation;
      X_ER.R = a.answer.M;
    }
    v_e = X_ER.R * v;
    w_e = X_ER.R * w;
    // The acceleration is given at the same point e: only its frame changes (a vector taken
    // at an instant, re-expressed): a_e = R_er a, alpha_e = R_er alpha.
    if (acc) a_e = X_ER.R * acc->a, alpha_e = X_ER.R * acc->alpha;
    S = Propagate(X_ER.R, Eigen::Matrix3d::Zero(), X_ER.R, S);  // re-expressed, R taken exact
  }
  for (TwistEdge& t : s_.twists) {
    if (t.head != point) continue;
    if (t.tail_body != ref_body) return ErrorCode::kMultipleTwistParents;
    if (JointOfChild(s_, point)) return ErrorCode::kJointEdge;
    const AccelerationIn acc_e{a_e, alpha_e};  // in the edge form, compared as stored
    const auto same = [&](const TwistSample& x) {
      return SameTwist(x, v_e, w_e) && SameSampleAcceleration(x, acc ? &acc_e : nullptr);
    };
    if (const ErrorCode c = CheckStamp(t.stamped, t.samples, stamp, time_, same);
        c != ErrorCode::kOk)
      return c;
    if (!stamp) {
      t.v = v_e;
      t.w = w_e;
      t.S = S;
      t.has_A = acc != nullptr;  // a twist without an acceleration clears the edge's
      t.a = a_e, t.alpha = alpha_e;
      return ErrorCode::kOk;
    }
    // The sample carries the acceleration given with it, or none (never the previous one's).
    InsertSample(t.samples, TwistSample{*stamp, v_e, w_e, acc != nullptr, a_e, alpha_e}, time_,
                 same);
    FromNewest(t);
    return ErrorCode::kOk;
  }
  State next = s_;
  next.bodies.insert(C);
  next.bodies.insert(ref_body);
  PutFrame(next, point, C);
  next.twists.push_back(TwistEdge{ref_body, point, v_e, w_e, stamp.has_value(), {}, S});
  if (stamp) {
    next.twists.back().samples.push_back(
        TwistSample{*stamp, v_e, w_e, acc != nullptr, a_e, alpha_e});
  }
  next.twists.back().has_A = acc != nullptr;
  next.twists.back().a = a_e, next.twists.back().alpha = alpha_e;
  next.twists.back().serial = next.next_twist_serial++;
  if (Violation(next) != Rule::kNone) return ErrorCode::kDuplicateTwistPath;
  s_ = std::move(next);
  return ErrorCode::kOk;
}

ErrorCode ReferenceModel::RemoveTwist(const std::string& point, const std::string& ref_body) {
  if (!ValidName(point) || !ValidName(ref_body)) return ErrorCode::kInvalidName;
  if (!s_.frames.count(point)) return ErrorCode::kUnknownFrame;
  if (!s_.bodies.count(ref_body)) return ErrorCode::kUnknownBody;
  for (std::size_t i = 0; i < s_.twists.size(); ++i) {
    if (s_.twists[i].head == point && s_.twists[i].tail_body == ref_body) {
      if (JointOfChild(s_, point)) return ErrorCode::kJointEdge;
      s_.twists.erase(s_.twists.begin() + static_cast<std::ptrdiff_t>(i));
      return ErrorCode::kOk;
    }
  }
  return ErrorCode::kNoSuchEdge;
}

// ============================================================ search

bool ReferenceModel::Find(const std::string& x, const std::string& y, Transform* X_YX) const {
  std::map<std::string, Transform> seen{{y, Transform{}}};  // node -> X_Y,node
  std::deque<std::string> todo{y};
  while (!todo.empty()) {
    const std::string n = todo.front();
    todo.pop_front();
    if (n == x) {
      *X_YX = seen.at(n);
      return true;
    }
    for (const PoseEdge& e : s_.poses) {
      if (e.tail == n && !seen.count(e.head)) {
        seen[e.head] = Compose(seen.at(n), e.X_TH);
        todo.push_back(e.head);
      } else if (e.head == n && !seen.count(e.tail)) {
        seen[e.tail] = Compose(seen.at(n), Invert(e.X_TH));
        todo.push_back(e.tail);
      }
    }
  }
  return false;
}

bool ReferenceModel::TwistPath(const std::string& e, const std::string& C, const std::string& D,
                               std::vector<std::pair<int, double>>* path) const {
  const std::map<std::string, std::string> tree = Trees(s_);
  // Breadth-first search over the bodies of TG(tree of e), remembering how each was reached.
  std::map<std::string, std::pair<std::string, std::pair<int, double>>> from{{C, {C, {-1, 0.0}}}};
  std::deque<std::string> todo{C};
  while (!todo.empty()) {
    const std::string n = todo.front();
    todo.pop_front();
    for (int i = 0; i < static_cast<int>(s_.twists.size()); ++i) {
      const TwistEdge& t = s_.twists[i];
      if (tree.at(t.head) != tree.at(e)) continue;
      const std::string H = s_.frames.at(t.head);
      // Crossing H -> tail body uses the stored twist (H wrt D); the other way it is inverted.
      if (H == n && !from.count(t.tail_body)) {
        from[t.tail_body] = {n, {i, +1.0}};
        todo.push_back(t.tail_body);
      } else if (t.tail_body == n && !from.count(H)) {
        from[H] = {n, {i, -1.0}};
        todo.push_back(H);
      }
    }
  }
  if (!from.count(D)) return false;
  path->clear();
  for (std::string n = D; n != C; n = from.at(n).first) path->push_back(from.at(n).second);
  return true;
}

// ============================================================ queries

Answer ReferenceModel::Ask(const Query& q) const {
  Answer a;
  const auto fail = [&](ErrorCode c) {
    a.code = c;
    return a;
  };
  const bool twist_kind = q.kind == QueryKind::kTwist || q.kind == QueryKind::kLinearVelocity ||
                          q.kind == QueryKind::kAngularVelocity;
  // The frames each kind reads, with the body each must be on (twists: none), and the bodies.
  std::vector<std::string> frames;
  std::string e, o, f, b, r = q.coord;
  if (q.kind == QueryKind::kPose) {
    e = q.point, o = q.orientation, f = q.ref_point, b = q.ref_orientation;
    frames = {e, o, f, b, r};
  } else if (q.kind == QueryKind::kPosition) {
    e = q.point, f = q.ref_point;
    frames = {e, f, r};
  } else if (q.kind == QueryKind::kOrientation) {
    o = q.orientation, b = q.ref_orientation;
    frames = {o, b, r};
  } else if (q.kind == QueryKind::kAngularVelocity) {
    e = q.coord;  // no point: any point of the tree will do
    frames = {r};
  } else {
    e = q.point;
    frames = {e, r};
  }
  // invalid_name: required names; bodies when given (angular velocity: body required).
  for (const std::string& n : frames) {
    if (!ValidName(n)) return fail(ErrorCode::kInvalidName);
  }
  if (q.kind == QueryKind::kAngularVelocity && q.body.empty()) return fail(ErrorCode::kInvalidName);
  if (twist_kind && q.ref_body.empty()) return fail(ErrorCode::kInvalidName);
  for (const std::string* n : {&q.body, &q.ref_body}) {
    if (!n->empty() && !ValidName(*n)) return fail(ErrorCode::kInvalidName);
  }
  // unknown_frame -> unknown_body.
  for (const std::string& n : frames) {
    if (!s_.frames.count(n)) return fail(ErrorCode::kUnknownFrame);
  }
  const std::string own = q.kind == QueryKind::kOrientation || q.kind == QueryKind::kPose ? o : e;
  const std::string C = q.body.empty() ? s_.frames.at(own) : q.body;
  const std::string D =
      q.ref_body.empty() ? s_.frames.at(q.kind == QueryKind::kPosition ? f : b) : q.ref_body;
  if (!s_.bodies.count(C) || !s_.bodies.count(D)) return fail(ErrorCode::kUnknownBody);
  // frame_body_mismatch (pose kinds: every point / orientation frame is on its named body).
  if (!twist_kind) {
    for (const std::string* x : {&e, &o}) {
      if (!x->empty() && s_.frames.at(*x) != C) return fail(ErrorCode::kFrameBodyMismatch);
    }
    for (const std::string* x : {&f, &b}) {
      if (!x->empty() && s_.frames.at(*x) != D) return fail(ErrorCode::kFrameBodyMismatch);
    }
  }
  // no_pose_path: every frame the query reads in one pose tree.
  Transform unused;
  for (const std::string& n : frames) {
    if (!Find(n, r, &unused)) return fail(ErrorCode::kNoPosePath);
  }
  // representation_constraint (docs/rules.md §11): homogeneous poses need e = a, f = b, r = b;
  // orientations r = b.
  if (representation_ == Representation::kHomogeneous) {
    if (q.kind == QueryKind::kPose && (e != o || f != b || r != b)) {
      return fail(ErrorCode::kRepresentationConstraint);
    }
    if (q.kind == QueryKind::kOrientation && r != b)
      return fail(ErrorCode::kRepresentationConstraint);
  }
  // Values, from the poses of the frames in [r] (X_RN: pose of n wrt r, in [r]).
  const auto X_R = [&](const std::string& n) {
    Transform X;
    Find(n, r, &X);
    return X;
  };
  if (!twist_kind) {
    // Orientation operator of [o] wrt [b] in [r]: R_rb R_bo R_br = R_rb (R_br R_ro) R_br = R_ro
    // R_br.
    if (!o.empty()) a.M = X_R(o).R * X_R(b).R.transpose();
    if (!e.empty()) a.p = X_R(e).p - X_R(f).p;
    return a;
  }
  if (C == D) return a;  // zero
  std::vector<std::pair<int, double>> path;
  if (!TwistPath(e, C, D, &path)) return fail(ErrorCode::kNoTwistPath);
  const Eigen::Vector3d p_e = X_R(e).p;
  for (const auto& [index, sign] : path) {
    const TwistEdge& t = s_.twists[index];
    const Transform X_RH = X_R(t.head);
    const Eigen::Vector3d w = X_RH.R * t.w;
    const Eigen::Vector3d v_h = X_RH.R * t.v;
    a.w += sign * w;
    a.v += sign * (v_h + w.cross(p_e - X_RH.p));  // v_e = v_h + w x (p_e - p_h)
  }
  if (q.kind == QueryKind::kLinearVelocity) a.w.setZero();  // only the asked part
  if (q.kind == QueryKind::kAngularVelocity) a.v.setZero();
  return a;
}

// ============================================================ time (docs/time.md)

bool ReferenceModel::ValuesAt(std::int64_t t, std::int64_t horizon,
                              const std::set<std::string>& used, State* at,
                              TimedAnswer* report) const {
  const auto read = [&](std::int64_t s) {
    report->oldest = report->oldest ? std::min(*report->oldest, s) : s;
    report->newest = report->newest ? std::max(*report->newest, s) : s;
  };
  for (PoseEdge& e : at->poses) {
    if (!e.stamped || !used.count(PoseKey(e.tail, e.head))) continue;
    const std::vector<PoseSample>& S = e.samples;
    if (t >= S.front().t && t <= S.back().t) {
      std::size_t i = 0;
      while (S[i].t < t) ++i;  // S[i].t >= t
      if (S[i].t == t) {
        e.X_TH = S[i].X;
        read(t);
        continue;
      }
      const PoseSample &a = S[i - 1], &b = S[i];
      const double lambda = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
      read(a.t);
      read(b.t);
      bool near_pi = false;
      if (time_.linear) {  // lerp + slerp (the geodesic of the relative rotation, shorter arc)
        const Eigen::Vector3d w = RotLog(a.X.R.transpose() * b.X.R, &near_pi);
        e.X_TH = Transform{a.X.R * RotExp(lambda * w), (1.0 - lambda) * a.X.p + lambda * b.X.p};
      } else {  // screw: X_a Exp(lambda Log(X_a^-1 X_b))
        Eigen::Vector3d v, w;
        SE3Log(Compose(Invert(a.X), b.X), &v, &w, &near_pi);
        e.X_TH = Compose(a.X, SE3Exp(lambda * v, lambda * w));
      }
      report->ambiguous = report->ambiguous || near_pi;
      continue;
    }
    const PoseSample& k = t < S.front().t ? S.front() : S.back();
    if (!(horizon > 0 && std::abs(static_cast<double>(t) - static_cast<double>(k.t)) <=
                             static_cast<double>(horizon))) {
      return false;
    }
    // Integrated with the edge's screw twist TwistCoord(h|H, T, [h]) at s_k from the twist edges.
    Query xi;
    xi.kind = QueryKind::kTwist;
    xi.point = xi.coord = e.head;
    xi.body = s_.frames.at(e.head);
    xi.ref_body = s_.frames.at(e.tail);
    TimeQuery at_k;
    at_k.kind = TimeQuery::Kind::kAt;
    at_k.t = k.t;
    const TimedAnswer twist = AskAt(xi, at_k);
    if (twist.answer.code != ErrorCode::kOk) return false;
    const double dt = static_cast<double>(t - k.t) * 1e-9;
    e.X_TH = Compose(k.X, SE3Exp(dt * twist.answer.v, dt * twist.answer.w));
    report->extrapolated = true;
    report->ambiguous = report->ambiguous || twist.ambiguous;
    read(k.t);
  }
  for (TwistEdge& e : at->twists) {
    if (!e.stamped || !used.count(TwistKey(e.tail_body, e.head))) continue;
    const std::vector<TwistSample>& S = e.samples;
    if (t >= S.front().t && t <= S.back().t) {
      std::size_t i = 0;
      while (S[i].t < t) ++i;
      if (S[i].t == t) {
        e.v = S[i].v, e.w = S[i].w;
        e.has_A = S[i].has_A, e.a = S[i].a, e.alpha = S[i].alpha;
        read(t);
        continue;
      }
      const TwistSample &a = S[i - 1], &b = S[i];
      const double lambda = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
      e.v = (1.0 - lambda) * a.v + lambda * b.v;
      e.w = (1.0 - lambda) * a.w + lambda * b.w;
      // An acceleration only when both samples carry one (no implicit zero), interpolated alike.
      e.has_A = a.has_A && b.has_A;
      e.a = (1.0 - lambda) * a.a + lambda * b.a;
      e.alpha = (1.0 - lambda) * a.alpha + lambda * b.alpha;
      read(a.t);
      read(b.t);
      continue;
    }
    const TwistSample& k = t < S.front().t ? S.front() : S.back();
    if (!(horizon > 0 && std::abs(static_cast<double>(t) - static_cast<double>(k.t)) <=
                             static_cast<double>(horizon))) {
      return false;
    }
    e.v = k.v, e.w = k.w;  // held, with its acceleration
    e.has_A = k.has_A, e.a = k.a, e.alpha = k.alpha;
    report->extrapolated = true;
    read(k.t);
  }
  return true;
}

TimedAnswer ReferenceModel::AskAt(const Query& q, const TimeQuery& policy) const {
  ReferenceModel at = *this;
  return AskAtWith(q, policy, &at);
}

ReferenceModel::TimedAcceleration ReferenceModel::AskAccelerationAt(const Query& q,
                                                                    const TimeQuery& policy) const {
  ReferenceModel at = *this;
  const TimedAnswer twist = AskAtWith(q, policy, &at);
  TimedAcceleration out;
  out.time = twist.time, out.oldest = twist.oldest, out.newest = twist.newest;
  out.extrapolated = twist.extrapolated;
  out.ambiguous = twist.ambiguous;
  out.answer.code = twist.answer.code;
  if (out.answer.code != ErrorCode::kOk) return out;
  out.answer = at.AskAcceleration(q);  // the values (and accelerations) at the time
  return out;
}

TimedAnswer ReferenceModel::AskAtWith(const Query& q, const TimeQuery& policy,
                                      ReferenceModel* at_model) const {
  ReferenceModel& at = *at_model;  // a copy of *this
  TimedAnswer out;
  out.answer = Ask(q);
  if (out.answer.code == ErrorCode::kInvalidName) return out;
  if (policy.kind == TimeQuery::Kind::kAt && policy.horizon < 0) {
    out.answer = Answer{};
    out.answer.code = ErrorCode::kInvalidNumber;
    return out;
  }
  if (out.answer.code != ErrorCode::kOk) return out;
  const bool twist_kind = q.kind == QueryKind::kTwist || q.kind == QueryKind::kLinearVelocity ||
                          q.kind == QueryKind::kAngularVelocity;
  const std::string& own = q.kind == QueryKind::kAngularVelocity ? q.coord : q.point;
  const bool zero = twist_kind && (q.body.empty() ? s_.frames.at(own) : q.body) == q.ref_body;
  const std::set<std::string> used = zero ? std::set<std::string>{} : UsedEdges(q);
  // The used stamped edges' newest stamps.
  std::vector<std::int64_t> newest;
  for (const PoseEdge& e : s_.poses) {
    if (e.stamped && used.count(PoseKey(e.tail, e.head))) newest.push_back(e.samples.back().t);
  }
  for (const TwistEdge& e : s_.twists) {
    if (e.stamped && used.count(TwistKey(e.tail_body, e.head)))
      newest.push_back(e.samples.back().t);
  }
  std::optional<std::int64_t> t;
  if (policy.kind == TimeQuery::Kind::kAt) t = policy.t;
  if (policy.kind == TimeQuery::Kind::kLatestCommon && !newest.empty()) {
    t = *std::min_element(newest.begin(), newest.end());
  }
  if (t) {
    if (!ValuesAt(*t, policy.kind == TimeQuery::Kind::kAt ? policy.horizon : 0, used, &at.s_,
                  &out)) {
      out.answer = Answer{};
      out.answer.code = ErrorCode::kExtrapolation;
      return out;
    }
  } else {
    for (const std::int64_t s : newest) {  // latest: each edge's newest sample is read
      out.oldest = out.oldest ? std::min(*out.oldest, s) : s;
      out.newest = out.newest ? std::max(*out.newest, s) : s;
    }
  }
  if (policy.not_before) {
    for (const std::int64_t s : newest) {
      if (s < *policy.not_before) {
        out.answer = Answer{};
        out.answer.code = ErrorCode::kStale;
        return out;
      }
    }
  }
  out.time = t;
  out.answer = at.Ask(q);
  return out;
}

std::set<std::string> ReferenceModel::UsedEdges(const Query& q) const {
  std::set<std::string> used;
  std::set<std::string> terminals;  // the frames the query reads
  switch (q.kind) {
    case QueryKind::kPose:
      terminals = {q.point, q.orientation, q.ref_point, q.ref_orientation, q.coord};
      break;
    case QueryKind::kPosition:
      terminals = {q.point, q.ref_point, q.coord};
      break;
    case QueryKind::kOrientation:
      terminals = {q.orientation, q.ref_orientation, q.coord};
      break;
    default: {
      const std::string e = q.kind == QueryKind::kAngularVelocity ? q.coord : q.point;
      terminals = {e, q.coord};
      const std::string C = q.body.empty() ? s_.frames.at(e) : q.body;
      std::vector<std::pair<int, double>> path;
      if (C != q.ref_body && TwistPath(e, C, q.ref_body, &path)) {
        for (const auto& [index, sign] : path) {
          used.insert(TwistKey(s_.twists[index].tail_body, s_.twists[index].head));
          terminals.insert(s_.twists[index].head);
        }
      }
    }
  }
  // A pose edge is used when removing it separates two terminals.
  for (std::size_t i = 0; i < s_.poses.size(); ++i) {
    ReferenceModel without = *this;
    without.s_.poses.erase(without.s_.poses.begin() + static_cast<std::ptrdiff_t>(i));
    Transform unused;
    for (const std::string& n : terminals) {
      if (!without.Find(n, *terminals.begin(), &unused)) {
        used.insert(PoseKey(s_.poses[i].tail, s_.poses[i].head));
        break;
      }
    }
  }
  return used;
}

// ============================================================ wrenches

void ReferenceModel::PutFrame(State& s, const std::string& frame, const std::string& body) {
  if (!s.frames.count(frame)) s.frame_order.push_back(frame);
  s.frames[frame] = body;
}

bool ReferenceModel::SameTree(const std::string& x, const std::string& y) const {
  Transform unused;
  return Find(x, y, &unused);
}

namespace {
bool ValidWrenchNumbers(const Eigen::Vector3d& f, const Eigen::Vector3d& m) {
  for (int i = 0; i < 3; ++i) {
    for (double x : {f[i], m[i]}) {
      if (!std::isfinite(x) || std::abs(x) > kMaxMagnitude) return false;
    }
  }
  return true;
}
}  // namespace

ErrorCode ReferenceModel::AddWrench(const std::string& on, const std::string& by,
                                    const std::string& point, const std::string& coord,
                                    const Eigen::Vector3d& f, const Eigen::Vector3d& m) {
  if (!ValidName(on) || !ValidName(by) || !ValidName(point) || !ValidName(coord)) {
    return ErrorCode::kInvalidName;
  }
  if (!ValidWrenchNumbers(f, m)) return ErrorCode::kInvalidNumber;
  if (!s_.frames.count(point) || !s_.frames.count(coord)) return ErrorCode::kUnknownFrame;
  if (!s_.bodies.count(on) || !s_.bodies.count(by)) return ErrorCode::kUnknownBody;
  if (on == by) return ErrorCode::kSelfWrench;
  WrenchEntry* existing = nullptr;
  for (WrenchEntry& w : s_.wrenches) {
    if (w.on == on && w.by == by) existing = &w;
  }
  // The storage frame: kept by an update, else chosen (the newest frame of C in the tree).
  std::string frame;
  if (existing) {
    frame = existing->frame;
  } else if (s_.frames.at(point) == on) {
    frame = point;
  } else if (s_.frames.at(coord) == on) {
    frame = coord;
  } else {
    for (const std::string& x : s_.frame_order) {
      if (s_.frames.at(x) == on && SameTree(x, point)) frame = x;  // the last one made wins
    }
  }
  if (frame.empty() || !SameTree(frame, point) || !SameTree(frame, coord)) {
    return ErrorCode::kWrenchNotConvertible;
  }
  for (const WrenchEntry& w : s_.wrenches) {
    if (w.on == by && w.by == on) return ErrorCode::kDuplicateWrench;
  }
  Transform X_SE, X_SR;  // the point and the coordinate frame relative to s, in [s]
  Find(point, frame, &X_SE);
  Find(coord, frame, &X_SR);
  WrenchEntry w{on, by, frame, X_SR.R * f, Eigen::Vector3d::Zero(), 0};
  w.m = X_SR.R * m + X_SE.p.cross(w.f);
  w.scale = (f.norm() + m.norm()) * (1 + X_SE.p.norm());
  if (existing) {
    w.serial = existing->serial;
    *existing = w;
  } else {
    w.serial = s_.next_wrench_serial++;
    s_.wrenches.push_back(w);
  }
  return ErrorCode::kOk;
}

ErrorCode ReferenceModel::FindWrench(const std::string& on, const std::string& by,
                                     std::uint64_t* serial) const {
  if (!ValidName(on) || !ValidName(by)) return ErrorCode::kInvalidName;
  if (!s_.bodies.count(on) || !s_.bodies.count(by)) return ErrorCode::kUnknownBody;
  if (on == by) return ErrorCode::kSelfWrench;
  for (const WrenchEntry& w : s_.wrenches) {
    if (w.on == on && w.by == by) {
      *serial = w.serial;
      return ErrorCode::kOk;
    }
  }
  return ErrorCode::kNoWrench;
}

ErrorCode ReferenceModel::SetWrench(const std::string& on, const std::string& by,
                                    std::uint64_t serial, const Eigen::Vector3d& f_S,
                                    const Eigen::Vector3d& m_S) {
  for (WrenchEntry& w : s_.wrenches) {
    if (w.on != on || w.by != by || w.serial != serial) continue;
    if (!ValidWrenchNumbers(f_S, m_S)) return ErrorCode::kInvalidNumber;
    w.f = f_S;
    w.m = m_S;
    w.scale = f_S.norm() + m_S.norm();
    return ErrorCode::kOk;
  }
  return ErrorCode::kNoWrench;
}

ErrorCode ReferenceModel::RemoveWrench(const std::string& on, const std::string& by) {
  if (!ValidName(on) || !ValidName(by)) return ErrorCode::kInvalidName;
  if (!s_.bodies.count(on) || !s_.bodies.count(by)) return ErrorCode::kUnknownBody;
  if (on == by) return ErrorCode::kSelfWrench;
  for (std::size_t i = 0; i < s_.wrenches.size(); ++i) {
    if (s_.wrenches[i].on == on && s_.wrenches[i].by == by) {
      s_.wrenches.erase(s_.wrenches.begin() + static_cast<std::ptrdiff_t>(i));
      return ErrorCode::kOk;
    }
  }
  return ErrorCode::kNoWrench;
}

WrenchAnswer ReferenceModel::AskWrench(const std::string& on, const std::string& by,
                                       const std::string& point, const std::string& coord) const {
  WrenchAnswer a;
  const auto fail = [&a](ErrorCode code) {
    a.code = code;
    return a;
  };
  if (!ValidName(on) || (!by.empty() && !ValidName(by)) || !ValidName(point) || !ValidName(coord)) {
    return fail(ErrorCode::kInvalidName);
  }
  if (!s_.frames.count(point) || !s_.frames.count(coord)) return fail(ErrorCode::kUnknownFrame);
  if (!s_.bodies.count(on) || (!by.empty() && !s_.bodies.count(by))) {
    return fail(ErrorCode::kUnknownBody);
  }
  if (on == by) return fail(ErrorCode::kSelfWrench);
  const std::vector<std::uint64_t> serials = WrenchTerms(on, by);
  if (serials.empty()) return fail(ErrorCode::kNoWrench);
  return AskWrenchTerms(serials, on, point, coord);
}

std::vector<std::uint64_t> ReferenceModel::WrenchTerms(const std::string& on,
                                                       const std::string& by) const {
  std::vector<std::uint64_t> serials;
  for (const WrenchEntry& w : s_.wrenches) {
    if ((w.on == on && (by.empty() || w.by == by)) || (w.by == on && (by.empty() || w.on == by))) {
      serials.push_back(w.serial);
    }
  }
  return serials;
}

WrenchAnswer ReferenceModel::AskWrenchTerms(const std::vector<std::uint64_t>& serials,
                                            const std::string& on, const std::string& point,
                                            const std::string& coord) const {
  WrenchAnswer a;
  std::vector<std::pair<double, const WrenchEntry*>> terms;
  for (const WrenchEntry& w : s_.wrenches) {
    if (std::find(serials.begin(), serials.end(), w.serial) == serials.end()) continue;
    terms.emplace_back(w.on == on ? 1.0 : -1.0, &w);  // a wrench by `on`: its reaction
  }
  for (const auto& [sign, w] : terms) {
    Transform X_RS, X_ES, X_RE;  // s wrt [r]; s wrt e (in [e]); e wrt [r]
    if (!Find(w->frame, coord, &X_RS) || !Find(w->frame, point, &X_ES) ||
        !Find(point, coord, &X_RE)) {
      a.code = ErrorCode::kNoPosePath;
      return a;
    }
    const Eigen::Vector3d f = sign * (X_RS.R * w->f);
    a.f += f;
    a.m += sign * (X_RS.R * w->m) + (X_RE.R * X_ES.p).cross(f);
    a.scale += (w->f.norm() + w->m.norm()) * (1 + X_ES.p.norm()) + w->scale;
  }
  return a;
}

// ============================================================ accelerations (docs/dynamics.md §1)
//
// The model's own formulas. Notation: for bodies X, Y and a point e, (w_XY, v_XYe) the twist of
// Y relative to X at e and (alpha_XY, a_XYe) its acceleration (a: the classical acceleration of
// the point of Y at e, a second derivative taken in X), all vectors at one instant in one frame.
//
// (1) Change of point within one body Y, r = q - p (both points fixed in Y): differentiating
//     v_q = v_p + w x r twice in X, with dr/dt (in X) = w x r:
//       a_q = a_p + alpha x r + w x (w x r).
// (2) Composition, Y relative to X through Z (Y's point e moving in Z, Z moving in X): the
//     classical five-term formula with e's position taken from Z's point at e gives
//       alpha_XY = alpha_XZ + alpha_ZY + w_XZ x w_ZY,
//       a_XYe   = a_XZe + a_ZYe + 2 w_XZ x v_ZYe
//     (a_XZe: the acceleration of the point of Z at e, by (1) from wherever Z's is known; the
//     centripetal and Euler terms of e in Z are in a_XZe, the 2 w x v term is Coriolis).
// (3) Inverse, X relative to Y at e: from (2) with Y -> X -> Y, whose motion is zero:
//       0 = alpha_YX + alpha_XY + w_YX x w_XY = alpha_YX + alpha_XY  (w_YX = -w_XY)
//       0 = a_YXe + a_XYe + 2 w_YX x v_XYe = a_YXe + a_XYe - 2 w_XY x v_XYe
//     hence alpha_YX = -alpha_XY and a_YXe = -a_XYe + 2 w_XY x v_XYe.
// (4) Change of frame: each vector rotated, v_[r] = R_rh v_[h] (no derivative is involved).

ErrorCode ReferenceModel::AddAcceleration(const std::string& point, const std::string& body,
                                          const std::string& ref_body, const std::string& coord,
                                          const Eigen::Vector3d& a, const Eigen::Vector3d& alpha,
                                          std::optional<std::int64_t> stamp) {
  if (!ValidName(point) || !ValidName(ref_body) || !ValidName(coord))
    return ErrorCode::kInvalidName;
  if (!body.empty() && !ValidName(body)) return ErrorCode::kInvalidName;
  if (!NumberOk(a) || !NumberOk(alpha)) return ErrorCode::kInvalidNumber;
  if (!s_.frames.count(point) || !s_.frames.count(coord)) return ErrorCode::kUnknownFrame;
  const std::string C = body.empty() ? s_.frames.at(point) : body;
  if (!s_.bodies.count(C) || !s_.bodies.count(ref_body)) return ErrorCode::kUnknownBody;
  // The edge ref_body -> {h}|C, or C -> {h}|ref_body (against: it holds the inverse relation),
  // with h in the tree of {point} (at most one: W3).
  TwistEdge* edge = nullptr;
  bool against = false;
  Transform unused;
  for (TwistEdge& t : s_.twists) {
    if (!Find(t.head, point, &unused)) continue;
    if (t.tail_body == ref_body && s_.frames.at(t.head) == C) edge = &t, against = false;
    if (t.tail_body == C && s_.frames.at(t.head) == ref_body) edge = &t, against = true;
  }
  if (edge == nullptr) return ErrorCode::kNoSuchEdge;
  if (JointOfChild(s_, edge->head)) return ErrorCode::kJointEdge;
  if (edge->stamped != stamp.has_value()) return ErrorCode::kStampMismatch;
  Transform X_HR, X_HE;  // [coord] wrt [h]; e wrt h, in [h]
  if (!Find(coord, edge->head, &X_HR)) return ErrorCode::kAccelerationNotConvertible;
  Find(point, edge->head, &X_HE);
  // The twist it goes with: the edge's, or (stamped) its sample at exactly the stamp, with the
  // poses read at the stamp (none there: not convertible).
  Eigen::Vector3d v = edge->v, w = edge->w;
  std::size_t sample = 0;
  if (stamp) {
    while (sample < edge->samples.size() && edge->samples[sample].t != *stamp) ++sample;
    if (sample == edge->samples.size()) return ErrorCode::kAccelerationNotConvertible;
    v = edge->samples[sample].v, w = edge->samples[sample].w;
    TimeQuery at;
    at.kind = TimeQuery::Kind::kAt;
    at.t = *stamp;
    Query o;  // the orientation of [coord] wrt [h]
    o.kind = QueryKind::kOrientation;
    o.orientation = coord;
    o.ref_orientation = o.coord = edge->head;
    Query x;  // the position of e wrt h, in [h]
    x.kind = QueryKind::kPosition;
    x.point = point;
    x.ref_point = x.coord = edge->head;
    const TimedAnswer R_at = AskAt(o, at), p_at = AskAt(x, at);
    if (R_at.answer.code != ErrorCode::kOk || p_at.answer.code != ErrorCode::kOk)
      return ErrorCode::kAccelerationNotConvertible;
    X_HR.R = R_at.answer.M;
    X_HE.p = p_at.answer.p;
  }
  // (4) into [h]; then (1) from the point e of C to h's origin: r = p_h - p_e = -p_HE, with the
  // angular velocity of C relative to ref_body: the edge's w (in [h]), or -w against it.
  const Eigen::Vector3d alpha_h = X_HR.R * alpha;
  const Eigen::Vector3d r = -X_HE.p;
  const Eigen::Vector3d w_given = against ? Eigen::Vector3d(-w) : w;
  const Eigen::Vector3d a_h = X_HR.R * a + alpha_h.cross(r) + w_given.cross(w_given.cross(r));
  // Against the edge, (3) at h: the edge's relation is the inverse of the given one, whose twist
  // at h is (-v, -w): alpha_edge = -alpha_h, a_edge = -a_h + 2 (-w) x (-v).
  const Eigen::Vector3d a_edge = against ? Eigen::Vector3d(-a_h + 2.0 * w.cross(v)) : a_h;
  const Eigen::Vector3d alpha_edge = against ? Eigen::Vector3d(-alpha_h) : alpha_h;
  if (stamp) return StoreSampleAcceleration(*edge, sample, a_edge, alpha_edge);
  edge->a = a_edge;
  edge->alpha = alpha_edge;
  edge->has_A = true;
  return ErrorCode::kOk;
}

ErrorCode ReferenceModel::StoreSampleAcceleration(TwistEdge& t, std::size_t sample,
                                                  const Eigen::Vector3d& a,
                                                  const Eigen::Vector3d& alpha) const {
  TwistSample& x = t.samples[sample];
  const AccelerationIn A{a, alpha};
  if (x.has_A) {
    if (SameSampleAcceleration(x, &A)) return ErrorCode::kOk;  // the same again: no change
    if (time_.reject_duplicates) return ErrorCode::kDuplicateStamp;
  }
  x.has_A = true, x.a = a, x.alpha = alpha;
  FromNewest(t);
  return ErrorCode::kOk;
}

ErrorCode ReferenceModel::FindTwist(const std::string& of, const std::string& wrt,
                                    std::uint64_t* serial) const {
  if (!ValidName(of) || !ValidName(wrt)) return ErrorCode::kInvalidName;
  if (!s_.frames.count(of)) return ErrorCode::kUnknownFrame;
  if (!s_.bodies.count(wrt)) return ErrorCode::kUnknownBody;
  for (const TwistEdge& t : s_.twists) {
    if (t.head != of || t.tail_body != wrt) continue;
    if (JointOfChild(s_, of)) return ErrorCode::kJointEdge;
    *serial = t.serial;
    return ErrorCode::kOk;
  }
  return ErrorCode::kNoSuchEdge;
}

ErrorCode ReferenceModel::SetTwist(std::uint64_t serial, const Eigen::Vector3d& v,
                                   const Eigen::Vector3d& w) {
  for (TwistEdge& t : s_.twists) {
    if (t.serial != serial) continue;
    if (!NumberOk(v) || !NumberOk(w)) return ErrorCode::kInvalidNumber;
    if (t.stamped) return ErrorCode::kStampMismatch;
    t.v = v, t.w = w;
    t.S = Matrix6::Zero();
    t.has_A = false;
    return ErrorCode::kOk;
  }
  return ErrorCode::kNoSuchEdge;
}

ErrorCode ReferenceModel::SetAcceleration(std::uint64_t serial, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& alpha,
                                          std::optional<std::int64_t> stamp) {
  for (TwistEdge& t : s_.twists) {
    if (t.serial != serial) continue;
    if (JointOfChild(s_, t.head)) return ErrorCode::kJointEdge;
    if (t.stamped != stamp.has_value()) return ErrorCode::kStampMismatch;
    std::size_t sample = 0;  // stamped: the twist sample at exactly the stamp
    if (stamp) {
      while (sample < t.samples.size() && t.samples[sample].t != *stamp) ++sample;
      if (sample == t.samples.size()) return ErrorCode::kStampMismatch;
    }
    if (!NumberOk(a) || !NumberOk(alpha)) return ErrorCode::kInvalidNumber;
    if (stamp) return StoreSampleAcceleration(t, sample, a, alpha);
    t.a = a, t.alpha = alpha, t.has_A = true;
    return ErrorCode::kOk;
  }
  return ErrorCode::kNoSuchEdge;
}

AccelerationAnswer ReferenceModel::AskAcceleration(const Query& q) const {
  AccelerationAnswer out;
  out.code = Ask(q).code;  // the twist query's errors (and its zero for C == D)
  if (out.code != ErrorCode::kOk) return out;
  const std::string& e = q.kind == QueryKind::kAngularVelocity ? q.coord : q.point;
  const std::string C = q.body.empty() ? s_.frames.at(e) : q.body;
  const std::string& D = q.ref_body;
  if (C == D) return out;                    // zero
  std::vector<std::pair<int, double>> path;  // from D to C
  TwistPath(e, C, D, &path);
  for (const auto& [index, sign] : path) {
    if (!s_.twists[index].has_A) {
      out.code = ErrorCode::kNoAcceleration;
      return out;
    }
  }
  const auto X_R = [&](const std::string& n) {
    Transform X;
    Find(n, q.coord, &X);
    return X;
  };
  const Eigen::Vector3d p_e = X_R(e).p;
  // The motion of B_i relative to D (B_0 = D), at e in [r], composed edge by edge by (2).
  Eigen::Vector3d w = Eigen::Vector3d::Zero(), v = w, alpha = w, a = w;
  for (const auto& [index, sign] : path) {
    const TwistEdge& t = s_.twists[index];
    const Transform X_RH = X_R(t.head);
    // The edge's motion (H relative to its tail body) at h, in [r] (4); then at e (1).
    const Eigen::Vector3d w_i = X_RH.R * t.w, alpha_i = X_RH.R * t.alpha;
    const Eigen::Vector3d r = p_e - X_RH.p;
    Eigen::Vector3d v_i = X_RH.R * t.v + w_i.cross(r);
    Eigen::Vector3d a_i = X_RH.R * t.a + alpha_i.cross(r) + w_i.cross(w_i.cross(r));
    Eigen::Vector3d ww = w_i, aa = alpha_i;
    if (sign < 0) {  // crossed from H to the tail body: the inverse (3)
      a_i = -a_i + 2.0 * w_i.cross(v_i);
      v_i = -v_i;
      ww = -w_i;
      aa = -alpha_i;
    }
    // (2): the step is B_{i+1} relative to B_i; (w, v, alpha, a) is B_i relative to D.
    alpha += aa + w.cross(ww);
    a += a_i + 2.0 * w.cross(v_i);
    w += ww;
    v += v_i;
  }
  out.a = a;
  out.alpha = alpha;
  if (q.kind == QueryKind::kLinearVelocity) out.alpha.setZero();  // only the asked part
  if (q.kind == QueryKind::kAngularVelocity) out.a.setZero();
  return out;
}

}  // namespace semgraph::reference
