// The report's maps: the overview of every parcel coloured by value class, and
// one parcel's plan; both to scale, with a scale bar and a north arrow.
#include <algorithm>
#include <cmath>

#include "cadastre/report/report.h"
#include "cadastre/report/report_parts.h"
#include "core/io/crs.h"

namespace c3d {

using namespace report_detail;

namespace {

// ColorBrewer YlOrRd, 5 classes: light = low value, dark red = high.
constexpr const char* kRamp[] = {"#ffffb2", "#fecc5c", "#fd8d3c", "#f03b20", "#bd0026"};
constexpr size_t kClasses = 5;
constexpr double kMapWidth = 660;    // px of the map frame; the legend sits right of it
constexpr double kMapMaxHeight = 760;
constexpr double kMapMinHeight = 300;  // room for the legend beside a flat town
constexpr double kLegendWidth = 300;
constexpr double kFrame = 14;          // px between the parcels and the frame
constexpr double kStrip = 34;          // px under the parcels for the scale bar and north arrow

// A class break rounded to a unit a hundredth to a tenth of the values' range:
// breaks an officer can read that still tell the classes apart.
double round_break(double v, double range) {
  const double unit = std::pow(10.0, std::floor(std::log10(range)) - 1);
  return std::round(v / unit) * unit;
}

// "M x y L ... Z" in metres from `origin`, y up (SVG's y is negated).
std::string world_path(const MultiPolygon2& shape, const Vec2& origin) {
  std::string d;
  auto ring = [&](const Ring2& r) {
    for (size_t i = 0; i < r.size(); ++i) {
      Vec2 q = r[i] - origin;
      d += fmt("%c%.2f %.2f", i ? 'L' : 'M', q.x(), -q.y());
    }
    d += "Z";
  };
  for (const Polygon2& p : shape) {
    ring(p.outer);
    for (const Ring2& h : p.holes) ring(h);
  }
  return d;
}

std::string hatch(const char* id, const char* ink, const char* paper, double size) {
  return fmt("<pattern id=\"%s\" patternUnits=\"userSpaceOnUse\" width=\"%g\" height=\"%g\" "
             "patternTransform=\"rotate(45)\"><rect width=\"%g\" height=\"%g\" fill=\"%s\"/>"
             "<rect width=\"%g\" height=\"%g\" fill=\"%s\"/></pattern>",
             id, size, size, size, size, paper, size / 3, size, ink);
}

struct Style {
  std::string fill, stroke, extra;
  long cls = -1;
};

Style parcel_style(ParcelStatus st, double value, const ValueClasses& vc) {
  Style s{"#ffffff", "#555555", "stroke-width=\"0.7\""};
  if (st == ParcelStatus::Failed) return {"url(#hatch-failed)", "#c62828", "stroke-width=\"1.6\""};
  if (st == ParcelStatus::Suspect) return {"url(#hatch-suspect)", "#e65100", "stroke-width=\"1.6\""};
  if (std::isfinite(value)) {
    s.cls = long(vc.of(value));
    s.fill = vc.colour(size_t(s.cls));
  }
  if (st == ParcelStatus::Empty) s.extra = "stroke-width=\"1\" stroke-dasharray=\"4 3\"";
  return s;
}

std::string legend_entry(double y, const std::string& swatch, const std::string& text) {
  return fmt("<g transform=\"translate(%.0f %.0f)\">", kMapWidth + 16, y) + swatch +
         "<text x=\"26\" y=\"12\">" + text + "</text></g>";
}

std::string swatch(const std::string& fill, const char* stroke, const char* extra = "") {
  return "<rect width=\"18\" height=\"14\" fill=\"" + fill + "\" stroke=\"" + stroke + "\" " +
         extra + "/>";
}

std::string map_legend(const ValueClasses& vc, const std::vector<int>& per_class,
                       const std::string& currency, std::map<ParcelStatus, int> n, int unvalued) {
  std::string s = fmt("<text x=\"%.0f\" y=\"18\" font-weight=\"bold\">NJOP per m&#178; of land "
                      "(%s/m&#178;)</text>", kMapWidth + 16, currency.c_str());
  double y = 30;
  for (size_t k = vc.count(); k-- > 0; y += 20)  // high values on top
    s += "<g class=\"class\" data-class=\"" + std::to_string(k) + "\" data-lo=\"" +
         (k ? fmt("%.17g", vc.breaks[k - 1]) : std::string("-inf")) + "\" data-hi=\"" +
         (k < vc.breaks.size() ? fmt("%.17g", vc.breaks[k]) : std::string("inf")) + "\">" +
         legend_entry(y, swatch(vc.colour(k), "#555"), vc.label(k) + fmt(" (%d)", per_class[k])) + "</g>";
  y += 10;
  s += legend_entry(y, swatch("#ffffff", "#555", "stroke-dasharray=\"4 3\""),
                    fmt("dashed: empty, land only (%d)", n[ParcelStatus::Empty]));
  s += legend_entry(y += 20, swatch("url(#hatch-suspect-px)", "#e65100", "stroke-width=\"1.6\""),
                    fmt("suspect, land only (%d)", n[ParcelStatus::Suspect]));
  s += legend_entry(y += 20, swatch("url(#hatch-failed-px)", "#c62828", "stroke-width=\"1.6\""),
                    fmt("failed, land only (%d)", n[ParcelStatus::Failed]));
  s += legend_entry(y += 20, swatch("#ffffff", "#555"), fmt("not valued (%d)", unvalued));
  return s;
}

}  // namespace

size_t ValueClasses::of(double v) const {
  return size_t(std::upper_bound(breaks.begin(), breaks.end(), v) - breaks.begin());
}

const char* ValueClasses::colour(size_t k) const {
  const size_t n = count();
  return kRamp[n == 1 ? 2 : size_t(std::lround(double(k) * (kClasses - 1) / double(n - 1)))];
}

std::string ValueClasses::label(size_t k) const {
  if (breaks.empty()) return "all";
  if (k == 0) return "&lt; " + money(breaks[0]);
  if (k == breaks.size()) return "&#8805; " + money(breaks.back());
  return money(breaks[k - 1]) + " &ndash; &lt; " + money(breaks[k]);
}

ValueClasses report_detail::value_classes(std::vector<double> values) {
  ValueClasses vc;
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }),
               values.end());
  std::sort(values.begin(), values.end());
  if (values.empty() || !(values.back() > values.front())) return vc;  // one class
  for (size_t k = 1; k < kClasses; ++k) {
    double b = round_break(values[k * values.size() / kClasses], values.back() - values.front());
    // Within the values' span, so neither the lowest nor the highest class is empty.
    if (b > values.front() && b <= values.back() && (vc.breaks.empty() || b > vc.breaks.back()))
      vc.breaks.push_back(b);
  }
  return vc;
}

