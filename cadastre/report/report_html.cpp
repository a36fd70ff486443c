// The report's summary page (OUT/report.html): status cards, the totals table,
// the overview map, the charts, the parcels without a valued model and the
// index of the detail pages.
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

// Sums over the parcels of one status (or all): what the totals table prints.
struct Totals {
  int parcels = 0, buildings = 0, unvalued = 0;
  std::map<ElementType, TypeTotal> areas;
  double land = 0, building = 0, njop = 0, sigma_njop = 0, tax = 0, sigma_tax = 0;

  void add(const ParcelResult& r, const ParcelValuation* v) {
    ++parcels;
    buildings += int(r.buildings.size());
    for (const auto& [t, x] : type_totals(r)) {
      areas[t].area += x.area;
      areas[t].sigma = std::hypot(areas[t].sigma, x.sigma);
    }
    if (!valued(v)) {  // money left out (NULL): implausible even as land only
      ++unvalued;
      return;
    }
    land += v->land_value;
    building += v->building_value;
    njop += v->njop;
    tax += v->tax;
    sigma_njop = std::hypot(sigma_njop, v->sigma_njop);
    sigma_tax = std::hypot(sigma_tax, v->sigma_tax);
  }
};

const ParcelStatus kStatuses[] = {ParcelStatus::Ok, ParcelStatus::Empty, ParcelStatus::Suspect,
                                  ParcelStatus::Failed};

const char* status_label(ParcelStatus s) {
  switch (s) {
    case ParcelStatus::Ok: return "Modelled";
    case ParcelStatus::Empty: return "Empty (no building)";
    case ParcelStatus::Suspect: return "Suspect (land only)";
    case ParcelStatus::Failed: return "Failed (land only)";
  }
  return "?";
}

// One row of the totals table; cells carry data-key so a test can find them.
std::string totals_row(const std::string& head, const char* cls, const Totals& t) {
  auto cell = [](const char* key, const std::string& text) {
    return fmt("<td class=\"n\" data-key=\"%s\">", key) + text + "</td>";
  };
  std::string s = fmt("<tr class=\"%s\"><th>", cls) + head + "</th>";
  s += cell("parcels", std::to_string(t.parcels)) + cell("buildings", std::to_string(t.buildings));
  for (ElementType e : kTypes) {
    auto it = t.areas.find(e);
    const TypeTotal x = it == t.areas.end() ? TypeTotal{} : it->second;
    s += cell(to_string(e), fmt("%.2f<br><span class=\"sig\">&plusmn; %.2f</span>", x.area, x.sigma));
  }
  s += cell("land_value", money(t.land)) + cell("building_value", money(t.building));
  s += cell("njop", money(t.njop) + "<br><span class=\"sig\">&plusmn; " + money(t.sigma_njop) + "</span>");
  s += cell("tax", money(t.tax) + "<br><span class=\"sig\">&plusmn; " + money(t.sigma_tax) + "</span>");
  s += cell("unvalued", std::to_string(t.unvalued));
  return s + "</tr>";
}

std::string totals_table(const BatchModel& m, const std::vector<ParcelValuation>& vals) {
  auto vmap = by_parcel(vals);
  std::map<ParcelStatus, Totals> by_status;
  Totals all;
  for (const ParcelResult& r : m.results) {
    const ParcelValuation* v = find_valuation(vmap, r.parcel_id);
    by_status[r.status].add(r, v);
    all.add(r, v);
  }
  std::string currency = vals.empty() ? "" : html_escape(vals.front().currency);
  std::string s = "<table class=\"totals\"><tr><th>Status</th><th>Parcels</th><th>Buildings</th>";
  for (ElementType e : kTypes) s += std::string("<th>") + label(e) + " m&#178;</th>";
  s += "<th>Land value " + currency + "</th><th>Building value " + currency + "</th><th>NJOP " +
       currency + "</th><th>PBB tax " + currency + "</th><th>Not valued</th></tr>";
  for (ParcelStatus st : kStatuses)
    s += totals_row(fmt("<span class=\"%s\">%s</span>", to_string(st), status_label(st)),
                    (std::string("status-") + to_string(st)).c_str(), by_status[st]);
  s += totals_row("Total", "total", all);
  return s + "</table><p class=\"meta\">Areas are sums of element areas; &plusmn; is 1&sigma;, "
             "combined in quadrature over buildings and parcels. Money totals leave out parcels "
             "not valued (no finite NJOP or tax).</p>";
}

