// The report's pictures: the axonometric view of a parcel's buildings, the
// legend and the two charts.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "cadastre/report/report.h"
#include "cadastre/report/report_parts.h"
#include "core/geometry/geometry.h"

namespace c3d {

using namespace report_detail;

namespace {

// Up to this many parcels the chart shows one bar each; beyond, a histogram.
constexpr size_t kBarsUpTo = 30;  // beyond, rotated ids overlap
constexpr int kMaxBins = 20;

// ---------------------------------------------------------------- pictures

// Isometric view from the south-west, above: screen right = (x - y)/sqrt2,
// screen up = (x + y + 2z)/sqrt6, depth (larger = farther) = x + y - z.
struct Projected {
  std::vector<std::vector<Vec2>> rings;
  double depth = 0;
  std::string fill;
  double shade = 1;
  bool down = false;
};

Vec2 project(const Vec3& p) {
  return Vec2((p.x() - p.y()) / std::sqrt(2.0), -(p.x() + p.y() + 2 * p.z()) / std::sqrt(6.0));
}

std::string shaded(const char* hex, double f) {
  unsigned r, g, b;
  std::sscanf(hex, "#%02x%02x%02x", &r, &g, &b);
  auto c = [f](unsigned v) { return std::min(255, int(std::lround(v * f))); };
  return fmt("#%02x%02x%02x", c(r), c(g), c(b));
}

Projected project_face(const Face& f, ElementType t) {
  Projected p;
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& v : f.ring) centroid += v;
  centroid /= double(std::max<size_t>(1, f.ring.size()));
  p.depth = centroid.x() + centroid.y() - centroid.z();
  Vec3 n = unit_normal(f);
  p.down = t == ElementType::Ground || t == ElementType::OuterCeiling;
  const Vec3 light = Vec3(-0.3, -0.6, 0.75).normalized();
  p.shade = 0.78 + 0.22 * std::abs(n.dot(light));  // abs: orientation-agnostic
  p.fill = shaded(colour(t), p.shade);
  auto add = [&](const Ring3& r) {
    std::vector<Vec2> out;
    for (const Vec3& v : r) out.push_back(project(v));
    p.rings.push_back(out);
  };
  add(f.ring);
  for (const Ring3& h : f.holes) add(h);
  return p;
}

std::string path_data(const std::vector<std::vector<Vec2>>& rings, const Vec2& lo, double s,
                      const Vec2& pad) {
  std::string d;
  for (const auto& r : rings) {
    for (size_t i = 0; i < r.size(); ++i) {
      Vec2 q = (r[i] - lo) * s + pad;
      d += fmt("%c%.1f %.1f", i ? 'L' : 'M', q.x(), q.y());
    }
    d += "Z";
  }
  return d;
}


// Bins of a round width (1, 2, 2.5 or 5 x 10^k) so their edges read well.
double nice_step(double raw) {
  double decade = std::pow(10.0, std::floor(std::log10(std::max(raw, 1e-9))));
  for (double f : {1.0, 2.0, 2.5, 5.0})
    if (f * decade >= raw) return f * decade;
  return 10 * decade;
}

// NJOP per parcel in bins of a round width: each bar labelled with its range
// (million), a count axis and axis titles.
std::string njop_histogram(const std::vector<std::pair<std::string, const ParcelValuation*>>& rows) {
  double low = HUGE_VAL, top = -HUGE_VAL;
  for (const auto& r : rows) low = std::min(low, r.second->njop), top = std::max(top, r.second->njop);
  // From the lowest value's bin, not from 0: no row of empty bins on the left.
  const double step = nice_step(std::max(top - low, 1.0) / kMaxBins), start = std::floor(low / step) * step;
  const int bins = int(std::floor((top - start) / step)) + 1;  // the largest value in the last bin
  std::vector<int> count(size_t(bins), 0);
  for (const auto& r : rows) count[size_t(std::clamp(int((r.second->njop - start) / step), 0, bins - 1))]++;
  const int cmax = std::max(1, *std::max_element(count.begin(), count.end()));
  const double left = 56, right = 550, top_y = 24, base = 190, bw = (right - left) / bins;
  const double ystep = nice_step(cmax / 5.0), ytop = std::ceil(cmax / ystep) * ystep;
  std::string s = "<svg class=\"histogram\" width=\"560\" height=\"300\" viewBox=\"0 0 560 300\" "
                  "role=\"img\" aria-label=\"Histogram of NJOP per parcel\">";
  for (double c = 0; c <= ytop + 1e-9; c += ystep) {
    double y = base - (base - top_y) * c / ytop;
    s += fmt("<line x1=\"%.0f\" x2=\"%.0f\" y1=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.0f\" "
             "y=\"%.1f\" text-anchor=\"end\" class=\"small\">%g</text>", left, right, y, y, left - 4, y + 4, c);
  }
  for (int b = 0; b < bins; ++b) {
    const double lo = (start + b * step) / 1e6, hi = (start + (b + 1) * step) / 1e6, x = left + b * bw;
    const double h = (base - top_y) * count[size_t(b)] / ytop;
    s += fmt("<rect class=\"bin\" data-lo=\"%.17g\" data-hi=\"%.17g\" data-count=\"%d\" x=\"%.1f\" "
             "y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#a0522d\" stroke=\"#fff\">"
             "<title>%g&ndash;%g million: %d parcel(s)</title></rect>",
             start + b * step, start + (b + 1) * step, count[size_t(b)], x, base - h, bw, h, lo, hi,
             count[size_t(b)]);
    s += fmt("<text class=\"small\" transform=\"translate(%.1f %.0f) rotate(-60)\" text-anchor=\"end\">"
             "%g&ndash;%g</text>", x + bw / 2 + 3, base + 8, lo, hi);
  }
  s += fmt("<line x1=\"%.0f\" x2=\"%.0f\" y1=\"%.0f\" y2=\"%.0f\" stroke=\"#222\"/>", left, right, base, base);
  s += fmt("<text x=\"%.0f\" y=\"294\" text-anchor=\"middle\">NJOP per parcel (million %s), "
           "bins of %g million</text>", (left + right) / 2, html_escape(rows.front().second->currency).c_str(),
           step / 1e6);
  s += fmt("<text transform=\"translate(14 %.0f) rotate(-90)\" text-anchor=\"middle\">parcels</text>",
           (top_y + base) / 2);
  return s + "</svg>";
}

}  // namespace

