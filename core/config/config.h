#pragma once
// The run configuration: one TOML file (config/cadastre3d.toml is the documented
// default). core/config.cpp is the only place that parses it; every stage gets
// its own plain section struct.
#include <map>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

struct ParcelFields {
  std::string id;             // empty: use the feature id
  bool id_required = true;    // false: a layer without the id field uses feature ids (a warning says so)
  std::string right_type = "TIPEHAK";
  std::string official_area = "LUASTERTUL";
};

struct ClipParams {
  double overhang_buffer_m = 1.6;  // points this far outside a parcel are still clipped to it
};

struct ReconstructionParams {
  int outlier_neighbours = 12;             // statistical outlier removal
  double outlier_std = 2.5;
  double roof_cluster_m = 0.0;             // individual roofs: gap that separates them (0: 4 x spacing, >= 0.5)
  double component_smoothness_deg = 8.0;   // region growing, planar components
  double component_curvature = 0.05;
  int min_component_points = 30;
  double min_component_area_m2 = 2.0;
  double plane_inlier_m = 0.15;            // robust plane fit
  double loose_point_reach_m = 2.0;        // roof points no plane took still widen the outline this far
                                           // from the planes' points (textured strips along eaves)
  double partition_cell_m = 0.0;           // labelling grid of the roof partition (0: point spacing, 0.05..0.15)
  double default_overhang_m = 0.5;         // when no wall is seen at all
  double storey_height_m = 3.0;
  double shared_roof_depth_m = 0.5;        // a roof reaching this far past the overhang buffer into a
                                           // neighbour is shared by attached houses: split at the boundary
  bool optimize = false;                   // refine with the primitive-constrained optimizer
  std::string optimize_device = "auto";    // auto | cpu | vulkan
};

// Per-parcel valuation facts the parcel layer does not carry (config
// [valuation.parcels."<id>"]); empty / NaN fields fall back to the defaults.
struct ParcelValuationOverride {
  std::string zone;
  std::string quality;
  double age_years = kNaN;
};

struct ValuationParams {
  std::string currency = "IDR";
  std::map<std::string, double> unit_cost;   // element type name -> cost per m2
  double depreciation_per_year = 0.0;        // share per year of age
  double max_depreciation = 0.0;
  double building_age_years = 0.0;
  std::string default_zone;
  std::map<std::string, double> land_price;  // zone -> price per m2
  double tax_rate = 0.0;                     // PBB: tax = rate * (NJOP - NJOPTKP)
  double tax_exemption = 0.0;                // NJOPTKP
  double gross_floor_cost_per_m2 = 0.0;      // optional, 0 = element costs only
  // Quality classes multiply the element unit costs (e.g. permanent 1.0).
  std::map<std::string, double> quality_factor;
  std::string default_quality;               // empty: factor 1
  std::map<std::string, ParcelValuationOverride> parcels;  // parcel id -> override
};

struct Config {
  std::string source;  // file it came from, or "(defaults)"
  ClassMapping classes;
  ParcelFields fields;
  ClipParams clip;
  ReconstructionParams reconstruction;
  ValuationParams valuation;
};

// Reads and checks a config file; throws InputError naming the file and key.
Config load_config(const std::string& path);
// The built-in defaults (same values as config/cadastre3d.toml).
Config default_config();

// The batch's parcel fields, with the id field named on a command line (then
// required) instead of the default's: so `evaluate` and `clip` name parcels
// as the batch did (Cimahi's NIB), and match the OBJ groups it wrote.
ParcelFields parcel_fields(const std::string& id_field);

}  // namespace c3d
