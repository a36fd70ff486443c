#include "ifc_citygml/attributes.h"

#include <cctype>
#include <cmath>

namespace c3d::exp {

std::string camel_case(const std::string& snake) {
  std::string out;
  bool up = false;
  for (char c : snake) {
    if (c == '_') { up = true; continue; }
    out += up ? char(std::toupper(static_cast<unsigned char>(c))) : c;
    up = false;
  }
  return out;
}

std::string rmse_name(Lod lod) {
  std::string digits;
  for (const char* c = to_string(lod); *c; ++c)
    if (std::isdigit(static_cast<unsigned char>(*c))) digits += *c;
  return "rmse_lod" + digits;
}

QualityAttributes quality_attributes(const Building& b, const LocalFrame& frame) {
  QualityAttributes q;
  const BuildingAttributes& a = b.attributes;
  const double z0 = frame.origin.z();
  auto number = [&](const std::string& name, double v) {
    if (std::isfinite(v)) q.numbers.emplace_back(name, v);
  };
  if (!a.roof_type.empty()) q.texts.emplace_back("roof_type", a.roof_type);
  number("roof_height_min", a.roof_z_min + z0);
  number("roof_height_50p", a.roof_z_50p + z0);
  number("roof_height_70p", a.roof_z_70p + z0);
  number("roof_height_max", a.roof_z_max + z0);
  number("ground_height", b.terrain_z + z0);
  if (b.roof_deviation.n > 0) number(rmse_name(b.lod), b.roof_deviation.rmse);
  for (const auto& l : b.lower_lods) number(rmse_name(l.lod), l.roof_rmse);
  number("point_density", a.point_density);
  if (a.roof_points > 0 || !a.roof_type.empty()) q.counts.emplace_back("roof_points", a.roof_points);
  if (!a.data_quality.empty()) q.texts.emplace_back("data_quality", a.data_quality);
  return q;
}

}  // namespace c3d::exp