double report_detail::njop_per_m2(const ParcelValuation* v) {
  if (!valued(v) || !(v->land_area > 0)) return std::nan("");
  return v->njop / v->land_area;
}

std::string report_detail::scale_bar(double px_per_m, double x, double y, double max_px) {
  double len = 1;
  for (double decade = 1e-2; decade < 1e7; decade *= 10)
    for (double f : {1.0, 2.0, 5.0})
      if (f * decade * px_per_m <= max_px) len = f * decade;
  const double w = len * px_per_m;
  std::string s = fmt("<g class=\"scalebar\" data-metres=\"%g\" transform=\"translate(%.1f %.1f)\">", len, x, y);
  s += fmt("<rect width=\"%.1f\" height=\"5\" fill=\"#fff\" stroke=\"#222\"/>"
           "<rect width=\"%.1f\" height=\"5\" fill=\"#222\"/>", w, w / 2);
  s += fmt("<text y=\"17\" class=\"small\">0</text><text x=\"%.1f\" y=\"17\" class=\"small\" "
           "text-anchor=\"middle\">%g m</text></g>", w, len);
  return s;
}

std::string report_detail::north_arrow(double x, double y) {
  return fmt("<g class=\"north\" transform=\"translate(%.1f %.1f)\"><path d=\"M0 -16L7 6L0 1L-7 6Z\" "
             "fill=\"#222\"/><text y=\"-20\" text-anchor=\"middle\" font-weight=\"bold\">N</text></g>",
             x, y);
}

