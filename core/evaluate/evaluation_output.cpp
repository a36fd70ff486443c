#include "core/evaluate/evaluation_output.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <fstream>

#include "core/error.h"

namespace c3d {

const char* const kRoofCoverKeys[3] = {"on_model", "off_model", "uncovered"};
const char* const kWallCoverKeys[4] = {"on_wall", "under_own_roof", "under_other_roof", "under_no_roof"};

namespace {

nlohmann::json to_json(const char* const* keys, const std::vector<Deviation>& parts) {
  nlohmann::json j;
  for (size_t k = 0; k < parts.size(); ++k) j[keys[k]] = to_json(parts[k]);
  return j;
}

nlohmann::json zone_json(const ZoneSummary& z) {
  return {{"id", z.id},
          {"roof", to_json(z.roof)},
          {"roof_vertical", to_json(z.roof_vertical)},
          {"roof_cover", to_json(kRoofCoverKeys, z.roof_cover.parts())},
          {"wall", to_json(z.wall)},
          {"wall_cover", to_json(kWallCoverKeys, z.wall_cover.parts())},
          {"roof_faces", z.roof_faces},
          {"wall_faces", z.wall_faces},
          {"unmodelled_roof_points", z.unmodelled_roof},
          {"unmodelled_wall_points", z.unmodelled_wall}};
}

// printf onto the end of a string (any length: parcel ids may be long).
void appendf(std::string& out, const char* format, ...) {
  va_list args, again;
  va_start(args, format);
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  if (n > 0) {
    const size_t at = out.size();
    out.resize(at + size_t(n) + 1);
    std::vsnprintf(&out[at], size_t(n) + 1, format, again);
    out.resize(at + size_t(n));
  }
  va_end(again);
}

// "a roof within 0.3 m": the printed name of the part on the model, from the
// same constant the split uses.
std::string within_on_model(const char* surface) {
  std::string s;
  appendf(s, "a %s within %.1f m", surface, kOnModelM);
  return s;
}

// Where a pooled deviation comes from: each part's points and share of the
// squared distance.
void append_parts(std::string& out, const char* title, const std::vector<std::string>& labels,
                  const std::vector<Deviation>& parts) {
  double total = 0;
  for (const Deviation& d : parts) total += double(d.n) * d.rmse * d.rmse;
  appendf(out, "%s (share of the squared distance):\n", title);
  for (size_t k = 0; k < parts.size(); ++k) {
    const Deviation& d = parts[k];
    const double share = total > 0 ? 100.0 * double(d.n) * d.rmse * d.rmse / total : 0.0;
    appendf(out, "  %-24s %8ld  rmse %6.3f  %5.1f %%\n", labels[k].c_str(), d.n, d.rmse, share);
  }
}

std::string columns(const Deviation& d) {
  std::string s;
  if (d.n == 0) appendf(s, "%8s %7s %7s %7s %7s", "0", "-", "-", "-", "-");
  else appendf(s, "%8ld %7.3f %7.3f %7.3f %7.3f", d.n, d.mean, d.std, d.rmse, d.max);
  return s;
}

void append_row(std::string& out, const ZoneSummary& z) {
  std::string vertical;
  if (z.roof_vertical.n) appendf(vertical, "%8.3f", z.roof_vertical.rmse);
  else appendf(vertical, "%8s", "-");
  appendf(out, "%-22s %s %s  %s\n", z.id.c_str(), columns(z.roof).c_str(), vertical.c_str(),
          columns(z.wall).c_str());
}

void write_rows(std::ofstream& out, const ZoneMeasure& z, bool roof) {
  const SurfaceMeasure& m = roof ? z.roof : z.wall;
  char buf[160];
  for (size_t i = 0; i < m.points.size(); ++i) {
    const Vec3& p = m.points[i];
    const double d = m.distance[i], v = roof ? z.roof_vertical[i] : kNaN;
    std::snprintf(buf, sizeof buf, ",%s,%.3f,%.3f,%.3f,%.4f,", roof ? "roof" : "wall", p.x(), p.y(), p.z(), d);
    out << z.id << buf;
    if (std::isfinite(v)) {
      std::snprintf(buf, sizeof buf, "%.4f", v);
      out << buf;
    }
    out << "," << (roof ? kRoofCoverKeys[roof_cover_part(v)]
                        : kWallCoverKeys[wall_cover_part(d, z.own_roof[i], z.other_roof[i])])
        << "\n";
  }
}

}  // namespace

nlohmann::json to_json(const Deviation& d) {
  return {{"n", d.n}, {"mean", d.mean}, {"std", d.std}, {"rmse", d.rmse}, {"max", d.max}};
}

nlohmann::json evaluation_json(const ModelEvaluation& evaluation, const EvaluationSummary& summary) {
  const ZoneSummary& p = summary.pooled;
  nlohmann::json j = {{"pooled",
                       {{"roof", to_json(p.roof)},
                        {"roof_vertical", to_json(p.roof_vertical)},
                        {"roof_cover", to_json(kRoofCoverKeys, p.roof_cover.parts())},
                        {"wall", to_json(p.wall)},
                        {"wall_cover", to_json(kWallCoverKeys, p.wall_cover.parts())}}},
                      {"points_outside_parcels", evaluation.points_outside},
                      {"faces_outside_parcels", evaluation.faces_outside}};
  if (evaluation.per_parcel) {
    j["parcels"] = nlohmann::json::array();
    for (const ZoneSummary& z : summary.zones) j["parcels"].push_back(zone_json(z));
  }
  return j;
}

std::string evaluation_table(const ModelEvaluation& e, const EvaluationSummary& s) {
  std::string out;
  appendf(out, "%-22s %8s %7s %7s %7s %7s %8s  %8s %7s %7s %7s %7s\n", "parcel", "roof n", "mean", "std", "rmse",
          "max", "vert rms", "wall n", "mean", "std", "rmse", "max");
  if (e.per_parcel)
    for (const ZoneSummary& z : s.zones) append_row(out, z);
  append_row(out, s.pooled);
  append_parts(out, "roof points by what the model has above or below them",
               {within_on_model("roof"), "a roof further off", "no roof"}, s.pooled.roof_cover.parts());
  append_parts(out, "wall points by where they stand",
               {within_on_model("wall"), "under the parcel's roof", "under another's roof", "under no roof"},
               s.pooled.wall_cover.parts());
  appendf(out,
          "roof points %zu, wall points %zu; in parcels without a model: %ld roof, %ld wall; "
          "outside every parcel: %ld; model faces outside every parcel: %ld\n",
          e.roof_points, e.wall_points, s.pooled.unmodelled_roof, s.pooled.unmodelled_wall, e.points_outside,
          e.faces_outside);
  out += "distances in m: mean/std/rmse/max of |d|; vert rms = vertical distance RMSE\n";
  return out;
}

void write_residuals_csv(const std::string& path, const std::vector<ZoneMeasure>& zones) {
  std::ofstream out(path);
  out << "parcel,kind,x,y,z,distance_m,vertical_m,part\n";
  for (const auto& z : zones) {
    write_rows(out, z, true);
    write_rows(out, z, false);
  }
  if (!out) throw InputError(path, "cannot write");
}

}  // namespace c3d
