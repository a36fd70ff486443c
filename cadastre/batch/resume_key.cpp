#include "cadastre/batch/resume_key.h"

#include <nlohmann/json.hpp>

#include "cadastre/sha256.h"

namespace c3d {

std::string run_parameters(const Config& cfg) {
  const auto& r = cfg.reconstruction;
  nlohmann::json j = {{"config", cfg.source},
                      {"overhang_buffer_m", cfg.clip.overhang_buffer_m},
                      {"optimize", r.optimize},
                      {"reconstruction",
                       {{"component_smoothness_deg", r.component_smoothness_deg},
                        {"component_curvature", r.component_curvature},
                        {"min_component_points", r.min_component_points},
                        {"min_component_area_m2", r.min_component_area_m2},
                        {"plane_inlier_m", r.plane_inlier_m},
                        {"loose_point_reach_m", r.loose_point_reach_m},
                        {"default_overhang_m", r.default_overhang_m},
                        {"storey_height_m", r.storey_height_m},
                        {"shared_roof_depth_m", r.shared_roof_depth_m},
                        {"roof_cluster_m", r.roof_cluster_m},
                        {"partition_cell_m", r.partition_cell_m}}}};
  return j.dump();
}

std::string run_key(const Config& cfg, const std::vector<std::string>& input_files) {
  std::string s = run_parameters(cfg);
  for (const auto& f : input_files) s += "|" + sha256_file(f);
  return sha256_hex(s);
}

std::string parcel_key(const std::string& run_key, const Parcel& p) {
  std::string s = run_key + "|" + p.id;
  for (const auto& poly : p.shape)
    for (const auto& v : poly.outer) s += "|" + std::to_string(v.x()) + "," + std::to_string(v.y());
  return sha256_hex(s);
}

}  // namespace c3d
