#include "core/evaluate/evaluation_output.h"

#include <cmath>
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
