// Analytic motions shared by the time tests (time_test.cc, time_query_test.cc), their ground
// truth (docs/time.md):
//   ScrewMotion  a body spinning at rate w about the z axis through the point c of its parent
//                while sliding along it at h: X(s) = (Rz(w s), c - Rz(w s) c + h s z), a
//                one-parameter subgroup (X(0) = I) whose screw twist (at the body's origin, in
//                its frame) is (c x w z + h z, w z), constant
//   Orbit        a body on a circle of radius rho about its parent's z axis, spinning about its
//                own x axis: X(s) = (Rz(a s) Rx(b s), rho (cos a s, sin a s, 0)); body twist
//                w = a Rx(b s)^T z + b x, v = R(s)^T dp/ds
#pragma once

#include <Eigen/Geometry>
#include <cmath>

#include "semgraph/core/scene_graph.h"

namespace semgraph::core::time_motions {

inline Stamp S(double seconds) { return *StampFromSeconds(seconds); }
inline Eigen::Quaterniond Rz(double a) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()));
}
inline Eigen::Quaterniond Rx(double a) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()));
}

struct ScrewMotion {
  Eigen::Vector3d c{0.7, -0.4, 0.2};
  double w = 1.3, h = 0.25;
  Eigen::Quaterniond q(double s) const { return Rz(w * s); }
  Eigen::Vector3d p(double s) const { return c - Rz(w * s) * c + Eigen::Vector3d(0, 0, h * s); }
  Eigen::Vector3d v() const { return c.cross(Eigen::Vector3d(0, 0, w)) + Eigen::Vector3d(0, 0, h); }
  Eigen::Vector3d omega() const { return {0, 0, w}; }
};

struct Orbit {
  double rho = 1.5, a = 0.8, b = 2.1;
  Eigen::Quaterniond q(double s) const { return Rz(a * s) * Rx(b * s); }
  Eigen::Vector3d p(double s) const {
    return rho * Eigen::Vector3d(std::cos(a * s), std::sin(a * s), 0);
  }
  Eigen::Vector3d omega(double s) const {
    return a * (Rx(b * s).conjugate() * Eigen::Vector3d::UnitZ()) + b * Eigen::Vector3d::UnitX();
  }
  Eigen::Vector3d v(double s) const {
    return q(s).conjugate() *
           Eigen::Vector3d(-rho * a * std::sin(a * s), rho * a * std::cos(a * s), 0);
  }
};

}  // namespace semgraph::core::time_motions
