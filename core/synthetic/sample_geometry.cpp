// Convex polygons and planes in a building frame, and the checks of a closed shell.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>

#include "core/geometry/geometry.h"
#include "core/synthetic/sample_detail.h"

namespace c3d {

using namespace sample_detail;

namespace {

// Keeps the part of a convex polygon where a u + b v + c >= 0. A degenerate
// half-plane (a = b = 0) keeps all when c > 0, or c == 0 and keep_tie.
Ring2 clip(const Ring2& poly, double a, double b, double c, bool keep_tie = true) {
  double n = std::hypot(a, b);
  if (n < 1e-12) return (c > 1e-12 || (std::abs(c) <= 1e-12 && keep_tie)) ? poly : Ring2{};
  a /= n, b /= n, c /= n;
  Ring2 out;
  for (size_t i = 0, k = poly.size(); i < k; ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % k];
    double fp = a * p.x() + b * p.y() + c, fq = a * q.x() + b * q.y() + c;
    if (fp >= 0) out.push_back(p);
    if ((fp > 0 && fq < 0) || (fp < 0 && fq > 0)) out.push_back(p + (q - p) * (fp / (fp - fq)));
  }
  Ring2 clean;
  for (const auto& p : out)
    if (clean.empty() || (p - clean.back()).norm() > 1e-12) clean.push_back(p);
  while (clean.size() > 1 && (clean.front() - clean.back()).norm() <= 1e-12) clean.pop_back();
  return clean.size() < 3 ? Ring2{} : clean;
}

}  // namespace

std::vector<Line> sample_detail::edges_of(const Ring2& r) {
  std::vector<Line> out;
  for (size_t i = 0, k = r.size(); i < k; ++i) {
    Vec2 d = r[(i + 1) % k] - r[i];
    double a = -d.y(), b = d.x();
    out.push_back({a, b, -(a * r[i].x() + b * r[i].y())});
  }
  return out;
}

double sample_detail::poly_area(const Ring2& r) { return r.size() < 3 ? 0.0 : std::abs(signed_area(r)); }

Ring2 sample_detail::clip_by_plane_diff(const Ring2& poly, const Plane& hi, const Plane& lo,
                                       bool keep_tie) {
  // keep where hi - lo >= 0
  return clip(poly, hi.a - lo.a, hi.b - lo.b, hi.c - lo.c, keep_tie);
}

Ring2 sample_detail::intersect(Ring2 p, const Ring2& r) {
  for (const auto& l : edges_of(r)) {
    if (p.empty()) break;
    p = clip(p, l.a, l.b, l.c);
  }
  return p;
}

std::vector<Ring2> sample_detail::subtract(Ring2 p, const Ring2& r) {
  std::vector<Ring2> out;
  for (const auto& l : edges_of(r)) {
    if (p.empty()) break;
    Ring2 o = clip(p, -l.a, -l.b, -l.c);
    if (poly_area(o) > kAreaEps) out.push_back(o);
    p = clip(p, l.a, l.b, l.c);
  }
  return out;
}

Ring3 sample_detail::lift(const Ring2& r, const Plane& pl) {
  Ring3 out;
  for (const auto& p : r) out.emplace_back(p.x(), p.y(), pl.z(p));
  return out;
}

Ring3 sample_detail::dedupe(const Ring3& r) {
  Ring3 out;
  for (const auto& p : r)
    if (out.empty() || (p - out.back()).norm() > 1e-9) out.push_back(p);
  while (out.size() > 1 && (out.front() - out.back()).norm() <= 1e-9) out.pop_back();
  return out;
}

// ---- Shell checks ----

namespace {
using Key = std::array<long long, 3>;
Key key_of(const Vec3& p) {
  return {std::llround(p.x() * 1e6), std::llround(p.y() * 1e6), std::llround(p.z() * 1e6)};
}
}  // namespace

bool shell_is_closed(const std::vector<Face>& shell, std::string* problem) {
  std::vector<Vec3> verts;  // sorted by x: an edge looks only at those within its x range
  for (const auto& f : shell) verts.insert(verts.end(), f.ring.begin(), f.ring.end());
  std::sort(verts.begin(), verts.end(), [](const Vec3& p, const Vec3& q) { return p.x() < q.x(); });
  auto by_x = [](const Vec3& p, double x) { return p.x() < x; };
  std::map<std::pair<Key, Key>, int> edges;
  for (const auto& f : shell) {
    const Ring3 r = dedupe(f.ring);
    for (size_t i = 0, n = r.size(); i < n; ++i) {
      const Vec3 a = r[i], b = r[(i + 1) % n];
      const Vec3 d = b - a;
      double len2 = d.squaredNorm();
      // Split the edge at every shell vertex lying inside it (T-junctions).
      std::vector<std::pair<double, Vec3>> cuts{{0, a}, {1, b}};
      const auto from = std::lower_bound(verts.begin(), verts.end(), std::min(a.x(), b.x()) - 1e-6, by_x);
      for (auto it = from; it != verts.end() && it->x() <= std::max(a.x(), b.x()) + 1e-6; ++it) {
        const Vec3& v = *it;
        double t = (v - a).dot(d) / len2;
        if (t > 1e-9 && t < 1 - 1e-9 && (a + d * t - v).norm() < 1e-6) cuts.push_back({t, v});
      }
      std::sort(cuts.begin(), cuts.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
      for (size_t k = 0; k + 1 < cuts.size(); ++k) {
        Key ka = key_of(cuts[k].second), kb = key_of(cuts[k + 1].second);
        if (ka != kb) ++edges[{ka, kb}];
      }
    }
  }
  for (const auto& [e, n] : edges) {
    auto rev = edges.find({e.second, e.first});
    int m = rev == edges.end() ? 0 : rev->second;
    if (n != 1 || m != 1) {
      if (problem) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "edge (%.3f %.3f %.3f)-(%.3f %.3f %.3f) used %d+%d times",
                      e.first[0] * 1e-6, e.first[1] * 1e-6, e.first[2] * 1e-6, e.second[0] * 1e-6,
                      e.second[1] * 1e-6, e.second[2] * 1e-6, n, m);
        *problem = buf;
      }
      return false;
    }
  }
  if (problem) problem->clear();
  return !edges.empty();
}

double shell_volume(const std::vector<Face>& shell) {
  if (shell.empty() || shell.front().ring.empty()) return 0;
  const Vec3 o = shell.front().ring.front();
  double v = 0;
  for (const auto& f : shell)
    for (size_t i = 1; i + 1 < f.ring.size(); ++i)
      v += (f.ring[0] - o).dot((f.ring[i] - o).cross(f.ring[i + 1] - o));
  return v / 6;
}

}  // namespace c3d
