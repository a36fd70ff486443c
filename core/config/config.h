#pragma once
// The run configuration: one TOML file. Every stage gets its own plain section
// struct; the member initializers below are the built-in defaults (the one place
// a default is written). core/config/parameters.cpp declares each file key once
// (type, unit, doc, range, stage) and that table drives the parser, the
// documented default file config/cadastre3d.toml, the run record and the resume key.
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

// Each field's doc, unit and range: core/config/parameters.cpp (file key in brackets
// where it differs from the member's name).

struct ParcelFields {
  std::string id;           // empty: use the feature id
  bool id_required = true;  // false: a layer without the id field uses feature ids (a warning
                            // says so); not a file key: naming [parcel_fields] id sets it
  std::string right_type = "TIPEHAK";
  std::string official_area = "LUASTERTUL";
};

struct ClipParams {
  double overhang_buffer_m = 1.6;
};

// How the batch goes through the data; changes no result (left out of the resume key).
struct BatchParams {
  int chunk_parcels = 250;
  int chunk_points = 1500000;
};

struct ReconstructionParams {
  int outlier_neighbours = 12;
  double outlier_std = 2.5;
  double roof_cluster_m = 0.0;  // 0: from the point spacing
  double component_smoothness_deg = 8.0;
  double component_curvature = 0.05;
  int min_component_points = 30;
  double min_component_area_m2 = 2.0;
  double plane_inlier_m = 0.15;
  double loose_point_reach_m = 2.0;
  double partition_cell_m = 0.0;  // 0: from the point spacing
  double default_overhang_m = 0.5;
  double storey_height_m = 3.0;
  double shared_roof_depth_m = 0.5;
  bool optimize = false;
  bool refine_curved = true;  // snap curved buildings' dense meshes onto their exact surfaces
  std::string optimize_device = "auto";  // auto, cpu or vulkan
};

// Per-parcel valuation facts the parcel layer does not carry (config
// [valuation.parcels."<id>"]); empty / NaN fields fall back to the defaults.
struct ParcelValuationOverride {
  std::string zone;
  std::string quality;
  double age_years = kNaN;
};

// The defaults are Cimahi's (IDR, 2024 cost level); a config file must give
// every fiscal figure itself (see the table's required keys).
struct ValuationParams {
  std::string currency = "IDR";
  std::map<std::string, double> unit_cost = {  // element type name -> cost per m2
      {"roof", 550000},   {"wall", 400000},          {"party_wall", 200000},
      {"ground", 350000}, {"outer_ceiling", 175000}};
  double depreciation_per_year = 0.015;  // share per year of age
  double max_depreciation = 0.5;
  double building_age_years = 10;
  std::string default_zone = "ZNT-B";
  std::map<std::string, double> land_price = {  // zone -> price per m2
      {"ZNT-A", 6500000}, {"ZNT-B", 4000000}, {"ZNT-C", 2500000}};
  double tax_rate = 0.001;          // [tax] rate; PBB: tax = rate * (NJOP - NJOPTKP)
  double tax_exemption = 10000000;  // [tax] njoptkp
  double gross_floor_cost_per_m2 = 0.0;  // 0 = element costs only
  // Quality classes multiply the element unit costs (e.g. permanent 1.0).
  std::map<std::string, double> quality_factor = {
      {"permanent", 1.0}, {"semi_permanent", 0.75}, {"temporary", 0.5}};
  std::string default_quality = "permanent";  // empty: factor 1
  std::map<std::string, ParcelValuationOverride> parcels;  // [parcels] parcel id -> override
};

// batch --mesh (docs/meshes.md): each modelled building's points meshed at four levels.
struct MeshParams {
  bool ladder = false;
  std::string method = "front";  // the dense method: front, pivot, poisson or alpha
  std::string simplify = "boundary";  // levels 3 and 2: boundary, or qem, garland, clustering to compare
};

struct Config {
  std::string source = "(defaults)";  // file it came from; not part of the settings
  ClassMapping classes;  // defaults in core/types.h
  // [parcel_fields]: the Cimahi BPN schema; without a config file a layer
  // lacking NIB falls back to feature ids.
  ParcelFields fields{"NIB", false};
  ClipParams clip;
  ReconstructionParams reconstruction;
  ValuationParams valuation;
  BatchParams batch;
  MeshParams mesh;
};

// Reads and checks a config file; throws InputError naming the file and the
// dotted key. A file is read on top of the defaults; unknown keys are errors.
Config load_config(const std::string& path);
// The built-in defaults (config/cadastre3d.toml is their documented text).
Config default_config();

// The config as a documented TOML file: every key with its doc, unit, range and
// stage as comments. default_config_toml() is config/cadastre3d.toml, verbatim.
std::string config_toml(const Config& c);
std::string default_config_toml();

// Every setting of the table (class mapping, parcel fields, valuation maps and
// per-parcel overrides included) as nested JSON with sorted keys, numbers as
// numbers, without the file path: what the run record stores.
nlohmann::json effective_config_json(const Config& c);
// SHA-256 hex of effective_config_json's compact dump: equal settings, equal
// fingerprint, whatever file (or comments) they came from. Part of the resume key.
std::string config_fingerprint(const Config& c);

// The batch's parcel fields, with the id field named on a command line (then
// required) instead of the default's: so `evaluate` and `clip` name parcels
// as the batch did (Cimahi's NIB), and match the OBJ groups it wrote.
ParcelFields parcel_fields(const std::string& id_field);

}  // namespace c3d
