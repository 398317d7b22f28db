// Seed 002's quadruped leg written out from the seed's own formulas (theta1, theta2, theta10, the
// foot, the Jacobian J = J1 J3^-1 J2^-1) and its zero-impact swing law with derivatives: the
// independent expectations of the numeric solver's and the generated kernels' tests.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <string>

#include "model/spatial_model.hpp"

namespace mechgen::spatial {

inline double param(const SpatialModel& m, const std::string& name) {
  for (const Parameter& p : m.common.parameters)
    if (p.name == name) return p.value;
  ADD_FAILURE() << "no parameter " << name;
  return 0;
}

// The seed's formulas, with its constants read from the model's parameters.
struct Seed {
  double a, b, c, d, e, f, h, i, j, th5, th7, th8, th11, th1_0, th12_0;
  explicit Seed(const SpatialModel& m)
      : a(param(m, "a")),
        b(param(m, "b")),
        c(param(m, "c")),
        d(param(m, "d")),
        e(param(m, "e")),
        f(param(m, "f")),
        h(param(m, "h")),
        i(param(m, "i")),
        j(param(m, "j")),
        th5(param(m, "theta5")),
        th7(param(m, "theta7")),
        th8(param(m, "theta8")),
        th11(param(m, "theta11")),
        th1_0(param(m, "theta1_0")),
        th12_0(param(m, "theta12_0")) {}
  double theta1(double l1) const {
    return th5 + th8 + std::acos((d * d + f * f - l1 * l1) / (2 * d * f));
  }
  double theta2(double l1, double l2) const {
    return 2 * M_PI - theta1(l1) + th7 - std::acos((a * a + e * e - l2 * l2) / (2 * a * e));
  }
  double theta10(double l3) const {
    return th11 - M_PI / 2 + std::acos((i * i + j * j - l3 * l3) / (2 * i * j));
  }
  // Local plane coordinates of D (the seed's x_D, z_D).
  double xD(double t1, double t2) const { return b * std::cos(t1) + (a + c) * std::cos(t1 + t2); }
  double zD(double t1, double t2) const {
    return b * std::sin(t1) + (a + c) * std::sin(t1 + t2) - h;
  }
  // The cylinders' lengths at the reference pose (law of cosines in the triangles QHG, QFC, OMN).
  Eigen::Vector3d reference_lengths() const {
    return {std::sqrt(d * d + f * f - 2 * d * f * std::cos(th1_0 - th5 - th8)),
            std::sqrt(a * a + e * e - 2 * a * e * std::cos(th12_0 - th7)),
            std::sqrt(i * i + j * j - 2 * i * j * std::cos(M_PI / 2 - th11))};
  }
  // The correct global foot: R(x, theta10) (x_D, 0, z_D).
  Eigen::Vector3d foot(const Eigen::Vector3d& l) const {
    const double t1 = theta1(l[0]), t2 = theta2(l[0], l[1]), t10 = theta10(l[2]);
    const double x = xD(t1, t2), z = zD(t1, t2);
    return {x, -z * std::sin(t10), z * std::cos(t10)};
  }
  // The seed's J = J1 J3^-1 J2^-1 (J1's third column with z_D: see the model's header).
  Eigen::Matrix3d jacobian(const Eigen::Vector3d& l, bool as_printed = false) const {
    const double t1 = theta1(l[0]), t2 = theta2(l[0], l[1]), t10 = theta10(l[2]);
    const double s1 = std::sin(t1), c1 = std::cos(t1), s12 = std::sin(t1 + t2),
                 c12 = std::cos(t1 + t2), s10 = std::sin(t10), c10 = std::cos(t10);
    const double r = as_printed ? xD(t1, t2) : zD(t1, t2);
    Eigen::Matrix3d J1, J2, J3;
    J1 << -b * s1 - (a + c) * s12, -(a + c) * s12, 0,                     //
        -(b * c1 + (a + c) * c12) * s10, -(a + c) * c12 * s10, -r * c10,  //
        (b * c1 + (a + c) * c12) * c10, (a + c) * c12 * c10, -r * s10;
    const double t3 = t1 - th5, t4 = 2 * M_PI - t1 - t2;
    J2 = Eigen::Vector3d(d * f * std::sin(t3 - th8) / l[0], a * e * std::sin(t4 + th7) / l[1],
                         i * j * std::sin(t10 - th11 + M_PI / 2) / l[2])
             .asDiagonal();
    J3 << 1, 0, 0, -1, -1, 0, 0, 0, 1;
    return J1 * J3.inverse() * J2.inverse();
  }
};

// The seed's swing (y horizontal along X, z vertical) and its derivatives, written out.
struct Swing {
  double S, H, T, x0, Y0, z0;
  Eigen::Vector3d x(double t) const {
    const double s = t / T;
    return {
        x0 + S * (6 * std::pow(s, 5) - 15 * std::pow(s, 4) + 10 * std::pow(s, 3) - 0.5), Y0,
        z0 + 64 * H * (-std::pow(s, 6) + 3 * std::pow(s, 5) - 3 * std::pow(s, 4) + std::pow(s, 3))};
  }
  Eigen::Vector3d v(double t) const {
    const double s = t / T;
    return {
        S / T * (30 * std::pow(s, 4) - 60 * std::pow(s, 3) + 30 * s * s), 0,
        64 * H / T * (-6 * std::pow(s, 5) + 15 * std::pow(s, 4) - 12 * std::pow(s, 3) + 3 * s * s)};
  }
  Eigen::Vector3d a(double t) const {
    const double s = t / T;
    return {S / (T * T) * (120 * std::pow(s, 3) - 180 * s * s + 60 * s), 0,
            64 * H / (T * T) * (-30 * std::pow(s, 4) + 60 * std::pow(s, 3) - 36 * s * s + 6 * s)};
  }
};

}  // namespace mechgen::spatial
