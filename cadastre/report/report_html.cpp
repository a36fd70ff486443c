// The report's HTML page: summary cards, charts, the parcel table and one
// section per parcel with its picture, elements and valuation.
#include <algorithm>
#include <cmath>
#include <map>

#include "cadastre/report/report.h"
#include "cadastre/report/report_parts.h"
#include "core/io/crs.h"

namespace c3d {

using namespace report_detail;

namespace {

const char* kCss = R"CSS(
body{font-family:"DejaVu Sans",Arial,sans-serif;margin:24px;color:#222;max-width:1200px}
h1{font-size:22px;margin-bottom:4px}h2{font-size:18px;border-bottom:2px solid #a0522d;padding-bottom:3px;margin-top:28px}
h3{font-size:15px;margin:4px 0}
.meta{color:#666;font-size:12px}
.cards{display:flex;gap:12px;flex-wrap:wrap}.card{border:1px solid #ccc;border-radius:6px;padding:8px 14px;min-width:120px}
.card b{display:block;font-size:20px}.ok{color:#2e7d32}.empty{color:#777}.failed{color:#c62828}.suspect{color:#e65100}
table{border-collapse:collapse;font-size:12px;margin:6px 0}th,td{border:1px solid #ccc;padding:3px 6px}
th{background:#f3ede8;text-align:left}td.n{text-align:right;white-space:nowrap}
.charts{display:flex;gap:24px;flex-wrap:wrap}.small{font-size:10px}svg text{font-size:12px;fill:#222}
.parcel{display:flex;gap:16px;border-top:1px solid #ddd;padding:10px 0;break-inside:avoid}
.parcel svg.pic{border:1px solid #ddd;background:#fbfbf8;flex:none}
)CSS";

std::string summary_html(const BatchModel& m, const std::vector<ParcelValuation>& vals) {
  int ok = 0, empty = 0, failed = 0, suspect = 0;
  std::string problems;
  for (size_t i = 0; i < m.results.size(); ++i) {
    const ParcelResult& r = m.results[i];
    ok += r.status == ParcelStatus::Ok;
    empty += r.status == ParcelStatus::Empty;
    failed += r.status == ParcelStatus::Failed;
    suspect += r.status == ParcelStatus::Suspect;
    if (r.status != ParcelStatus::Ok)
      problems += fmt("<tr><td>%s</td><td class=\"%s\">%s</td><td>%s</td></tr>",
                      html_escape(r.parcel_id).c_str(), to_string(r.status), to_string(r.status),
                      html_escape(r.reason).c_str());
  }
  double land = 0, building = 0, njop = 0, tax = 0, s_njop = 0, s_tax = 0;
  std::string currency = vals.empty() ? "" : vals.front().currency;
  int unvalued = 0;  // money left out (NULL): implausible even as land only
  for (const auto& v : vals) {
    if (!std::isfinite(v.njop) || !std::isfinite(v.tax)) {
      ++unvalued;
      continue;
    }
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
           "</div><div class=\"card failed\">Failed<b>%d</b></div><div class=\"card suspect\">Suspect<b>%d</b></div>",
           ok, empty, failed, suspect);
  if (unvalued) s += fmt("<div class=\"card failed\">Not valued<b>%d</b></div>", unvalued);
  s += fmt("<div class=\"card\">Land value (%s)<b>%s</b></div>", currency.c_str(), money(land).c_str());
  s += fmt("<div class=\"card\">Building value (%s)<b>%s</b></div>", currency.c_str(),
           money(building).c_str());
  s += fmt("<div class=\"card\">NJOP total (%s)<b>%s</b>&plusmn; %s</div>", currency.c_str(),
           money(njop).c_str(), money(s_njop).c_str());
  s += fmt("<div class=\"card\">PBB tax (%s)<b>%s</b>&plusmn; %s</div></div>", currency.c_str(),
           money(tax).c_str(), money(s_tax).c_str());
  if (!problems.empty())
    s += "<h3>Parcels without a valued model</h3><p>Failed and suspect parcels are valued as land "
         "only until an officer reviews them (docs/plausibility.md).</p><table><tr><th>Parcel</th>"
         "<th>Status</th><th>Reason</th></tr>" + problems + "</table>";
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
      s += fmt("<p class=\"meta\">%s: LoD %s%s, volume %.1f m&#179;, eave %.2f m, ridge %.2f m, %d storey(s), "
               "solid %s; roof deviation RMSE %.3f m (%ld points), wall %.3f m (%ld points)</p>",
               html_escape(b.id).c_str(), html_escape(b.lod).c_str(),
               b.lod_note.empty() ? "" : (" (" + html_escape(b.lod_note) + ")").c_str(), b.volume,
               b.eave_height, b.ridge_height, b.storeys,
               b.solid_valid ? "closed" : ("open: " + html_escape(b.solid_problem)).c_str(),
               b.roof_deviation.rmse, b.roof_deviation.n, b.wall_deviation.rmse, b.wall_deviation.n);
    if (!r.buildings.empty()) s += element_table(r, v);
    if (v) s += valuation_lines(*v);
    s += "</div></div>";
  }
  return s;
}

}  // namespace

std::string report_html(const BatchModel& m, const std::vector<ParcelValuation>& vals,
                        const ReportInfo& info) {
  std::string s = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" +
                  html_escape(info.title) + "</title><style>" + kCss + "</style></head><body>";
  s += "<h1>" + html_escape(info.title) + "</h1><p class=\"meta\">";
  if (!info.source.empty()) s += "Source: " + html_escape(info.source) + ". ";
  if (!info.run_note.empty()) s += html_escape(info.run_note) + ". ";
  s += "Areas in m&#178; in " + html_escape(areas_crs_text(m.crs_wkt)) + ", values in " + html_escape(vals.empty() ? "" : vals.front().currency) +
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

}  // namespace c3d
