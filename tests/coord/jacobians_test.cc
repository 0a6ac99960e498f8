// coord/jacobians.h: every Jacobian against central finite differences of the exact operation
// (the perturbation applied exactly: p + dp, Exp(dth) R; the answer's change read back as
// (p' - p, Log(M' M^T))). The operations are written here from their definitions with Eigen's
// own AngleAxis for Exp / Log, independently of the Jacobians' derivation.
#include "semgraph/coord/jacobians.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "semgraph/coord/se3.h"

namespace semgraph::coord::jacobians {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;

Matrix3d ExpR(const Vector3d& w) {
  const double th = w.norm();
  return th == 0.0 ? Matrix3d::Identity() : Matrix3d(Eigen::AngleAxisd(th, w / th));
}
Vector3d LogR(const Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}
struct Pose {
  Matrix3d R = Matrix3d::Identity();
  Vector3d p = Vector3d::Zero();
};
Pose operator*(const Pose& a, const Pose& b) { return {a.R * b.R, a.R * b.p + a.p}; }
Pose Inv(const Pose& a) { return {a.R.transpose(), -(a.R.transpose() * a.p)}; }
Pose Perturbed(const Pose& X, const Vector6& d) {
  return {ExpR(d.tail<3>()) * X.R, X.p + d.head<3>()};
}
Vector6 Delta(const Pose& X0, const Pose& X1) {
  Vector6 d;
  d << X1.p - X0.p, LogR(X1.R * X0.R.transpose());
  return d;
}
Pose RandomPose(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Vector3d w(n(rng), n(rng), n(rng));
  return {ExpR(w), Vector3d(n(rng), n(rng), n(rng))};
}

// Central differences of f: R^6 -> R^6 at 0.
template <class F>
Matrix6 Numeric(F&& f) {
  const double h = 1e-6;
  Matrix6 J;
  for (int k = 0; k < 6; ++k) {
    Vector6 d = Vector6::Zero();
    d(k) = h;
    J.col(k) = (f(d) - f(-d)) / (2.0 * h);
  }
  return J;
}
void ExpectClose(const Matrix6& analytic, const Matrix6& numeric, const char* what) {
  EXPECT_LE((analytic - numeric).cwiseAbs().maxCoeff(), 1e-6 * (1.0 + numeric.norm()))
      << what << "\nanalytic\n"
      << analytic << "\nnumeric\n"
      << numeric;
}

TEST(Jacobians, ComposeAndInverseMatchFiniteDifferences) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 20; ++trial) {
    const Pose AB = RandomPose(rng), BC = RandomPose(rng);
    Matrix6 J_AB, J_BC;
    Compose(AB.R, AB.p, BC.R, BC.p, J_AB, J_BC);
    const Pose AC = AB * BC;
    ExpectClose(J_AB, Numeric([&](const Vector6& d) { return Delta(AC, Perturbed(AB, d) * BC); }),
                "compose, left");
    ExpectClose(J_BC, Numeric([&](const Vector6& d) { return Delta(AC, AB * Perturbed(BC, d)); }),
                "compose, right");
    ExpectClose(Inverse(AB.R, AB.p),
                Numeric([&](const Vector6& d) { return Delta(Inv(AB), Inv(Perturbed(AB, d))); }),
                "inverse");
  }
}

TEST(Jacobians, CovarianceHelpersAreTheFirstOrderSums) {
  std::mt19937 rng(2);
  const Pose AB = RandomPose(rng), BC = RandomPose(rng);
  Eigen::Isometry3d X_AB = Eigen::Isometry3d::Identity(), X_BC = X_AB;
  X_AB.linear() = AB.R;
  X_AB.translation() = AB.p;
  X_BC.linear() = BC.R;
  X_BC.translation() = BC.p;
  Matrix6 L = Matrix6::Random(), M = Matrix6::Random();
  const Covariance6 S1 = L * L.transpose(), S2 = M * M.transpose();
  Matrix6 J1, J2;
  Compose(AB.R, AB.p, BC.R, BC.p, J1, J2);
  const Covariance6 expected = J1 * S1 * J1.transpose() + J2 * S2 * J2.transpose();
  EXPECT_LE((ComposeCovariance(X_AB, S1, X_BC, S2) - expected).norm(), 1e-12 * expected.norm());
  // AddPropagated's block form against the dense product, for a J with a zero bottom-left.
  Matrix6 Jr = Matrix6::Random();
  Jr.bottomLeftCorner<3, 3>().setZero();
  Covariance6 acc = S2;
  AddPropagated(Jr, S1, acc);
  EXPECT_LE((acc - (S2 + Jr * S1 * Jr.transpose())).norm(), 1e-12 * acc.norm());
  const Matrix6 Ji = Inverse(AB.R, AB.p);
  EXPECT_LE((InverseCovariance(X_AB, S1) - Ji * S1 * Ji.transpose()).norm(),
            1e-12 * S1.norm() * 10);
}