std::string report_detail::legend_svg() {
  std::string s = "<svg class=\"legend\" width=\"560\" height=\"22\" viewBox=\"0 0 560 22\">";
  double x = 0;
  for (ElementType t : kTypes) {
    s += fmt("<rect x=\"%.0f\" y=\"4\" width=\"14\" height=\"14\" fill=\"%s\" stroke=\"#333\" "
             "stroke-width=\"0.5\"/><text x=\"%.0f\" y=\"16\">%s</text>",
             x, colour(t), x + 19, label(t));
    x += 112;
  }
  return s + "</svg>";
}

// ---------------------------------------------------------------- charts

std::string report_detail::area_chart(const BatchModel& m) {
  std::map<ElementType, TypeTotal> all;
  for (const auto& r : m.results)
    for (const auto& [t, x] : type_totals(r)) {
      all[t].area += x.area;
      all[t].sigma = std::hypot(all[t].sigma, x.sigma);
    }
  double top = 1;
  for (const auto& [t, x] : all) top = std::max(top, x.area + x.sigma);
  const int w = 560, row = 34, left = 110, bar_w = 300;  // room after the longest bar for its label
  std::string s = fmt("<svg width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" role=\"img\" "
                      "aria-label=\"Area by element type\">",
                      w, row * 5 + 10, w, row * 5 + 10);
  int i = 0;
  for (ElementType t : kTypes) {
    TypeTotal x = all[t];
    double y = 8 + i++ * row, len = bar_w * x.area / top, err = bar_w * x.sigma / top;
    s += fmt("<text x=\"%d\" y=\"%.0f\" text-anchor=\"end\">%s</text>", left - 8, y + 17, label(t));
    s += fmt("<rect x=\"%d\" y=\"%.0f\" width=\"%.1f\" height=\"22\" fill=\"%s\" stroke=\"#333\" "
             "stroke-width=\"0.5\"/>",
             left, y, len, colour(t));
    if (err > 0.5)
      s += fmt("<line x1=\"%.1f\" x2=\"%.1f\" y1=\"%.0f\" y2=\"%.0f\" stroke=\"#000\"/>",
               left + len - err, left + len + err, y + 11, y + 11);
    s += fmt("<text x=\"%.1f\" y=\"%.0f\">%.1f &plusmn; %.1f m&#178;</text>", left + len + err + 6,
             y + 16, x.area, x.sigma);
  }
  return s + "</svg>";
}

