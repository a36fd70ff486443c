// The report's detail pages: report/parcels-NNN.html (a table and one section
// per parcel, kParcelsPerPage parcels each) and report/parcel/<id>.html (one
// printable A4 page per parcel), and the list of every report file.
#include <algorithm>
#include <cmath>
#include <map>

#include "cadastre/report/report.h"
#include "cadastre/report/report_3d.h"
#include "cadastre/report/report_parts.h"
#include "core/io/crs.h"

namespace c3d {

using namespace report_detail;

namespace {

// Element rows a parcel's page prints one by one; beyond, totals by type (an
// A4 sheet holds the pictures, the valuation and about 35 rows).
constexpr size_t kPrintedElements = 30;

const char* kCss = R"CSS(
body{font-family:"DejaVu Sans",Arial,sans-serif;margin:24px;color:#222;max-width:1200px}
h1{font-size:22px;margin-bottom:4px}h2{font-size:18px;border-bottom:2px solid #a0522d;padding-bottom:3px;margin-top:28px}
h3{font-size:15px;margin:4px 0}
.meta{color:#666;font-size:12px}
.cards{display:flex;gap:12px;flex-wrap:wrap;margin-bottom:10px}.card{border:1px solid #ccc;border-radius:6px;padding:8px 14px;min-width:120px}
.card b{display:block;font-size:20px}.ok{color:#2e7d32}.empty{color:#777}.failed{color:#c62828}.suspect{color:#e65100}
table{border-collapse:collapse;font-size:12px;margin:6px 0}th,td{border:1px solid #ccc;padding:3px 6px}
th{background:#f3ede8;text-align:left}td.n{text-align:right;white-space:nowrap}
tr.total th,tr.total td{font-weight:bold;border-top:2px solid #555}
table.totals{font-size:11px}table.totals th{vertical-align:top}.sig{color:#666;font-size:10px;font-weight:normal}
.charts{display:flex;gap:24px;flex-wrap:wrap}.small{font-size:10px}svg text{font-size:12px;fill:#222}
.parcel{display:flex;gap:16px;border-top:1px solid #ddd;padding:10px 0;break-inside:avoid}
svg.pic{border:1px solid #ddd;background:#fbfbf8;flex:none}.pics{display:flex;gap:10px}
nav{background:#f3ede8;padding:6px 10px;margin-bottom:10px;font-size:13px}nav a{margin-right:14px}
.print-only{display:none}
@page{size:A4;margin:12mm}
.view3d{border:1px solid #999;margin:8px 0;background:#f4f4ef}.view3d-canvas{width:100%;height:460px}
.view3d-pick,.view3d-legend,.view3d-note{font-size:13px;padding:4px 8px;margin:0}.view3d-legend label,.view3d-legend .entry{margin-right:12px;white-space:nowrap}
.view3d .swatch{display:inline-block;width:12px;height:12px;margin:0 4px;border:1px solid #555;vertical-align:middle}
@media print{nav,.noprint,.screen-only{display:none}.print-only{display:block}body{margin:0;max-width:none;font-size:10px}
h1{font-size:16px}h2{font-size:13px;break-after:avoid}.parcel{break-inside:avoid}
table{font-size:8px}th,td{padding:1px 3px}tr{break-inside:avoid}.meta{font-size:8px}
svg.pic{width:330px;height:240px}}
)CSS";

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
      // A dash where no point measured the element: 0.000 would claim a perfect fit.
      s += fmt("<tr><td>%s</td><td class=\"n\">%d</td><td style=\"white-space:nowrap\"><span style=\"color:%s\">&#9632;</span> "
               "%s</td><td class=\"n\">%s</td><td class=\"n\">%.2f</td><td class=\"n\">%.1f</td>"
               "<td class=\"n\">%.0f</td><td class=\"n\">%d</td><td class=\"n\">%s</td><td>%s</td>",
               html_escape(b.id).c_str(), i, colour(e.type), label(e.type),
               pm(e.area, e.sigma_area).c_str(), e.plan_area, e.slope_deg, e.azimuth_deg,
               e.support_points, e.support_points > 0 ? fmt("%.3f", e.rmse).c_str() : "&mdash;",
               e.type == ElementType::Wall || e.type == ElementType::PartyWall ? to_string(e.evidence) : "");
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

// A deviation with its point count, or a dash where no point measured it.
std::string deviation(const Deviation& d) {
  return d.n > 0 ? fmt("%.3f m (%ld points)", d.rmse, d.n) : std::string("&mdash; (no points)");
}

// What the optimizer did to a curved building's dense mesh; "" where it did not run.
std::string refinement_text(const MeshRefinement& m) {
  if (m.triangles == 0) return "";
  return fmt("; its scan's mesh (%d triangles, %.0f %% of the vertices snapped onto its exact surfaces) "
             "lies %.3f &rarr; %.3f m from them (Chamfer) and %.3f &rarr; %.3f m from the points",
             m.triangles, 100 * m.snapped_share, m.chamfer_before_m, m.chamfer_after_m, m.cloud_before_m,
             m.cloud_after_m);
}

// A percentage with its sign, or a dash for none.
std::string signed_percent(double share) {
  return std::isfinite(share) ? fmt("%+.1f %%", 100 * share) : std::string("&mdash;");
}

// Of level 4's planar regions, how many a lighter level kept and how far
// their extent moved (seed 002's table): a level that smears frames and
// ridges shows it here.
std::string planar_kept(const MeshLevelRecord& l) {
  if (l.level == 4) return fmt("%ld", l.planar_regions);
  if (!std::isfinite(l.extent_change_m)) return "&mdash;";
  return fmt("%ld of %ld, &#8804; %.3f m", l.planar_regions, l.planar_regions + l.planar_lost, l.extent_change_m);
}

// The building's mesh ladder (batch --mesh, docs/meshes.md): whether the
// element model agrees with the closed hull of its points, each level's
// figures and files, and on the parcel's own page a picture of each level.
// `to_out`: the way from the page up to the output folder.
std::string mesh_lines(const Building& b, const std::string& to_out, bool pictures) {
  const BuildingMesh& m = b.mesh;
  if (m.method.empty()) return "";
  std::string s = "<p class=\"meta\">" + html_escape(b.id) + " mesh (" + html_escape(m.method) +
                  fmt(", %ld points, spacing %.2f m): ", m.points, m.spacing_m);
  if (!m.flag.empty())
    s += "<b class=\"suspect\">the model differs from the hull of its points: " + html_escape(m.flag) +
         "; look at it</b>";
  else if (std::isfinite(m.volume_diff))
    s += "the model agrees with the hull of its points (volume " + signed_percent(m.volume_diff) + ", roof area " +
         signed_percent(m.roof_area_diff) + ")";
  if (!m.problem.empty()) s += (m.flag.empty() && !std::isfinite(m.volume_diff) ? "" : "; ") + html_escape(m.problem);
  s += "</p>";
  if (m.levels.empty()) return s;
  s += "<table><tr><th>level</th><th>faces</th><th>cloud to mesh, mean / p95</th><th>closed</th>"
       "<th>volume</th><th>planar regions kept, extent change</th><th>files</th></tr>";
  std::string pics;
  for (auto l = m.levels.rbegin(); l != m.levels.rend(); ++l) {
    std::string files = "<a href=\"" + html_escape(to_out + l->ply) + "\">ply</a>";
    if (!l->glb.empty()) files += " <a href=\"" + html_escape(to_out + l->glb) + "\">glb</a>";
    s += fmt("<tr><td class=\"n\">%d</td><td class=\"n\">%ld</td><td class=\"n\">%.3f / %.3f m</td><td>%s</td>",
             l->level, l->faces, l->mean_m, l->p95_m, l->closed ? "yes" : "no") +
         "<td class=\"n\">" + (std::isfinite(l->volume) ? fmt("%.1f m&#179;", l->volume) : std::string("&mdash;")) +
         "</td><td class=\"n\">" + planar_kept(*l) + "</td><td>" + files + "</td></tr>";
    if (pictures && !l->picture.empty())
      pics += "<img src=\"" + html_escape(to_out + l->picture) +
              fmt("\" width=\"240\" height=\"173\" loading=\"lazy\" alt=\"level %d\" title=\"level %d, %ld faces\">",
                  l->level, l->level, l->faces);
  }
  s += "</table>";
  if (!pics.empty()) s += "<div class=\"pics\">" + pics + "</div>";
  return s;
}

std::string building_lines(const ParcelResult& r) {
  std::string s;  // concatenated: a note or a problem may be longer than fmt's buffer
  for (const Building& b : r.buildings)
    s += "<p class=\"meta\">" + html_escape(b.id) + ": LoD " + to_string(b.lod) +
         (b.lod_note.empty() ? "" : " (" + html_escape(b.lod_note) + ")") +
         fmt(", volume %.1f m&#179;, eave %.2f m, ridge %.2f m, %d storey(s), solid ", b.volume,
             b.eave_height, b.ridge_height, b.storeys) +
         (b.solid_valid ? std::string("closed") : "open: " + html_escape(b.solid_problem)) +
         "; roof deviation RMSE " + deviation(b.roof_deviation) + ", wall " + deviation(b.wall_deviation) +
         refinement_text(b.refinement) + "</p>";
  return s;
}

// Per element type over the parcel: count, area ± sigma, amount. What a printed
// page shows of a building of many elements.
std::string type_table(const ParcelResult& r, const ParcelValuation* v) {
  std::map<std::string, std::pair<int, double>> amount;  // type -> (elements, amount)
  if (v)
    for (const auto& c : v->items)
      if (c.element_index >= 0) ++amount[c.element_type].first, amount[c.element_type].second += c.amount;
  std::map<ElementType, int> count;
  for (const Building& b : r.buildings)
    for (const Element& e : b.elements) ++count[e.type];
  auto totals = type_totals(r);
  std::string s = "<table><tr><th>Element type</th><th>Elements</th><th>Area m&#178;</th><th>Amount</th></tr>";
  for (ElementType t : kTypes) {
    if (!count[t]) continue;
    auto a = amount.find(to_string(t));
    s += fmt("<tr><td><span style=\"color:%s\">&#9632;</span> %s</td><td class=\"n\">%d</td><td class=\"n\">",
             colour(t), label(t), count[t]) + pm(totals[t].area, totals[t].sigma) + "</td><td class=\"n\">" +
         (a == amount.end() ? std::string() : money(a->second.second)) + "</td></tr>";
  }
  return s + "</table>";
}

std::string status_heading(const Parcel& p, const ParcelResult& r) {
  return html_escape(p.id) + " &mdash; " + html_escape(p.right_type) +
         fmt(" &mdash; <span class=\"%s\">%s</span>", to_string(r.status), to_string(r.status));
}

std::string page_meta(const BatchModel& m, const ReportInfo& info) {
  return "<p class=\"meta\">" + html_escape(info.title) +
         (info.source.empty() ? "" : ", " + html_escape(info.source)) + ". Areas in m&#178; in " +
         html_escape(areas_crs_text(m.crs_wkt)) + ".</p>";
}

// Where the parcel lies: the mean of its outline's vertices, in the areas' CRS.
std::string location(const Parcel& p) {
  Vec2 sum = Vec2::Zero();
  size_t n = 0;
  for (const Polygon2& poly : p.shape)
    for (const Vec2& v : poly.outer) sum += v, ++n;
  if (n == 0) return "";
  sum /= double(n);
  return fmt("<p class=\"meta\">Location: E %.2f, N %.2f%s</p>", sum.x(), sum.y(),
             std::isfinite(p.official_area) ? fmt("; certified area %.1f m&#178;", p.official_area).c_str() : "");
}

std::string link(const std::string& href, const std::string& text) {
  return "<a href=\"" + href + "\">" + text + "</a>";
}

std::string group_nav(size_t from, size_t total) {
  std::string s = "<nav>" + link("../report.html", "&uarr; Summary");
  if (from > 0) s += link(group_page(from - kParcelsPerPage), "&larr; Previous page");
  if (from + kParcelsPerPage < total)
    s += link(group_page(from + kParcelsPerPage), "Next page &rarr;");
  return s + "</nav>";
}

}  // namespace

std::string report_detail::group_html(const BatchModel& m, const std::vector<ParcelValuation>& vals,
                                      const ReportInfo& info, size_t from, size_t total) {
  const size_t to = std::min(total, from + kParcelsPerPage);
  auto vmap = by_parcel(vals);
  std::string s = page_head(info.title + fmt(": parcels %zu-%zu", from + 1, to)) + group_nav(from, total);
  s += fmt("<h1>Parcels %zu&ndash;%zu of %zu</h1>", from + 1, to, total) + page_meta(m, info);
  s += parcel_table_head() + parcel_rows(m, vals, from, to, "") + "</table>";
  s += "<p class=\"meta\">* computed area (no certified area in the parcel layer). &plusmn; values "
       "are 1&sigma; from the plane fits.</p><h2>Buildings and elements</h2>" + legend_svg();
  for (size_t i = from; i < to; ++i) {
    const Parcel& p = m.parcels[i];
    s += fmt("<div class=\"parcel\" id=\"p%zu\">", i) + parcel_svg(p, m.results[i], m.frame) +
         "<div><h3>" + link(parcel_page(p), "Parcel " + status_heading(p, m.results[i])) + "</h3>" +
         parcel_detail(p, m.results[i], find_valuation(vmap, p.id)) + "</div></div>";
  }
  return s + group_nav(from, total) + "</body></html>\n";
}

std::string report_detail::parcel_html(const BatchModel& m, const ParcelValuation* v,
                                       const ReportInfo& info, size_t i, size_t total) {
  const Parcel& p = m.parcels[i];
  const ParcelResult& r = m.results[i];
  std::string s = page_head("Parcel " + p.id) + "<nav>" + link("../../report.html", "&uarr; Summary") +
                  link("../" + group_page(i) + fmt("#p%zu", i),
                       fmt("Parcels %zu&ndash;%zu", i / kParcelsPerPage * kParcelsPerPage + 1,
                           std::min(total, (i / kParcelsPerPage + 1) * kParcelsPerPage)));
  // Neighbours in layer order; a page's own folder holds them (parcel/<id>.html).
  const std::string prefix = "parcel/";
  if (i > 0) s += link(parcel_page(m.parcels[i - 1]).substr(prefix.size()), "&larr; Previous parcel");
  if (i + 1 < total)
    s += link(parcel_page(m.parcels[i + 1]).substr(prefix.size()), "Next parcel &rarr;");
  s += "</nav><h1>Parcel " + status_heading(p, r) + "</h1>" + page_meta(m, info) + location(p);
  if (!info.run_note.empty()) s += "<p class=\"meta\">" + html_escape(info.run_note) + ".</p>";
  if (!r.buildings.empty()) s += parcel_view(p, r, v, m.frame, "../");
  s += "<div class=\"pics\">" + plan_svg(p, r, m.frame, 340, 250) + parcel_svg(p, r, m.frame, 340, 250) +
       "</div>" + legend_svg();
  return s + parcel_detail(p, r, v, true) + "</body></html>\n";
}

std::string report_detail::page_head(const std::string& title) {
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" +
         html_escape(title) + "</title><style>" + kCss + "</style></head><body>";
}

std::string report_detail::parcel_table_head() {
  return "<table><tr><th>Parcel</th><th>Right</th><th>Status</th><th>Land m&#178;</th>"
         "<th>Roof m&#178;</th><th>Wall m&#178;</th><th>Party wall m&#178;</th><th>Ground m&#178;</th>"
         "<th>Outer ceiling m&#178;</th><th>Land value</th><th>Building value</th><th>NJOP</th>"
         "<th>PBB tax</th></tr>";
}

std::string report_detail::parcel_rows(const BatchModel& m, const std::vector<ParcelValuation>& vals,
                                       size_t from, size_t to, const std::string& link_prefix) {
  auto vmap = by_parcel(vals);
  std::string s;
  for (size_t i = from; i < to; ++i) {
    const Parcel& p = m.parcels[i];
    const ParcelResult& r = m.results[i];
    auto tt = type_totals(r);
    const ParcelValuation* v = find_valuation(vmap, p.id);
    s += "<tr><td>" + link(link_prefix + parcel_page(p), html_escape(p.id)) + "</td><td>" +
         html_escape(p.right_type) +
         fmt("</td><td class=\"%s\">%s</td>", to_string(r.status), to_string(r.status));
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
  return s;
}

std::string report_detail::parcel_detail(const Parcel& p, const ParcelResult& r,
                                         const ParcelValuation* v, bool printed) {
  std::string s;
  if (!r.reason.empty()) s += "<p>" + html_escape(r.reason) + "</p>";
  if (!p.repair_note.empty()) s += "<p class=\"meta\">Parcel shape: " + html_escape(p.repair_note) + "</p>";
  s += building_lines(r);
  for (const Building& b : r.buildings) s += mesh_lines(b, printed ? "../../" : "../", printed);
  size_t elements = 0;
  for (const Building& b : r.buildings) elements += b.elements.size();
  if (printed && elements > kPrintedElements)  // too many rows for one sheet: totals by type in print
    s += type_table(r, v) +
         fmt("<p class=\"print-only meta\">The %zu elements one by one: this page on screen, its "
             "detail page and report.csv.</p>", elements) +
         "<div class=\"screen-only\">" + element_table(r, v) + "</div>";
  else if (elements > 0)
    s += element_table(r, v);
  if (v) s += valuation_lines(*v);
  return s;
}

std::vector<ReportFile> report_files(const BatchModel& m, const std::vector<ParcelValuation>& vals,
                                     const ReportInfo& info) {
  std::vector<ReportFile> files;
  files.push_back({"report.html", report_html(m, vals, info)});
  for (size_t from = 0; from < m.parcels.size(); from += kParcelsPerPage)
    files.push_back({"report/" + group_page(from), group_html(m, vals, info, from, m.parcels.size())});
  auto vmap = by_parcel(vals);
  for (size_t i = 0; i < m.parcels.size(); ++i)
    files.push_back({"report/" + parcel_page(m.parcels[i]),
                     parcel_html(m, find_valuation(vmap, m.parcels[i].id), info, i, m.parcels.size())});
  files.push_back({"report.csv", report_csv(m, vals)});
  return files;
}

}  // namespace c3d