// Y = X Exp(dt xi), at small and large angles (the series branch and the closed form).
TEST(Jacobians, ExtrapolationMatchesFiniteDifferences) {
  std::mt19937 rng(3);
  for (double scale : {1e-3, 0.03, 0.5, 2.0}) {
    for (int trial = 0; trial < 5; ++trial) {
      const Pose X = RandomPose(rng);
      std::normal_distribution<double> n(0.0, scale);
      const Vector3d v(n(rng), n(rng), n(rng)), w(n(rng), n(rng), n(rng));
      const double dt = 0.7;
      const auto integrate = [&](const Pose& X0, const Vector3d& v1, const Vector3d& w1) {
        const auto E = kernels::Exp(dt * v1, dt * w1);
        return X0 * Pose{E.q.toRotationMatrix(), E.p};
      };
      const Pose Y = integrate(X, v, w);
      Matrix6 J_X, J_xi;
      ExtrapolateJacobians(X.R, v, w, dt, J_X, J_xi);
      ExpectClose(J_X, Numeric([&](const Vector6& d) {
                    return Delta(Y, integrate(Perturbed(X, d), v, w));
                  }),
                  "extrapolation, pose");
      ExpectClose(J_xi, Numeric([&](const Vector6& d) {
                    return Delta(Y, integrate(X, v + d.head<3>(), w + d.tail<3>()));
                  }),
                  "extrapolation, twist");
    }
  }
}

// A pose edge's derivative from its two samples (twist source `poses`), per sample, for both
// interpolations, written here from se3.h's definitions: linear w = Log(R0^T R1) / dt,
// v = R_l^T (p1 - p0) / dt with R_l = R0 Exp(l Log(R0^T R1)); screw Log(X0^-1 X1) / dt with
// SE(3)'s Log as (th, V(th)^-1 p) from the closed-form V (Eigen's inverse). Rotations between
// the samples from 1e-3 to 2.5 rad, fractions 0, 0.3, 1.
Vector6 LinearDerivative(const Pose& X0, const Pose& X1, double dt, double l) {
  const Vector3d phi = LogR(X0.R.transpose() * X1.R);
  const Matrix3d R_l = X0.R * ExpR(l * phi);
  Vector6 out;
  out << R_l.transpose() * (X1.p - X0.p) / dt, phi / dt;
  return out;
}
Vector6 ScrewDerivative(const Pose& X0, const Pose& X1, double dt) {
  const Pose D = Inv(X0) * X1;
  const Vector3d w = LogR(D.R);
  const double th = w.norm();
  const Matrix3d W = Hat(w);
  const Matrix3d V = th == 0.0
                         ? Matrix3d::Identity()
                         : Matrix3d(Matrix3d::Identity() + (1 - std::cos(th)) / (th * th) * W +
                                    (th - std::sin(th)) / (th * th * th) * W * W);
  Vector6 out;
  out << V.inverse() * D.p / dt, w / dt;
  return out;
}
TEST(Jacobians, SegmentTwistMatchesFiniteDifferences) {
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  for (double angle : {1e-3, 0.05, 0.5, 1.5, 2.5}) {
    for (int trial = 0; trial < 4; ++trial) {
      const Pose X0 = RandomPose(rng);
      const Vector3d axis = Vector3d(n(rng), n(rng), n(rng)).normalized();
      const Pose X1{X0.R * ExpR(angle * axis), X0.p + Vector3d(n(rng), n(rng), n(rng))};
      const double dt = 0.4;
      for (double l : {0.0, 0.3, 1.0}) {
        const Vector3d phi = LogR(X0.R.transpose() * X1.R);
        const Matrix3d R_l = X0.R * ExpR(l * phi);
        Matrix6 J0, J1;
        LinearSegmentTwistJacobians(X0.R, R_l, phi, X1.p - X0.p, dt, l, J0, J1);
        ExpectClose(J0, Numeric([&](const Vector6& d) {
                      return Vector6(LinearDerivative(Perturbed(X0, d), X1, dt, l) -
                                     LinearDerivative(X0, X1, dt, l));
                    }),
                    "linear, sample 0");
        ExpectClose(J1, Numeric([&](const Vector6& d) {
                      return Vector6(LinearDerivative(X0, Perturbed(X1, d), dt, l) -
                                     LinearDerivative(X0, X1, dt, l));
                    }),
                    "linear, sample 1");
      }
      Vector3d rho, phi;
      const Pose D = Inv(X0) * X1;
      kernels::Log({Eigen::Quaterniond(D.R), D.p}, rho, phi);
      Matrix6 J0, J1;
      ScrewSegmentTwistJacobians(X0.R, X1.p - X0.p, rho, phi, dt, J0, J1);
      ExpectClose(
          J0, Numeric([&](const Vector6& d) {
            return Vector6(ScrewDerivative(Perturbed(X0, d), X1, dt) - ScrewDerivative(X0, X1, dt));
          }),
          "screw, sample 0");
      ExpectClose(
          J1, Numeric([&](const Vector6& d) {
            return Vector6(ScrewDerivative(X0, Perturbed(X1, d), dt) - ScrewDerivative(X0, X1, dt));
          }),
          "screw, sample 1");
      // Jl^-1 is the inverse of Jl.
      EXPECT_LE((LeftJacobianInverseSO3(phi) * LeftJacobianSO3(phi) - Matrix3d::Identity())
                    .cwiseAbs()
                    .maxCoeff(),
                1e-12);
    }
  }
}

