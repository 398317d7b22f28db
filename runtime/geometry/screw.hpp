// The spatial geometry layer, written once and templated on the scalar: double in the numeric
// solver, GiNaC::ex in the generator (as Pinocchio templates every algorithm on its scalar).
// Only + - * and sin/cos (found by argument-dependent lookup) are used, so any field type works.
//
// Conventions (seed 001, Tsai 1999): every screw is expressed in the ground frame.
//  - Pose {R, p} maps a point x to R x + p.
//  - Twist {w, v}: angular velocity w and the velocity v of the body point at the ground origin
//    (the spatial, or "ground-origin", twist). The velocity of a point x is v + w x x.
//  - Wrench {f, m}: force f and moment m about the ground origin.
//  - A screw axis: unit direction s, a point s0 on it and a pitch h. Its unit twist is
//    {s, s0 x s + h s}; a prismatic (infinite pitch) axis has the unit twist {0, s}.
#pragma once

#include <array>
#include <cmath>

namespace mechgen::geometry {

template <class T>
using Vec3 = std::array<T, 3>;

// Row-major 3 x 3 matrix.
template <class T>
struct Mat3 {
  std::array<T, 9> m;
  T& operator()(int i, int j) { return m[static_cast<size_t>(3 * i + j)]; }
  const T& operator()(int i, int j) const { return m[static_cast<size_t>(3 * i + j)]; }
  static Mat3 identity() { return {{T(1), T(0), T(0), T(0), T(1), T(0), T(0), T(0), T(1)}}; }
};

template <class T>
struct Pose {
  Mat3<T> R = Mat3<T>::identity();
  Vec3<T> p{T(0), T(0), T(0)};
};

template <class T>
struct Twist {
  Vec3<T> w{T(0), T(0), T(0)}, v{T(0), T(0), T(0)};
};

template <class T>
struct Wrench {
  Vec3<T> f{T(0), T(0), T(0)}, m{T(0), T(0), T(0)};
};

enum class ScrewKind { rotation, translation, helical };

// One elementary screw (one joint coordinate), at the reference pose, ground frame.
template <class T>
struct ScrewAxis {
  ScrewKind kind = ScrewKind::rotation;
  Vec3<T> s{T(0), T(0), T(1)};   // unit direction
  Vec3<T> s0{T(0), T(0), T(0)};  // a point on the axis
  T pitch = T(0);                // helical: translation per radian
};

// ---- vectors and matrices ----------------------------------------------------------------------

template <class T>
Vec3<T> operator+(const Vec3<T>& a, const Vec3<T>& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
template <class T>
Vec3<T> operator-(const Vec3<T>& a, const Vec3<T>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
template <class T>
Vec3<T> operator-(const Vec3<T>& a) {
  return {-a[0], -a[1], -a[2]};
}
template <class T>
Vec3<T> operator*(const T& k, const Vec3<T>& a) {
  return {k * a[0], k * a[1], k * a[2]};
}
template <class T>
T dot(const Vec3<T>& a, const Vec3<T>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class T>
Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <class T>
Vec3<T> operator*(const Mat3<T>& A, const Vec3<T>& x) {
  return {A(0, 0) * x[0] + A(0, 1) * x[1] + A(0, 2) * x[2],
          A(1, 0) * x[0] + A(1, 1) * x[1] + A(1, 2) * x[2],
          A(2, 0) * x[0] + A(2, 1) * x[1] + A(2, 2) * x[2]};
}
template <class T>
Mat3<T> operator*(const Mat3<T>& A, const Mat3<T>& B) {
  Mat3<T> C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C(i, j) = A(i, 0) * B(0, j) + A(i, 1) * B(1, j) + A(i, 2) * B(2, j);
  return C;
}
template <class T>
Mat3<T> transpose(const Mat3<T>& A) {
  Mat3<T> C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C(i, j) = A(j, i);
  return C;
}

// Rodrigues' formula (seed 001 eq. 2): rotation by angle q about the unit axis s.
template <class T>
Mat3<T> rodrigues(const Vec3<T>& s, const T& q) {
  using std::cos;
  using std::sin;
  const T c = cos(q), sn = sin(q), v = T(1) - c;
  return {{s[0] * s[0] * v + c, s[0] * s[1] * v - s[2] * sn, s[0] * s[2] * v + s[1] * sn,
           s[0] * s[1] * v + s[2] * sn, s[1] * s[1] * v + c, s[1] * s[2] * v - s[0] * sn,
           s[0] * s[2] * v - s[1] * sn, s[1] * s[2] * v + s[0] * sn, s[2] * s[2] * v + c}};
}

// ---- poses
// ---------------------------------------------------------------------------------------

template <class T>
Pose<T> operator*(const Pose<T>& a, const Pose<T>& b) {
  return {a.R * b.R, a.R * b.p + a.p};
}
template <class T>
Pose<T> inverse(const Pose<T>& a) {
  const Mat3<T> Rt = transpose(a.R);
  return {Rt, -(Rt * a.p)};
}
template <class T>
Vec3<T> apply(const Pose<T>& a, const Vec3<T>& x) {
  return a.R * x + a.p;
}

// The screw displacement of magnitude q along an axis (seed 001 eqs. 1-3): a rotation by q about
// the axis with a translation h q along it (helical), or a translation by q (prismatic).
template <class T>
Pose<T> screw_displacement(const ScrewAxis<T>& a, const T& q) {
  if (a.kind == ScrewKind::translation) return {Mat3<T>::identity(), q * a.s};
  Pose<T> d;
  d.R = rodrigues(a.s, q);
  d.p = a.s0 - d.R * a.s0;
  if (a.kind == ScrewKind::helical) d.p = d.p + (a.pitch * q) * a.s;
  return d;
}

// ---- twists and wrenches ---------------------------------------------------------------------

template <class T>
Twist<T> operator+(const Twist<T>& a, const Twist<T>& b) {
  return {a.w + b.w, a.v + b.v};
}
template <class T>
Twist<T> operator-(const Twist<T>& a, const Twist<T>& b) {
  return {a.w - b.w, a.v - b.v};
}
template <class T>
Twist<T> operator*(const T& k, const Twist<T>& a) {
  return {k * a.w, k * a.v};
}
template <class T>
Wrench<T> operator+(const Wrench<T>& a, const Wrench<T>& b) {
  return {a.f + b.f, a.m + b.m};
}

// The unit twist of an elementary screw (seed 001 eq. 4 with a unit magnitude).
template <class T>
Twist<T> unit_twist(const ScrewAxis<T>& a) {
  if (a.kind == ScrewKind::translation) return {{T(0), T(0), T(0)}, a.s};
  Twist<T> t{a.s, cross(a.s0, a.s)};
  if (a.kind == ScrewKind::helical) t.v = t.v + a.pitch * a.s;
  return t;
}

// The adjoint map: the twist `x` carried along by the displacement `g` (both ground frame).
template <class T>
Twist<T> adjoint(const Pose<T>& g, const Twist<T>& x) {
  const Vec3<T> w = g.R * x.w;
  return {w, g.R * x.v + cross(g.p, w)};
}

// The Lie bracket [a, b] = ad_a b: the rate of change of the screw b carried by a body whose
// twist is a. Differentiating the circulation law gives these convective terms (seed 001 eq. 6).
template <class T>
Twist<T> lie_bracket(const Twist<T>& a, const Twist<T>& b) {
  return {cross(a.w, b.w), cross(a.w, b.v) + cross(a.v, b.w)};
}

// The reciprocal product (power of a wrench on a twist).
template <class T>
T reciprocal(const Twist<T>& x, const Wrench<T>& y) {
  return dot(x.w, y.m) + dot(x.v, y.f);
}

// Velocity of the point x of a body moving with twist t.
template <class T>
Vec3<T> point_velocity(const Twist<T>& t, const Vec3<T>& x) {
  return t.v + cross(t.w, x);
}

// Acceleration of the point x of a body with twist t and twist rate dt (the time derivative of
// the ground-origin twist).
template <class T>
Vec3<T> point_acceleration(const Twist<T>& t, const Twist<T>& dt, const Vec3<T>& x) {
  return dt.v + cross(dt.w, x) + cross(t.w, point_velocity(t, x));
}

}  // namespace mechgen::geometry
