#pragma once
// The 3DBAG-style building attributes GIS users filter on (roof type, roof
// heights as percentiles, ground height, RMSE per LoD, points and density,
// data quality), as the CityJSON and CityGML writers name them. Heights are
// world z (local + frame origin); values that are NaN (no roof points) are
// left out, never written as null.
#include <string>
#include <utility>
#include <vector>

#include "core/types.h"

namespace c3d::exp {

struct QualityAttributes {
  std::vector<std::pair<std::string, double>> numbers;  // m, m2 or points/m2
  std::vector<std::pair<std::string, long>> counts;
  std::vector<std::pair<std::string, std::string>> texts;
};

// Names in snake_case (CityJSON); camel_case() gives CityGML's.
QualityAttributes quality_attributes(const Building& b, const LocalFrame& frame);
std::string camel_case(const std::string& snake);
// "rmse_lod22" for LoD 2.2.
std::string rmse_name(Lod lod);

}  // namespace c3d::exp
