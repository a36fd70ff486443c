#include "cadastre/report/report.h"
#include "core/text.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include "cadastre/store.h"
#include "core/error.h"
#include "core/geometry/geometry.h"
#include "valuation/valuation.h"

namespace c3d {

namespace {

const ElementType kTypes[] = {ElementType::Roof, ElementType::Wall, ElementType::PartyWall,
                              ElementType::Ground, ElementType::OuterCeiling};

const char* colour(ElementType t) {
  switch (t) {
    case ElementType::Roof: return "#a0522d";         // red-brown
    case ElementType::Wall: return "#d8d8d8";         // light grey
    case ElementType::PartyWall: return "#f28e2b";    // orange
    case ElementType::Ground: return "#555555";       // dark grey
    case ElementType::OuterCeiling: return "#4e79a7"; // blue
  }
  return "#000";
}

const char* label(ElementType t) {
  switch (t) {
    case ElementType::Roof: return "Roof";
    case ElementType::Wall: return "Wall";
    case ElementType::PartyWall: return "Party wall";
    case ElementType::Ground: return "Ground floor";
    case ElementType::OuterCeiling: return "Outer ceiling";
  }
  return "?";
}

std::string fmt(const char* f, ...) {
  char buf[512];
  va_list a;
  va_start(a, f);
  std::vsnprintf(buf, sizeof buf, f, a);
  va_end(a);
  return buf;
}

// Money with thousands separators, no decimals (IDR has no minor unit in use).
std::string money(double v) {
  if (!std::isfinite(v)) return "";
  std::string digits = fmt("%.0f", std::abs(v));
  std::string out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return (v < -0.5 ? "-" : "") + out;
}

std::string html_escape(const std::string& s) { return escape_markup(s); }

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string pm(double v, double sigma, const char* unit = "") {
  return fmt("%.2f&nbsp;&plusmn;&nbsp;%.2f%s", v, sigma, unit);
}

std::map<std::string, const ParcelValuation*> by_parcel(const std::vector<ParcelValuation>& v) {
  std::map<std::string, const ParcelValuation*> m;
  for (const auto& x : v) m[x.parcel_id] = &x;
  return m;
}

// Sum of element areas of one type over a parcel, sigma in quadrature.
struct TypeTotal {
  double area = 0, sigma = 0;
};

std::map<ElementType, TypeTotal> type_totals(const ParcelResult& r) {
  std::map<ElementType, TypeTotal> t;
  for (const Building& b : r.buildings)
    for (const Element& e : b.elements) {
      TypeTotal& x = t[e.type];
      x.area += e.area;
      x.sigma = std::hypot(x.sigma, e.sigma_area);
    }
  return t;
}

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

std::string legend_svg() {
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

std::string area_chart(const BatchModel& m) {
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

// NJOP per parcel as stacked land / building bars; a histogram when there are many.
std::string value_chart(const BatchModel& m, const std::vector<ParcelValuation>& vals) {
  auto vmap = by_parcel(vals);
  std::vector<std::pair<std::string, const ParcelValuation*>> rows;
  for (const auto& p : m.parcels)
    if (auto it = vmap.find(p.id); it != vmap.end()) rows.push_back({p.id, it->second});
  if (rows.empty()) return "<p>No valuations.</p>";
  double top = 1;
  for (const auto& r : rows) top = std::max(top, r.second->njop + r.second->sigma_njop);
  const int h = 220, base = 190, left = 70;
  if (rows.size() > 60) {  // histogram of NJOP
    const int bins = 20;
    std::vector<int> count(bins, 0);
    for (const auto& r : rows) count[std::min(bins - 1, int(bins * r.second->njop / top))]++;
    int cmax = *std::max_element(count.begin(), count.end());
    std::string s = fmt("<svg width=\"560\" height=\"%d\" viewBox=\"0 0 560 %d\">", h + 20, h + 20);
    for (int b = 0; b < bins; ++b) {
      double bh = 170.0 * count[b] / std::max(1, cmax);
      s += fmt("<rect x=\"%d\" y=\"%.1f\" width=\"22\" height=\"%.1f\" fill=\"#a0522d\"/>",
               left + b * 24, base - bh, bh);
    }
    s += fmt("<text x=\"%d\" y=\"%d\">0</text><text x=\"%d\" y=\"%d\" text-anchor=\"end\">%s</text>",
             left, base + 16, left + bins * 24, base + 16, money(top).c_str());
    s += fmt("<text x=\"5\" y=\"20\">parcels (max %d per bin)</text>", cmax);
    return s + "</svg>";
  }
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

// ---------------------------------------------------------------- tables

const char* kCss = R"CSS(
body{font-family:"DejaVu Sans",Arial,sans-serif;margin:24px;color:#222;max-width:1200px}
h1{font-size:22px;margin-bottom:4px}h2{font-size:18px;border-bottom:2px solid #a0522d;padding-bottom:3px;margin-top:28px}
h3{font-size:15px;margin:4px 0}
.meta{color:#666;font-size:12px}
.cards{display:flex;gap:12px;flex-wrap:wrap}.card{border:1px solid #ccc;border-radius:6px;padding:8px 14px;min-width:120px}
.card b{display:block;font-size:20px}.ok{color:#2e7d32}.empty{color:#777}.failed{color:#c62828}
table{border-collapse:collapse;font-size:12px;margin:6px 0}th,td{border:1px solid #ccc;padding:3px 6px}
th{background:#f3ede8;text-align:left}td.n{text-align:right;white-space:nowrap}
.charts{display:flex;gap:24px;flex-wrap:wrap}.small{font-size:10px}svg text{font-size:12px;fill:#222}
.parcel{display:flex;gap:16px;border-top:1px solid #ddd;padding:10px 0;break-inside:avoid}
.parcel svg.pic{border:1px solid #ddd;background:#fbfbf8;flex:none}
)CSS";

std::string summary_html(const BatchModel& m, const std::vector<ParcelValuation>& vals) {
  int ok = 0, empty = 0, failed = 0;
  std::string problems;
  for (size_t i = 0; i < m.results.size(); ++i) {
    const ParcelResult& r = m.results[i];
    ok += r.status == ParcelStatus::Ok;
    empty += r.status == ParcelStatus::Empty;
    failed += r.status == ParcelStatus::Failed;
    if (r.status != ParcelStatus::Ok)
      problems += fmt("<tr><td>%s</td><td class=\"%s\">%s</td><td>%s</td></tr>",
                      html_escape(r.parcel_id).c_str(), to_string(r.status), to_string(r.status),
                      html_escape(r.reason).c_str());
  }
  double land = 0, building = 0, njop = 0, tax = 0, s_njop = 0, s_tax = 0;
  std::string currency = vals.empty() ? "" : vals.front().currency;
  for (const auto& v : vals) {
    land += v.land_value;
    building += v.building_value;
    njop += v.njop;
    tax += v.tax;
    s_njop = std::hypot(s_njop, v.sigma_njop);
    s_tax = std::hypot(s_tax, v.sigma_tax);
  }
  std::string s = "<div class=\"cards\">";
  s += fmt("<div class=\"card\">Parcels<b>%zu</b></div>", m.parcels.size());
  s += fmt("<div class=\"card ok\">Modelled<b>%d</b></div><div class=\"card empty\">Empty<b>%d</b>"
           "</div><div class=\"card failed\">Failed<b>%d</b></div>",
           ok, empty, failed);
  s += fmt("<div class=\"card\">Land value (%s)<b>%s</b></div>", currency.c_str(), money(land).c_str());
  s += fmt("<div class=\"card\">Building value (%s)<b>%s</b></div>", currency.c_str(),
           money(building).c_str());
  s += fmt("<div class=\"card\">NJOP total (%s)<b>%s</b>&plusmn; %s</div>", currency.c_str(),
           money(njop).c_str(), money(s_njop).c_str());
  s += fmt("<div class=\"card\">PBB tax (%s)<b>%s</b>&plusmn; %s</div></div>", currency.c_str(),
           money(tax).c_str(), money(s_tax).c_str());
  if (!problems.empty())
    s += "<h3>Parcels without a model</h3><table><tr><th>Parcel</th><th>Status</th><th>Reason"
         "</th></tr>" + problems + "</table>";
  return s;
}

std::string parcel_table(const BatchModel& m, const std::vector<ParcelValuation>& vals) {
  auto vmap = by_parcel(vals);
  std::string s =
      "<table><tr><th>Parcel</th><th>Right</th><th>Status</th><th>Land m&#178;</th>"
      "<th>Roof m&#178;</th><th>Wall m&#178;</th><th>Party wall m&#178;</th><th>Ground m&#178;</th>"
      "<th>Outer ceiling m&#178;</th><th>Land value</th><th>Building value</th><th>NJOP</th>"
      "<th>PBB tax</th></tr>";
  for (size_t i = 0; i < m.parcels.size(); ++i) {
    const Parcel& p = m.parcels[i];
    const ParcelResult& r = m.results[i];
    auto tt = type_totals(r);
    auto it = vmap.find(p.id);
    const ParcelValuation* v = it == vmap.end() ? nullptr : it->second;
    s += fmt("<tr><td><a href=\"#p%zu\">%s</a></td><td>%s</td><td class=\"%s\">%s</td>", i,
             html_escape(p.id).c_str(), html_escape(p.right_type).c_str(), to_string(r.status),
             to_string(r.status));
    s += v ? fmt("<td class=\"n\">%.1f%s</td>", v->land_area, v->land_area_source == "official" ? "" : "*")
           : std::string("<td></td>");
    for (ElementType t : kTypes)
      s += tt.count(t) ? "<td class=\"n\">" + pm(tt[t].area, tt[t].sigma) + "</td>" : "<td></td>";
    if (v)
      s += "<td class=\"n\">" + money(v->land_value) + "</td><td class=\"n\">" +
           money(v->building_value) + " &plusmn; " + money(v->sigma_building_value) +
           "</td><td class=\"n\">" + money(v->njop) + "</td><td class=\"n\">" + money(v->tax) +
           "</td>";
    else
      s += "<td></td><td></td><td></td><td></td>";
    s += "</tr>";
  }
  return s + "</table><p class=\"meta\">* computed area (no certified area in the parcel "
             "layer). &plusmn; values are 1&sigma; from the plane fits.</p>";
}

std::string element_table(const ParcelResult& r, const ParcelValuation* v) {
  std::map<std::pair<std::string, int>, const CostItem*> items;
  if (v)
    for (const auto& c : v->items) items[{c.building_id, c.element_index}] = &c;
  std::string s =
      "<table><tr><th>Building</th><th>#</th><th>Element</th><th>Area m&#178;</th><th>Plan m&#178;"
      "</th><th>Slope&deg;</th><th>Azimuth&deg;</th><th>Points</th><th>RMSE m</th><th>Evidence</th>"
      "<th>Unit cost</th><th>Amount</th></tr>";
  for (const Building& b : r.buildings)
    for (int i = 0; i < int(b.elements.size()); ++i) {
      const Element& e = b.elements[size_t(i)];
      auto it = items.find({b.id, i});
      s += fmt("<tr><td>%s</td><td class=\"n\">%d</td><td style=\"white-space:nowrap\"><span style=\"color:%s\">&#9632;</span> "
               "%s</td><td class=\"n\">%s</td><td class=\"n\">%.2f</td><td class=\"n\">%.1f</td>"
               "<td class=\"n\">%.0f</td><td class=\"n\">%d</td><td class=\"n\">%.3f</td><td>%s</td>",
               html_escape(b.id).c_str(), i, colour(e.type), label(e.type),
               pm(e.area, e.sigma_area).c_str(), e.plan_area, e.slope_deg, e.azimuth_deg,
               e.support_points, e.rmse, e.type == ElementType::Wall || e.type == ElementType::PartyWall
                                             ? to_string(e.evidence) : "");
      if (it != items.end())
        s += "<td class=\"n\">" + money(it->second->unit_cost) + "</td><td class=\"n\">" +
             money(it->second->amount) + " &plusmn; " + money(it->second->sigma_amount) + "</td>";
      else
        s += "<td></td><td></td>";
      s += "</tr>";
    }
  return s + "</table>";
}

std::string valuation_lines(const ParcelValuation& v) {
  std::string s = "<table>";
  auto row = [&](const std::string& k, const std::string& val) {
    s += "<tr><th>" + k + "</th><td class=\"n\">" + val + "</td></tr>";
  };
  row("Land", fmt("%.1f m&#178; (%s) &times; %s (zone %s) = ", v.land_area,
                  v.land_area_source.c_str(), money(v.land_price_per_m2).c_str(),
                  html_escape(v.zone).c_str()) + money(v.land_value));
  row("Building replacement cost", money(v.building_cost) + " &plusmn; " + money(v.sigma_building_cost));
  row(fmt("Depreciation (%.0f years, %.0f %%)", v.age_years, 100 * v.depreciation_share),
      "&minus;" + money(v.depreciation));
  row("Building value", money(v.building_value) + " &plusmn; " + money(v.sigma_building_value));
  row("NJOP", "<b>" + money(v.njop) + "</b> &plusmn; " + money(v.sigma_njop));
  row(fmt("PBB tax %.2f %% &times; (NJOP &minus; %s)", 100 * v.tax_rate, money(v.njoptkp).c_str()),
      "<b>" + money(v.tax) + "</b> &plusmn; " + money(v.sigma_tax) + " " + v.currency);
  if (!v.note.empty()) row("Note", html_escape(v.note));
  return s + "</table>";
}

std::string parcel_sections(const BatchModel& m, const std::vector<ParcelValuation>& vals) {
  auto vmap = by_parcel(vals);
  std::string s;
  for (size_t i = 0; i < m.parcels.size(); ++i) {
    const Parcel& p = m.parcels[i];
    const ParcelResult& r = m.results[i];
    auto it = vmap.find(p.id);
    const ParcelValuation* v = it == vmap.end() ? nullptr : it->second;
    s += fmt("<div class=\"parcel\" id=\"p%zu\">", i) + parcel_svg(p, r, m.frame) + "<div>";
    s += fmt("<h3>Parcel %s &mdash; %s &mdash; <span class=\"%s\">%s</span></h3>",
             html_escape(p.id).c_str(), html_escape(p.right_type).c_str(), to_string(r.status),
             to_string(r.status));
    if (!r.reason.empty()) s += "<p>" + html_escape(r.reason) + "</p>";
    for (const Building& b : r.buildings)
      s += fmt("<p class=\"meta\">%s: volume %.1f m&#179;, eave %.2f m, ridge %.2f m, %d storey(s), "
               "solid %s; roof deviation RMSE %.3f m (%ld points), wall %.3f m (%ld points)</p>",
               html_escape(b.id).c_str(), b.volume, b.eave_height, b.ridge_height, b.storeys,
               b.solid_valid ? "closed" : ("open: " + html_escape(b.solid_problem)).c_str(),
               b.roof_deviation.rmse, b.roof_deviation.n, b.wall_deviation.rmse, b.wall_deviation.n);
    if (!r.buildings.empty()) s += element_table(r, v);
    if (v) s += valuation_lines(*v);
    s += "</div></div>";
  }
  return s;
}

}  // namespace

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

std::string report_html(const BatchModel& m, const std::vector<ParcelValuation>& vals,
                        const ReportInfo& info) {
  std::string s = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" +
                  html_escape(info.title) + "</title><style>" + kCss + "</style></head><body>";
  s += "<h1>" + html_escape(info.title) + "</h1><p class=\"meta\">";
  if (!info.source.empty()) s += "Source: " + html_escape(info.source) + ". ";
  if (!info.run_note.empty()) s += html_escape(info.run_note) + ". ";
  if (m.epsg) s += fmt("CRS EPSG:%d. ", m.epsg);
  s += "Areas in m&#178;, values in " + html_escape(vals.empty() ? "" : vals.front().currency) +
       ".</p>";
  s += "<h2>Summary</h2>" + summary_html(m, vals);
  s += "<h2>Charts</h2><div class=\"charts\"><div><h3>Area by element type (all parcels)</h3>" +
       area_chart(m) + "</div><div><h3>Value per parcel (NJOP)</h3>" + value_chart(m, vals) +
       "</div></div>";
  s += "<h2>Parcels</h2>" + parcel_table(m, vals);
  s += "<h2>Buildings and elements</h2>" + legend_svg() + parcel_sections(m, vals);
  s += "<p class=\"meta\">Cost approach: building = &Sigma; element area &times; unit cost &times; "
       "quality factor, less depreciation by age; land = parcel area &times; zone land price; "
       "NJOP = land + building; PBB = rate &times; max(0, NJOP &minus; NJOPTKP). Each amount "
       "carries &plusmn;1&sigma; = unit cost &times; &sigma; of its area; totals combine in "
       "quadrature.</p></body></html>\n";
  return s;
}

namespace {

const char* const kCsvColumns[] = {
    "record", "parcel_id", "status", "reason", "right_type", "building_id", "element_index",
    "element_type", "area_m2", "sigma_area_m2", "plan_area_m2", "slope_deg", "azimuth_deg",
    "support_points", "rmse_m", "wall_evidence", "unit_cost", "amount", "sigma_amount", "roof_m2",
    "wall_m2", "party_wall_m2", "ground_m2", "outer_ceiling_m2", "land_area_m2",
    "land_area_source", "zone", "land_value", "building_cost", "depreciation", "building_value",
    "sigma_building_value", "njop", "sigma_njop", "tax", "sigma_tax", "currency"};

// One CSV row addressed by column name, so parcel and element rows share a header.
class CsvRow {
 public:
  CsvRow() {
    for (const char* c : kCsvColumns) cells_[c];
  }
  CsvRow& set(const char* col, const std::string& v) {
    cells_.at(col) = csv_field(v);
    return *this;
  }
  CsvRow& num(const char* col, double v, const char* f = "%.2f") {
    return std::isfinite(v) ? set(col, fmt(f, v)) : *this;
  }
  std::string line() const {
    std::string s;
    for (const char* c : kCsvColumns) s += (s.empty() ? "" : ",") + cells_.at(c);
    return s + "\n";
  }

 private:
  std::map<std::string, std::string> cells_;
};

}  // namespace

std::string report_csv(const BatchModel& m, const std::vector<ParcelValuation>& vals) {
  auto vmap = by_parcel(vals);
  std::string s;
  for (const char* c : kCsvColumns) s += (s.empty() ? "" : ",") + std::string(c);
  s += "\n";
  static const char* const area_cols[] = {"roof_m2", "wall_m2", "party_wall_m2", "ground_m2",
                                          "outer_ceiling_m2"};
  for (size_t i = 0; i < m.parcels.size(); ++i) {
    const Parcel& p = m.parcels[i];
    const ParcelResult& r = m.results[i];
    auto it = vmap.find(p.id);
    const ParcelValuation* v = it == vmap.end() ? nullptr : it->second;
    auto tt = type_totals(r);
    CsvRow row;
    row.set("record", "parcel").set("parcel_id", p.id).set("status", to_string(r.status))
        .set("reason", r.reason).set("right_type", p.right_type);
    for (int k = 0; k < 5; ++k) row.num(area_cols[k], tt[kTypes[k]].area, "%.3f");
    if (v) {
      row.num("land_area_m2", v->land_area, "%.3f").set("land_area_source", v->land_area_source)
          .set("zone", v->zone).num("land_value", v->land_value)
          .num("building_cost", v->building_cost).num("depreciation", v->depreciation)
          .num("building_value", v->building_value)
          .num("sigma_building_value", v->sigma_building_value).num("njop", v->njop)
          .num("sigma_njop", v->sigma_njop).num("tax", v->tax).num("sigma_tax", v->sigma_tax)
          .set("currency", v->currency);
    }
    s += row.line();
    std::map<std::pair<std::string, int>, const CostItem*> items;
    if (v)
      for (const auto& c : v->items) items[{c.building_id, c.element_index}] = &c;
    for (const Building& b : r.buildings)
      for (int k = 0; k < int(b.elements.size()); ++k) {
        const Element& e = b.elements[size_t(k)];
        CsvRow er;
        er.set("record", "element").set("parcel_id", p.id).set("building_id", b.id)
            .set("element_index", std::to_string(k)).set("element_type", to_string(e.type))
            .num("area_m2", e.area, "%.3f").num("sigma_area_m2", e.sigma_area, "%.3f")
            .num("plan_area_m2", e.plan_area, "%.3f").num("slope_deg", e.slope_deg)
            .num("azimuth_deg", e.azimuth_deg)
            .set("support_points", std::to_string(e.support_points))
            .num("rmse_m", e.rmse, "%.4f").set("wall_evidence", to_string(e.evidence));
        if (auto c = items.find({b.id, k}); c != items.end())
          er.num("unit_cost", c->second->unit_cost).num("amount", c->second->amount)
              .num("sigma_amount", c->second->sigma_amount);
        s += er.line();
      }
  }
  return s;
}

void write_report(const std::string& out_dir, const BatchModel& model,
                  const std::vector<ParcelValuation>& valuations, const ReportInfo& info) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  auto write = [&](const std::string& name, const std::string& text) {
    std::string path = (std::filesystem::path(out_dir) / name).string();
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) throw InputError(path, "cannot write report");
  };
  write("report.html", report_html(model, valuations, info));
  write("report.csv", report_csv(model, valuations));
}

void write_report_from_store(const std::string& store_path, const std::string& out_dir,
                             const Config& cfg, bool revalue) {
  write_report_from_store(load_batch_model(store_path), store_path, out_dir, cfg, revalue);
}

void write_report_from_store(const BatchModel& model, const std::string& store_path,
                             const std::string& out_dir, const Config& cfg, bool revalue) {
  std::vector<ParcelValuation> vals =
      revalue ? value_batch(model, cfg.valuation) : load_valuations(store_path);
  ReportInfo info;
  info.source = store_path;
  auto runs = load_runs(store_path);
  if (!runs.empty()) {
    const RunRecord& r = runs.back();
    info.run_note = r.tool_version + ", run " + std::to_string(r.id) + " started " + r.started +
                    (r.finished.empty() ? " (not finished)" : ", finished " + r.finished) + ", " +
                    std::to_string(r.inputs.size()) + " input file(s) with SHA-256 in the store";
  }
  if (revalue) info.run_note += (info.run_note.empty() ? "" : "; ") +
                                std::string("re-valued with ") + cfg.source;
  write_report(out_dir, model, vals, info);
}

}  // namespace c3d