// The series branch of BarfootQ (angles below 0.1) against its closed form evaluated in long
// double (no cancellation to speak of at these angles in 64-bit mantissas).
TEST(Jacobians, BarfootQSeriesMatchesTheClosedForm) {
  const Vector3d rho(0.3, -1.2, 0.8), axis = Vector3d(1.0, 2.0, -0.5).normalized();
  for (long double th : {0.0999L, 0.05L, 0.02L}) {
    const long double s = std::sin(th), c = std::cos(th), t2 = th * th;
    const double c1 = static_cast<double>((th - s) / (t2 * th));
    const double c2 = static_cast<double>((t2 + 2.0L * c - 2.0L) / (2.0L * t2 * t2));
    const double c3 = static_cast<double>((2.0L * th - 3.0L * s + th * c) / (2.0L * t2 * t2 * th));
    const Vector3d phi = static_cast<double>(th) * axis;
    const Matrix3d P = Hat(phi), Rh = Hat(rho);
    const Matrix3d expected = 0.5 * Rh + c1 * (P * Rh + Rh * P + P * Rh * P) +
                              c2 * (P * P * Rh + Rh * P * P - 3.0 * P * Rh * P) +
                              c3 * (P * Rh * P * P + P * P * Rh * P);
    EXPECT_LE((BarfootQ(rho, phi) - expected).cwiseAbs().maxCoeff(), 1e-12) << double(th);
  }
}

// A random tree of poses (frame 0 the root Z, parent[i] < i) and a pose answer between any of
// its frames: every edge's Jacobian on it.
struct Tree {
  std::vector<int> parent;
  std::vector<Pose> X_PF;  // edge into i
  Pose InZ(int i) const { return i == 0 ? Pose{} : InZ(parent[i]) * X_PF[i]; }
  bool Below(int g, int k) const {  // k == g or below g
    for (; k != 0; k = parent[k]) {
      if (k == g) return true;
    }
    return g == 0;
  }
};
Tree RandomTree(std::mt19937& rng, int n) {
  Tree t;
  t.parent.assign(n, -1);
  t.X_PF.assign(n, Pose{});
  for (int i = 1; i < n; ++i) {
    t.parent[i] = std::uniform_int_distribution<int>(0, i - 1)(rng);
    t.X_PF[i] = RandomPose(rng);
  }
  return t;
}
Pose PoseAnswer(const Tree& t, int e, int a, int f, int b, int r) {
  const Pose Ze = t.InZ(e), Za = t.InZ(a), Zf = t.InZ(f), Zb = t.InZ(b), Zr = t.InZ(r);
  const Matrix3d R_RZ = Zr.R.transpose();
  return {R_RZ * Za.R * Zb.R.transpose() * Zr.R, R_RZ * (Ze.p - Zf.p)};
}