std::string report_detail::value_chart(const BatchModel& m,
                                       const std::vector<ParcelValuation>& vals) {
  auto vmap = by_parcel(vals);
  std::vector<std::pair<std::string, const ParcelValuation*>> rows;
  for (const auto& p : m.parcels)
    if (const ParcelValuation* v = find_valuation(vmap, p.id); valued(v)) rows.push_back({p.id, v});  // NaN: no bar
  if (rows.empty()) return "<p>No valuations.</p>";
  double top = 1;
  for (const auto& r : rows) top = std::max(top, r.second->njop + r.second->sigma_njop);
  const int h = 220, base = 190, left = 70;
  if (rows.size() > kBarsUpTo) return njop_histogram(rows);
  double step = std::min(40.0, 470.0 / rows.size());
  std::string s = fmt("<svg width=\"560\" height=\"%d\" viewBox=\"0 0 560 %d\">", h + 60, h + 60);
  for (int k = 0; k <= 4; ++k) {
    double y = base - 170.0 * k / 4;
    s += fmt("<line x1=\"%d\" x2=\"550\" y1=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>"
             "<text x=\"%d\" y=\"%.1f\" text-anchor=\"end\" class=\"small\">%s</text>",
             left, y, y, left - 4, y + 4, fmt(top >= 4e7 ? "%.0f" : "%.1f", top * k / 4 / 1e6).c_str());
  }
  s += "<text x=\"4\" y=\"12\" class=\"small\">million</text>";
  for (size_t i = 0; i < rows.size(); ++i) {
    const ParcelValuation& v = *rows[i].second;
    double x = left + 4 + i * step, bw = step * 0.75;
    double land = 170.0 * v.land_value / top, bld = 170.0 * v.building_value / top;
    s += fmt("<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#8c9a5b\"><title>%s "
             "land %s</title></rect>",
             x, base - land, bw, land, html_escape(rows[i].first).c_str(), money(v.land_value).c_str());
    s += fmt("<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#a0522d\"><title>%s "
             "building %s</title></rect>",
             x, base - land - bld, bw, bld, html_escape(rows[i].first).c_str(),
             money(v.building_value).c_str());
    s += fmt("<text transform=\"translate(%.1f %d) rotate(-50)\" text-anchor=\"end\" "
             "class=\"small\">%s</text>",
             x + bw / 2 + 3, base + 10, html_escape(rows[i].first).c_str());
  }
  s += "<rect x=\"380\" y=\"6\" width=\"12\" height=\"12\" fill=\"#8c9a5b\"/><text x=\"396\" "
       "y=\"16\" class=\"small\">land</text><rect x=\"440\" y=\"6\" width=\"12\" height=\"12\" "
       "fill=\"#a0522d\"/><text x=\"456\" y=\"16\" class=\"small\">building</text>";
  return s + "</svg>";
}

