#pragma once
// A model evaluation written out: the JSON record and the residuals CSV (one
// row per measured point).
#include <string>

#include <nlohmann/json.hpp>

#include "core/evaluate/zones.h"

namespace c3d {

// The names of RoofCover's and WallCover's parts, in parts() order.
extern const char* const kRoofCoverKeys[3];  // on_model, off_model, uncovered
extern const char* const kWallCoverKeys[4];  // on_wall, under_own_roof, under_other_roof, under_no_roof

nlohmann::json to_json(const Deviation& d);  // n, mean, std, rmse, max
// "pooled", "points_outside_parcels", "faces_outside_parcels", and per parcel
// ("parcels", one object per zone) when the evaluation is per parcel.
nlohmann::json evaluation_json(const ModelEvaluation& evaluation, const EvaluationSummary& summary);

// The printed report: one row per zone (when per parcel) and the pooled row,
// where the pooled squared distance comes from, and the point counts.
std::string evaluation_table(const ModelEvaluation& evaluation, const EvaluationSummary& summary);

// One row per measured point, so a disputed deviation can be looked at point by
// point (QGIS reads the CSV as a point layer by its x/y columns):
// parcel,kind,x,y,z,distance_m,vertical_m,part. Throws InputError when the file
// cannot be written.
void write_residuals_csv(const std::string& path, const std::vector<ZoneMeasure>& zones);

}  // namespace c3d