ValueClasses report_detail::map_classes(const BatchModel& m, const std::vector<ParcelValuation>& vals) {
  auto vmap = by_parcel(vals);
  std::vector<double> coloured;  // failed and suspect parcels are drawn apart, not by class
  for (size_t i = 0; i < m.parcels.size(); ++i) {
    const ParcelStatus st = m.results[i].status;
    if (st == ParcelStatus::Ok || st == ParcelStatus::Empty)
      coloured.push_back(njop_per_m2(find_valuation(vmap, m.parcels[i].id)));
  }
  return value_classes(coloured);
}

std::string report_detail::overview_map(const BatchModel& m, const std::vector<ParcelValuation>& vals,
                                        const std::string& link_prefix) {
  auto vmap = by_parcel(vals);
  std::vector<double> values;
  Vec2 lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
  for (size_t i = 0; i < m.parcels.size(); ++i) {
    values.push_back(njop_per_m2(find_valuation(vmap, m.parcels[i].id)));
    for (const Polygon2& poly : m.parcels[i].shape)
      for (const Vec2& q : poly.outer) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  }
  if (!std::isfinite(lo.x())) return "<p>No parcel geometry.</p>";
  const ValueClasses vc = map_classes(m, vals);
  const Vec2 origin = m.frame.origin.head<2>(), ext = (hi - lo).cwiseMax(Vec2(1, 1));
  const double scale = std::min((kMapWidth - 2 * kFrame) / ext.x(), (kMapMaxHeight - 2 * kFrame) / ext.y());
  const double height = std::max(kMapMinHeight, ext.y() * scale + 2 * kFrame);  // of the parcels' box
  // The view box in metres, centred on the parcels: one px is 1/scale metres.
  const Vec2 mid = (lo + hi) / 2 - origin;
  const double vw = kMapWidth / scale, vh = height / scale;
  std::string crs = html_escape(areas_crs_text(m.crs_wkt));
  std::string s = fmt("<svg class=\"map\" width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\" "
                      "role=\"img\" aria-label=\"Overview map of the parcels by value\"><defs>",
                      kMapWidth + kLegendWidth, height + kStrip + 22, kMapWidth + kLegendWidth,
                      height + kStrip + 22);
  s += hatch("hatch-failed-px", "#c62828", "#fdecea", 6) + hatch("hatch-suspect-px", "#e65100", "#fff3e0", 6);
  s += fmt("</defs><rect width=\"%.0f\" height=\"%.0f\" fill=\"#fbfbf8\" stroke=\"#999\"/>", kMapWidth,
           height + kStrip);
  // Paths in metres of the parcel layer's CRS minus `origin`: browsers draw in
  // single precision, which rounds 9,240,000 to whole metres.
  s += fmt("<svg class=\"world\" x=\"0\" y=\"0\" width=\"%.0f\" height=\"%.0f\" viewBox=\"%.3f %.3f %.3f %.3f\" "
           "data-origin-x=\"%.3f\" data-origin-y=\"%.3f\" data-crs=\"%s\"><defs>",
           kMapWidth, height, mid.x() - vw / 2, -mid.y() - vh / 2, vw, vh, origin.x(), origin.y(), crs.c_str());
  s += hatch("hatch-failed", "#c62828", "#fdecea", 6 / scale) +
       hatch("hatch-suspect", "#e65100", "#fff3e0", 6 / scale) + "</defs>";
  std::vector<int> per_class(vc.count(), 0);
  std::map<ParcelStatus, int> n;
  int unvalued = 0;
  for (size_t i = 0; i < m.parcels.size(); ++i) {
    const Parcel& p = m.parcels[i];
    const ParcelResult& r = m.results[i];
    const Style st = parcel_style(r.status, values[i], vc);
    if (st.cls >= 0) ++per_class[size_t(st.cls)];
    ++n[r.status];
    unvalued += !std::isfinite(values[i]);
    s += "<a href=\"" + link_prefix + parcel_page(p) + "\"><path data-parcel=\"" + html_escape(p.id) +
         "\" data-status=\"" + to_string(r.status) + "\" data-class=\"" + std::to_string(st.cls) +
         "\" data-value=\"" + fmt("%.17g", values[i]) + "\" d=\"" + world_path(p.shape, origin) +
         "\" fill=\"" + st.fill + "\" fill-rule=\"evenodd\" stroke=\"" + st.stroke + "\" " + st.extra +
         " vector-effect=\"non-scaling-stroke\"><title>" + html_escape(p.id) + " (" + to_string(r.status) +
         "): " + (std::isfinite(values[i]) ? money(values[i]) + " per m&#178;" : std::string("not valued")) +
         "</title></path></a>";
  }
  // Scale bar and north arrow in a strip under the parcels, never over one.
  s += "</svg>" + north_arrow(kMapWidth - 24, height + kStrip - 8) +
       scale_bar(scale, 14, height + 8, kMapWidth / 4);
  s += map_legend(vc, per_class, vals.empty() ? "" : html_escape(vals.front().currency), n, unvalued);
  s += fmt("<text x=\"0\" y=\"%.0f\" class=\"small\">%s, grid north up; x = %.2f + map x, y = %.2f "
           "&minus; map y (metres). Classes: quintiles of the modelled and empty parcels, rounded.</text>",
           height + kStrip + 16, crs.c_str(), origin.x(), origin.y());
  return s + "</svg>";
}