TEST(Jacobians, EdgeOnPoseMatchesFiniteDifferencesForEveryEdge) {
  std::mt19937 rng(4);
  for (int trial = 0; trial < 30; ++trial) {
    const Tree t = RandomTree(rng, 8);
    std::uniform_int_distribution<int> any(0, 7);
    const int e = any(rng), a = any(rng), f = any(rng), b = any(rng), r = any(rng);
    const Pose ans = PoseAnswer(t, e, a, f, b, r);
    PoseInZ q;
    q.R_RZ = t.InZ(r).R.transpose();
    q.p_ZoEo_Z = t.InZ(e).p;
    q.p_ZoFo_Z = t.InZ(f).p;
    q.O_Z = t.InZ(a).R * t.InZ(b).R.transpose();
    for (int g = 1; g < 8; ++g) {
      const PoseMoves m{t.Below(g, e), t.Below(g, f), t.Below(g, a), t.Below(g, b), t.Below(g, r)};
      const EdgeInZ edge{t.InZ(t.parent[g]).R, t.InZ(g).p};
      ExpectClose(EdgeOnPose(q, edge, m), Numeric([&](const Vector6& d) {
                    Tree u = t;
                    u.X_PF[g] = Perturbed(t.X_PF[g], d);
                    return Delta(ans, PoseAnswer(u, e, a, f, b, r));
                  }),
                  "edge on pose");
    }
  }
}

// A twist answer at e in [r]: the sum of signed twists of steps at frames h_j (each in [h_j]).
struct TwistData {
  std::vector<int> h;
  std::vector<double> sign;
  std::vector<Vector3d> v, w;
};
Vector6 TwistAnswer(const Tree& t, const TwistData& d, int e, int r) {
  const Pose Ze = t.InZ(e);
  const Matrix3d R_RZ = t.InZ(r).R.transpose();
  Vector3d v = Vector3d::Zero(), w = Vector3d::Zero();
  for (std::size_t j = 0; j < d.h.size(); ++j) {
    const Pose Zh = t.InZ(d.h[j]);
    const Vector3d w_Z = d.sign[j] * Zh.R * d.w[j];
    v += d.sign[j] * Zh.R * d.v[j] + w_Z.cross(Ze.p - Zh.p);  // the rigid-body velocity at e
    w += w_Z;
  }
  Vector6 out;
  out << R_RZ * v, R_RZ * w;
  return out;
}

TEST(Jacobians, EdgesOnTwistMatchFiniteDifferences) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 30; ++trial) {
    const Tree t = RandomTree(rng, 8);
    std::uniform_int_distribution<int> any(0, 7);
    const int e = any(rng), r = any(rng);
    TwistData d;
    for (int j = 0; j < 3; ++j) {
      d.h.push_back(any(rng));
      d.sign.push_back(j == 1 ? -1.0 : 1.0);
      d.v.emplace_back(n(rng), n(rng), n(rng));
      d.w.emplace_back(n(rng), n(rng), n(rng));
    }
    const Vector6 ans = TwistAnswer(t, d, e, r);
    const Matrix3d R_RZ = t.InZ(r).R.transpose();
    const Vector3d p_e = t.InZ(e).p;
    Vector3d v_Z = Vector3d::Zero(), w_Z = Vector3d::Zero();
    std::vector<TwistStepInZ> steps;
    for (std::size_t j = 0; j < d.h.size(); ++j) {
      const Pose Zh = t.InZ(d.h[j]);
      TwistStepInZ s{d.sign[j] * Zh.R * d.v[j], d.sign[j] * Zh.R * d.w[j], Zh.p, false};
      v_Z += s.a_Z + s.w_Z.cross(p_e - Zh.p);
      w_Z += s.w_Z;
      steps.push_back(s);
      // The twist edge itself.
      ExpectClose(TwistEdgeOnTwist(R_RZ, Zh.R, Zh.p, p_e, d.sign[j]),
                  Numeric([&](const Vector6& dd) {
                    TwistData u = d;
                    u.v[j] += dd.head<3>();
                    u.w[j] += dd.tail<3>();
                    return Vector6(TwistAnswer(t, u, e, r) - ans);
                  }),
                  "twist edge on twist");
    }
    for (int g = 1; g < 8; ++g) {
      for (std::size_t j = 0; j < steps.size(); ++j) steps[j].moves = t.Below(g, d.h[j]);
      const EdgeInZ edge{t.InZ(t.parent[g]).R, t.InZ(g).p};
      ExpectClose(PoseEdgeOnTwist(R_RZ, p_e, v_Z, w_Z, steps, edge, t.Below(g, e), t.Below(g, r)),
                  Numeric([&](const Vector6& dd) {
                    Tree u = t;
                    u.X_PF[g] = Perturbed(t.X_PF[g], dd);
                    return Vector6(TwistAnswer(u, d, e, r) - ans);
                  }),
                  "pose edge on twist");
    }
  }
}

}  // namespace
}  // namespace semgraph::coord::jacobians