std::string status_cards(const BatchModel& m, const std::vector<ParcelValuation>& vals) {
  std::map<ParcelStatus, int> n;
  for (const auto& r : m.results) ++n[r.status];
  auto vmap = by_parcel(vals);
  int unvalued = 0;
  for (const auto& p : m.parcels) unvalued += !valued(find_valuation(vmap, p.id));
  std::string s = "<div class=\"cards\">";
  s += fmt("<div class=\"card\">Parcels<b>%zu</b></div>", m.parcels.size());
  s += fmt("<div class=\"card ok\">Modelled<b>%d</b></div><div class=\"card empty\">Empty<b>%d</b>"
           "</div><div class=\"card failed\">Failed<b>%d</b></div><div class=\"card suspect\">Suspect<b>%d</b></div>",
           n[ParcelStatus::Ok], n[ParcelStatus::Empty], n[ParcelStatus::Failed], n[ParcelStatus::Suspect]);
  if (unvalued) s += fmt("<div class=\"card failed\">Not valued<b>%d</b></div>", unvalued);
  return s + "</div>";
}

std::string problem_table(const BatchModel& m) {
  std::string rows;
  for (size_t i = 0; i < m.results.size(); ++i) {
    const ParcelResult& r = m.results[i];
    if (r.status == ParcelStatus::Ok || r.status == ParcelStatus::Empty) continue;
    rows += "<tr><td><a href=\"report/" + parcel_page(m.parcels[i]) + "\">" +
            html_escape(r.parcel_id) + "</a></td>" +
            fmt("<td class=\"%s\">%s</td><td>", to_string(r.status), to_string(r.status)) +
            html_escape(r.reason) + "</td></tr>";
  }
  if (rows.empty()) return "";
  return "<h2>Parcels without a valued model</h2><p>Failed and suspect parcels are valued as land "
         "only until an officer reviews them (docs/plausibility.md).</p><table><tr><th>Parcel</th>"
         "<th>Status</th><th>Reason</th></tr>" + rows + "</table>";
}

// One line per detail page: its parcels (first and last id) and their statuses.
std::string page_index(const BatchModel& m) {
  std::string s = "<table class=\"index\"><tr><th>Page</th><th>Parcels</th><th>First id</th>"
                  "<th>Last id</th><th>Modelled</th><th>Empty</th><th>Suspect</th><th>Failed</th></tr>";
  for (size_t from = 0; from < m.parcels.size(); from += kParcelsPerPage) {
    size_t to = std::min(m.parcels.size(), from + kParcelsPerPage);
    std::map<ParcelStatus, int> n;
    for (size_t i = from; i < to; ++i) ++n[m.results[i].status];
    s += "<tr><td><a href=\"report/" + group_page(from) + "\">" + group_page(from) + "</a></td>" +
         fmt("<td class=\"n\">%zu&ndash;%zu</td>", from + 1, to) + "<td>" +
         html_escape(m.parcels[from].id) + "</td><td>" + html_escape(m.parcels[to - 1].id) +
         fmt("</td><td class=\"n\">%d</td><td class=\"n\">%d</td><td class=\"n\">%d</td>"
             "<td class=\"n\">%d</td></tr>",
             n[ParcelStatus::Ok], n[ParcelStatus::Empty], n[ParcelStatus::Suspect],
             n[ParcelStatus::Failed]);
  }
  return s + "</table>";
}

}  // namespace

std::string report_html(const BatchModel& m, const std::vector<ParcelValuation>& vals,
                        const ReportInfo& info) {
  std::string s = page_head(info.title);
  s += "<h1>" + html_escape(info.title) + "</h1><p class=\"meta\">";
  if (!info.source.empty()) s += "Source: " + html_escape(info.source) + ". ";
  if (!info.run_note.empty()) s += html_escape(info.run_note) + ". ";
  s += "Areas in m&#178; in " + html_escape(areas_crs_text(m.crs_wkt)) + ", values in " +
       html_escape(vals.empty() ? "" : vals.front().currency) + ".</p>";
  s += "<h2>Summary</h2>" + status_cards(m, vals) + totals_table(m, vals);
  s += "<h2>3D view</h2>" + summary_view();
  s += "<h2>Overview map</h2>" + overview_map(m, vals, "report/");
  s += "<h2>Charts</h2><div class=\"charts\"><div><h3>Area by element type (all parcels)</h3>" +
       area_chart(m) + "</div><div><h3>Value per parcel (NJOP)</h3>" + value_chart(m, vals) +
       "</div></div>";
  s += problem_table(m);
  s += fmt("<h2>Parcel pages</h2><p>%zu parcels, %zu per page; each parcel also has a printable "
           "A4 page (linked from its page and from the map).</p>",
           m.parcels.size(), kParcelsPerPage) + page_index(m);
  s += "<p class=\"meta\">Cost approach: building = &Sigma; element area &times; unit cost &times; "
       "quality factor, less depreciation by age; land = parcel area &times; zone land price; "
       "NJOP = land + building; PBB = rate &times; max(0, NJOP &minus; NJOPTKP). Each amount "
       "carries &plusmn;1&sigma; = unit cost &times; &sigma; of its area; totals combine in "
       "quadrature.</p></body></html>\n";
  return s;
}

}  // namespace c3d
