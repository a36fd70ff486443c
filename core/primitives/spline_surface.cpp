#include "core/primitives/spline_surface.h"

#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>

#include <stdexcept>
#include <vector>

namespace c3d {

namespace {

// Flat knots as distinct knots and multiplicities.
void split_knots(const std::vector<double>& flat, std::vector<double>& knots, std::vector<int>& mults) {
  for (double k : flat) {
    if (!knots.empty() && k == knots.back()) ++mults.back();
    else knots.push_back(k), mults.push_back(1);
  }
}

TColStd_Array1OfReal reals(const std::vector<double>& v) {
  TColStd_Array1OfReal a(1, int(v.size()));
  for (size_t i = 0; i < v.size(); ++i) a.SetValue(int(i) + 1, v[i]);
  return a;
}

TColStd_Array1OfInteger ints(const std::vector<int>& v) {
  TColStd_Array1OfInteger a(1, int(v.size()));
  for (size_t i = 0; i < v.size(); ++i) a.SetValue(int(i) + 1, v[i]);
  return a;
}

std::vector<double> flat_knots(const TColStd_Array1OfReal& knots, const TColStd_Array1OfInteger& mults) {
  std::vector<double> flat;
  for (int i = knots.Lower(); i <= knots.Upper(); ++i) flat.insert(flat.end(), size_t(mults(i)), knots(i));
  return flat;
}

}  // namespace

Handle(Geom_BSplineSurface) occ_surface(const SplineSurface& s) {
  if (s.empty()) throw std::invalid_argument("no spline surface");
  TColgp_Array2OfPnt poles(1, s.poles_u, 1, s.poles_v);
  for (int j = 0; j < s.poles_v; ++j)
    for (int i = 0; i < s.poles_u; ++i) {
      const Vec3& q = s.poles[size_t(i + s.poles_u * j)];
      poles.SetValue(i + 1, j + 1, gp_Pnt(q.x(), q.y(), q.z()));
    }
  std::vector<double> ku, kv;
  std::vector<int> mu, mv;
  split_knots(s.knots_u, ku, mu);
  split_knots(s.knots_v, kv, mv);
  return new Geom_BSplineSurface(poles, reals(ku), reals(kv), ints(mu), ints(mv), s.degree_u, s.degree_v);
}

SplineSurface plain_surface(const Geom_BSplineSurface& g) {
  SplineSurface s;
  s.degree_u = g.UDegree(), s.degree_v = g.VDegree();
  s.poles_u = g.NbUPoles(), s.poles_v = g.NbVPoles();
  for (int j = 1; j <= s.poles_v; ++j)
    for (int i = 1; i <= s.poles_u; ++i) {
      const gp_Pnt p = g.Pole(i, j);
      s.poles.emplace_back(p.X(), p.Y(), p.Z());
    }
  s.knots_u = flat_knots(g.UKnots(), g.UMultiplicities());
  s.knots_v = flat_knots(g.VKnots(), g.VMultiplicities());
  return s;
}

}  // namespace c3d
