#pragma once
// A free-form roof's cubic B-spline height field (SplineSurface, core/types.h)
// in plain arithmetic, for the optimizer to snap onto: its height and slopes
// (Cox-de Boor) and the nearest point of the surface to a point (Gauss-Newton).
// Templated so that the kernel's CPU reference runs the float steps of
// shaders/opt_snap_curved.comp and the optimizer's choices run in double.
#include <algorithm>
#include <optional>
#include <utility>
#include <vector>

#include "core/types.h"

namespace c3d {

// The surface's heights over its parameters: z = h(u, v), the plan point of
// (u, v) being origin + u e1 + v e2 (the poles stand at their Greville
// abscissae, so the spline's plan is linear in its parameters).
struct HeightFieldData {
  Vec2 origin = Vec2::Zero(), e1 = Vec2::UnitX();
  int nu = 0, nv = 0;               // poles along u and v
  std::vector<double> ku, kv;       // knots, nu + 4 and nv + 4, ends repeated
  std::vector<double> z;            // pole heights, u fastest
  Vec2 e2() const { return {-e1.y(), e1.x()}; }
  Vec2 uv(const Vec2& q) const { return {(q - origin).dot(e1), (q - origin).dot(e2())}; }
  Vec2 plan(double u, double v) const { return origin + u * e1 + v * e2(); }
};

// The plan frame a spline's poles stand on: the plan point of parameters
// (0, 0) and the unit direction of u (core/optimizer/exact_surfaces.cpp).
std::pair<Vec2, Vec2> spline_plan_frame(const SplineSurface& s);

// The data of a cubic spline's height field; none for other degrees
// (core/optimizer/exact_surfaces.cpp).
std::optional<HeightFieldData> height_field_data(const SplineSurface& s);

template <class T>
struct HeightSample {
  T h, hu, hv;  // height, dh/du, dh/dv
};

// The four cubic basis functions that do not vanish at t (clamped into the
// knots' span) and their derivatives; returns the index of the first one's pole.
template <class T>
int cubic_basis(const T* knots, int poles, T t, T n[4], T dn[4]) {
  t = std::clamp(t, knots[3], knots[poles]);
  int s = 3;
  while (s < poles - 1 && t >= knots[s + 1]) ++s;
  T left[4], right[4], n2[3];
  n[0] = T(1);
  for (int j = 1; j <= 3; ++j) {
    left[j] = t - knots[s + 1 - j];
    right[j] = knots[s + j] - t;
    T saved = T(0);
    for (int r = 0; r < j; ++r) {
      const T temp = n[r] / (right[r + 1] + left[j - r]);
      n[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    n[j] = saved;
    if (j == 2) n2[0] = n[0], n2[1] = n[1], n2[2] = n[2];
  }
  for (int r = 0; r <= 3; ++r) {
    T d = T(0);
    if (r >= 1) d += T(3) * n2[r - 1] / (knots[s + r] - knots[s + r - 3]);
    if (r <= 2) d -= T(3) * n2[r] / (knots[s + r + 1] - knots[s + r - 2]);
    dn[r] = d;
  }
  return s - 3;
}

template <class T>
HeightSample<T> height_at(const T* ku, int nu, const T* kv, int nv, const T* z, T u, T v) {
  T bu[4], du[4], bv[4], dv[4];
  const int iu = cubic_basis(ku, nu, u, bu, du), iv = cubic_basis(kv, nv, v, bv, dv);
  HeightSample<T> s{T(0), T(0), T(0)};
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a) {
      const T pole = z[(iu + a) + nu * (iv + b)];
      s.h += bu[a] * bv[b] * pole;
      s.hu += du[a] * bv[b] * pole;
      s.hv += bu[a] * dv[b] * pole;
    }
  return s;
}

// Gauss-Newton steps from (pu, pv) towards the parameters of the surface's
// point nearest (pu, pv, pz), within the knots' span. Near a surface that
// bends no tighter than a 0.5 m radius (judge_free_form), six steps leave
// well under a micrometre.
constexpr int kNearestSteps = 6;

template <class T>
void nearest_parameters(const T* ku, int nu, const T* kv, int nv, const T* z, T pu, T pv, T pz, T& u, T& v) {
  u = pu, v = pv;
  for (int step = 0; step < kNearestSteps; ++step) {
    u = std::clamp(u, ku[3], ku[nu]);
    v = std::clamp(v, kv[3], kv[nv]);
    const HeightSample<T> s = height_at(ku, nu, kv, nv, z, u, v);
    const T r = s.h - pz;
    const T gu = (u - pu) + r * s.hu, gv = (v - pv) + r * s.hv;
    const T k = (s.hu * gu + s.hv * gv) / (T(1) + s.hu * s.hu + s.hv * s.hv);
    u -= gu - s.hu * k;
    v -= gv - s.hv * k;
  }
  u = std::clamp(u, ku[3], ku[nu]);
  v = std::clamp(v, kv[3], kv[nv]);
}

}  // namespace c3d