std::string parcel_svg(const Parcel& parcel, const ParcelResult& result, const LocalFrame& frame,
                       int width, int height) {
  std::vector<Projected> faces;
  double ground_z = HUGE_VAL;
  for (const Building& b : result.buildings) {
    ground_z = std::min(ground_z, b.terrain_z);
    for (const Element& e : b.elements)
      for (const Face& f : e.faces)
        if (f.ring.size() >= 3) faces.push_back(project_face(f, e.type));
  }
  if (!std::isfinite(ground_z)) ground_z = 0;
  std::vector<std::vector<Vec2>> outline;
  for (const Polygon2& poly : parcel.shape) {
    std::vector<Vec2> ring;
    for (const Vec2& w : poly.outer) {
      Vec2 l = frame.to_local(w);
      ring.push_back(project(Vec3(l.x(), l.y(), ground_z)));
    }
    outline.push_back(ring);
  }
  // Far to near; faces looking down (ground, outer ceiling) cannot be seen from
  // above, so they go first and show only where nothing covers them.
  std::stable_sort(faces.begin(), faces.end(), [](const Projected& a, const Projected& b) {
    if (a.down != b.down) return a.down;
    return a.depth > b.depth;
  });
  Vec2 lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
  auto grow = [&](const std::vector<Vec2>& r) {
    for (const Vec2& q : r) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  };
  for (const auto& f : faces)
    for (const auto& r : f.rings) grow(r);
  for (const auto& r : outline) grow(r);
  std::string s = fmt("<svg class=\"pic\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
                      "role=\"img\" aria-label=\"parcel %s\">",
                      width, height, width, height, html_escape(parcel.id).c_str());
  if (!std::isfinite(lo.x())) return s + "<text x=\"10\" y=\"20\">no geometry</text></svg>";
  const double margin = 12;
  Vec2 ext = (hi - lo).cwiseMax(Vec2(1e-6, 1e-6));
  double scale = std::min((width - 2 * margin) / ext.x(), (height - 2 * margin - 14) / ext.y());
  Vec2 pad((width - ext.x() * scale) / 2, 14 + (height - 14 - ext.y() * scale) / 2);
  if (!outline.empty())
    s += "<path d=\"" + path_data(outline, lo, scale, pad) +
         "\" fill=\"#eef3e6\" stroke=\"#6b8e23\" stroke-dasharray=\"5 3\" stroke-width=\"1.2\"/>";
  for (const auto& f : faces)
    s += "<path d=\"" + path_data(f.rings, lo, scale, pad) + "\" fill=\"" + f.fill +
         "\" fill-rule=\"evenodd\" stroke=\"#333\" stroke-width=\"0.6\" stroke-linejoin=\"round\"/>";
  s += fmt("<text x=\"6\" y=\"14\" class=\"small\">%s</text>", html_escape(parcel.id).c_str());
  return s + "</svg>";
}

std::string mesh_svg(const TriMesh& mesh, const std::string& title, int width, int height) {
  std::string s = fmt("<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"pic\" width=\"%d\" height=\"%d\" "
                      "viewBox=\"0 0 %d %d\" role=\"img\" aria-label=\"%s\">",
                      width, height, width, height, html_escape(title).c_str());
  const std::string caption = fmt("<text x=\"6\" y=\"14\" font-size=\"11\" font-family=\"sans-serif\">%s, %zu faces</text>",
                                  html_escape(title).c_str(), mesh.triangles.size());
  if (mesh.triangles.empty() || mesh.triangles.size() > kMaxPictureFaces)
    return s + caption + "<text x=\"6\" y=\"32\" font-size=\"11\" font-family=\"sans-serif\">" +
           (mesh.triangles.empty() ? "no faces" : "too many faces to draw: open the .glb") + "</text></svg>";
  struct Tri {
    std::array<Vec2, 3> corners;
    double depth, shade;
  };
  std::vector<Tri> tris;
  const Vec3 light = Vec3(-0.3, -0.6, 0.75).normalized();
  Vec2 lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
  for (const auto& t : mesh.soup()) {
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
    const Vec3 c = (t[0] + t[1] + t[2]) / 3;
    Tri tri{{project(t[0]), project(t[1]), project(t[2])}, c.x() + c.y() - c.z(),
            0.55 + 0.45 * std::abs(n.normalized().dot(light))};
    for (const Vec2& q : tri.corners) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    tris.push_back(tri);
  }
  std::stable_sort(tris.begin(), tris.end(), [](const Tri& a, const Tri& b) { return a.depth > b.depth; });
  const double margin = 10;
  const Vec2 ext = (hi - lo).cwiseMax(Vec2(1e-6, 1e-6));
  const double scale = std::min((width - 2 * margin) / ext.x(), (height - 2 * margin - 16) / ext.y());
  const Vec2 pad((width - ext.x() * scale) / 2, 16 + (height - 16 - ext.y() * scale) / 2);
  for (const Tri& t : tris) {
    s += "<path d=\"" + path_data({{t.corners.begin(), t.corners.end()}}, lo, scale, pad) + "\" fill=\"" +
         shaded("#d8d2c4", t.shade) + "\" stroke=\"#555\" stroke-width=\"0.25\" stroke-linejoin=\"round\"/>";
  }
  return s + caption + "</svg>";
}

}  // namespace c3d
