#include "core/synthetic/sample_summary.h"

#include <sstream>

namespace c3d {

BatchModel truth_model(const SampleTown& town) {
  BatchModel model;
  model.frame = town.frame;
  model.crs_wkt = town.crs_wkt;
  model.epsg = town.epsg;
  model.parcels = town.parcels;
  for (size_t i = 0; i < town.parcels.size(); ++i) {
    ParcelResult r;
    r.parcel_index = int(i);
    r.parcel_id = town.parcels[i].id;
    r.status = town.truth[i].empty() ? ParcelStatus::Empty : ParcelStatus::Ok;
    for (const auto& tb : town.truth[i]) r.buildings.push_back(tb.model);
    model.results.push_back(std::move(r));
  }
  return model;
}

SampleTownCounts count_town(const SampleTown& town) {
  SampleTownCounts n;
  for (size_t i = 0; i < town.parcels.size(); ++i) {
    ++n.layouts[to_string(town.layouts[i])];
    n.buildings += int(town.truth[i].size());
  }
  for (auto c : town.cloud.classes) (c == 6 ? n.roof_points : c == 64 ? n.wall_points : n.other_points)++;
  return n;
}

std::string sample_town_text(const SampleTown& town, const SampleFiles& files, const std::string& truth_obj_dir) {
  const SampleTownCounts n = count_town(town);
  std::ostringstream out;
  out << "sample town, seed " << town.seed << ", EPSG:" << town.epsg << "\n"
      << "  parcels   " << files.parcels << "  (" << town.parcels.size() << " parcels, " << n.buildings
      << " buildings)\n"
      << "  dtm       " << files.dtm << "  (" << town.dtm.nx << " x " << town.dtm.ny << " cells of 1 m, "
      << int(town.dtm.nodata_share * 1000) / 10.0 << " % NoData)\n";
  if (!files.cloud.empty())
    out << "  cloud     " << files.cloud << "  (" << town.cloud.points.size() << " points: " << n.roof_points
        << " roof, " << n.wall_points << " wall, " << n.other_points << " ground"
        << (files.cloud_tiles.empty() ? "" : "; " + std::to_string(files.cloud_tiles.size()) + " tiles") << ")\n";
  out << "  truth     " << files.truth << ", " << truth_obj_dir << "/<parcel>.obj\n  layouts  ";
  for (const auto& [layout, count] : n.layouts) out << " " << layout << " " << count;
  out << "\n";
  return out.str();
}

}  // namespace c3d