std::string report_detail::plan_svg(const Parcel& p, const ParcelResult& r, const LocalFrame& frame,
                                    int width, int height) {
  struct Piece {
    double z;
    std::string d;
    const char* fill;
  };
  std::vector<Piece> pieces;  // roofs and grounds seen from above, low to high
  Vec2 lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
  MultiPolygon2 local;
  for (const Polygon2& poly : p.shape) {
    Polygon2 q;
    for (const Vec2& w : poly.outer) q.outer.push_back(frame.to_local(w));
    for (const Vec2& v : q.outer) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    local.push_back(q);
  }
  for (const Building& b : r.buildings)
    for (const Element& e : b.elements) {
      if (e.type != ElementType::Roof && e.type != ElementType::Ground) continue;
      for (const Face& f : e.faces) {
        Polygon2 q;
        double z = 0;
        for (const Vec3& v : f.ring) q.outer.push_back(v.head<2>()), z += v.z() / double(f.ring.size());
        for (const Vec2& v : q.outer) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
        pieces.push_back({e.type == ElementType::Ground ? -HUGE_VAL : z, world_path({q}, Vec2::Zero()), colour(e.type)});
      }
    }
  std::stable_sort(pieces.begin(), pieces.end(), [](const Piece& a, const Piece& b) { return a.z < b.z; });
  std::string s = fmt("<svg class=\"pic plan\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" role=\"img\" "
                      "aria-label=\"plan of parcel %s\">", width, height, width, height, html_escape(p.id).c_str());
  if (!std::isfinite(lo.x())) return s + "<text x=\"10\" y=\"20\">no geometry</text></svg>";
  const double margin = 18;
  const Vec2 ext = (hi - lo).cwiseMax(Vec2(1, 1)), mid = (lo + hi) / 2;
  const double scale = std::min((width - 2 * margin) / ext.x(), (height - 2 * margin - 20) / ext.y());
  const double vw = width / scale, vh = height / scale;
  s += fmt("<svg x=\"0\" y=\"0\" width=\"%d\" height=\"%d\" viewBox=\"%.3f %.3f %.3f %.3f\">", width, height,
           mid.x() - vw / 2, -mid.y() - vh / 2, vw, vh);
  s += "<path d=\"" + world_path(local, Vec2::Zero()) + "\" fill=\"#eef3e6\" stroke=\"#6b8e23\" "
       "stroke-dasharray=\"5 3\" stroke-width=\"1.2\" vector-effect=\"non-scaling-stroke\"/>";
  for (const Piece& q : pieces)
    s += "<path d=\"" + q.d + "\" fill=\"" + q.fill + "\" stroke=\"#333\" stroke-width=\"0.6\" "
         "vector-effect=\"non-scaling-stroke\"/>";
  s += "</svg>" + north_arrow(width - 16, 30) + scale_bar(scale, 8, height - 22, width / 3.0);
  return s + fmt("<text x=\"6\" y=\"14\" class=\"small\">plan, %s</text></svg>", html_escape(p.id).c_str());
}

}  // namespace c3d
