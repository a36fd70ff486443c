#include "core/synthetic/sample_summary.h"

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

}  // namespace c3d
