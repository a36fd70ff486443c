#pragma once
// The columns the store writes into each of its tables, in one list per
// table (internal to cadastre/store/): the INSERT is made from the list and
// the SELECT that reads the row back names the same columns, so rows are
// read by name and a column added to a table is added in one place.
#include <map>
#include <string>
#include <vector>

#include "cadastre/store/sql_db.h"

namespace c3d::store_columns {

struct Column {
  const char* name;
  // What a store written before the column existed reads as (SQL); nullptr:
  // every store has it.
  const char* before = nullptr;
};

struct Table {
  const char* name;
  std::vector<Column> columns;
};

// "INSERT INTO t (c, ...) VALUES (?, ...)". `fixed` gives some columns a SQL
// value instead of a `?`; the binds follow the list without those.
std::string insert_sql(const Table& t, const std::map<std::string, std::string>& fixed = {});

// The same, replacing the row whose `key` is taken (every other column).
std::string upsert_sql(const Table& t, const std::string& key, const std::map<std::string, std::string>& fixed = {});

// "UPDATE t SET c=?, ... WHERE fid=?": the binds follow the list, then the fid.
std::string update_sql(const Table& t);

// "a.c AS c, ..." for a SELECT over the table under alias `a` (none: no
// prefix): `fid` and every column, or only the columns named in `only` (of
// the list: a join names each column once). A column this store lacks reads
// as its `before`.
std::string select_list(const sql::Db& db, const Table& t, const std::string& alias = "",
                        const std::vector<std::string>& only = {});

inline const Table kBaunit{"la_baunit", {{"parcel_id"}, {"name"}, {"baunit_type"}}};

inline const Table kRrr{"la_rrr",
                        {{"baunit_id"}, {"party_id"}, {"rrr_class"}, {"rrr_type"}, {"share"}, {"local_type", "NULL"}}};

inline const Table kSpatialUnit{
    "la_spatialunit",
    {{"geom"}, {"baunit_id"}, {"parcel_id"}, {"layer_index"}, {"official_area"}, {"computed_area"}, {"repair_note"}}};

// A store from before LoDs were recorded holds LoD 2.2 models only.
inline const Table kBuilding{"building",
                             {{"geom"},
                              {"spatialunit_id"},
                              {"building_id"},
                              {"building_index"},
                              {"geom_kind"},
                              {"volume"},
                              {"eave_height"},
                              {"ridge_height"},
                              {"terrain_z"},
                              {"storeys"},
                              {"solid_valid"},
                              {"solid_problem"},
                              {"lod", "'2.2'"},
                              {"lod_note", "''"},
                              {"roof_area"},
                              {"roof_plan_area"},
                              {"wall_area"},
                              {"party_wall_area"},
                              {"ground_area"},
                              {"outer_ceiling_area"},
                              {"roof_dev_n"},
                              {"roof_dev_max"},
                              {"roof_dev_mean"},
                              {"roof_dev_std"},
                              {"roof_dev_rmse"},
                              {"wall_dev_n"},
                              {"wall_dev_max"},
                              {"wall_dev_mean"},
                              {"wall_dev_std"},
                              {"wall_dev_rmse"},
                              {"exact_shape", "''"},
                              {"refine_triangles", "NULL"},
                              {"refine_snapped_share", "NULL"},
                              {"refine_chamfer_before", "NULL"},
                              {"refine_chamfer_after", "NULL"},
                              {"refine_cloud_before", "NULL"},
                              {"refine_cloud_after", "NULL"}}};

// Written by store_lods after the building row (an UPDATE of its fid).
inline const Table kBuildingAttributes{"building",
                                       {{"roof_type", "NULL"},
                                        {"roof_z_min", "NULL"},
                                        {"roof_z_50p", "NULL"},
                                        {"roof_z_70p", "NULL"},
                                        {"roof_z_max", "NULL"},
                                        {"roof_points", "NULL"},
                                        {"point_density", "NULL"},
                                        {"roof_rmse", "NULL"},
                                        {"data_quality", "NULL"}}};

inline const Table kElement{"building_element",
                            {{"geom"},
                             {"building_fid"},
                             {"element_index"},
                             {"element_type"},
                             {"area"},
                             {"plan_area"},
                             {"slope_deg"},
                             {"azimuth_deg"},
                             {"sigma_area"},
                             {"support_points"},
                             {"rmse"},
                             {"wall_evidence"},
                             {"sigma_shared", "0"}}};

inline const Table kBuildingLod{
    "building_lod", {{"geom"}, {"building_fid"}, {"lod"}, {"face_types"}, {"volume"}, {"roof_rmse"}}};

inline const Table kBuildingMesh{"building_mesh",
                                 {{"building_fid"},
                                  {"building_id"},
                                  {"method"},
                                  {"points"},
                                  {"spacing"},
                                  {"model_volume"},
                                  {"hull_volume"},
                                  {"volume_diff"},
                                  {"model_roof_area"},
                                  {"hull_roof_area"},
                                  {"roof_area_diff"},
                                  {"flag"},
                                  {"problem"}}};

inline const Table kBuildingMeshLevel{"building_mesh_level",
                                      {{"building_fid"},
                                       {"level"},
                                       {"faces"},
                                       {"vertices"},
                                       {"seconds"},
                                       {"c2m_mean"},
                                       {"c2m_std"},
                                       {"c2m_p95"},
                                       {"c2m_max"},
                                       {"mesh_to_cloud"},
                                       {"far_share"},
                                       {"closed"},
                                       {"manifold"},
                                       {"volume"},
                                       {"roof_area"},
                                       {"planar_regions", "0"},
                                       {"planar_lost", "0"},
                                       {"extent_change", "NULL"},
                                       {"thickness", "NULL"},
                                       {"ply"},
                                       {"ply_sha256"},
                                       {"glb"},
                                       {"glb_sha256"},
                                       {"picture"},
                                       {"picture_sha256"}}};

inline const Table kValuationUnit{
    "vm_valuationunit",
    {{"baunit_id"}, {"spatialunit_id"}, {"parcel_id"}, {"zone"}, {"quality"}, {"land_area"}, {"land_area_source"}}};

inline const Table kValuation{"vm_valuation",
                              {{"valuationunit_id"},
                               {"run_id"},
                               {"approach"},
                               {"currency"},
                               {"land_price_per_m2"},
                               {"land_value"},
                               {"building_cost"},
                               {"sigma_building_cost"},
                               {"age_years"},
                               {"depreciation_share"},
                               {"depreciation"},
                               {"building_value"},
                               {"sigma_building_value"},
                               {"njop"},
                               {"sigma_njop"},
                               {"tax_rate"},
                               {"njoptkp"},
                               {"taxable"},
                               {"tax"},
                               {"sigma_tax"},
                               {"note"},
                               {"valued"}}};

inline const Table kCostItem{"vm_cost_item",
                             {{"valuation_id"},
                              {"element_fid"},
                              {"building_id"},
                              {"element_index"},
                              {"element_type"},
                              {"quality"},
                              {"area"},
                              {"sigma_area"},
                              {"unit_cost"},
                              {"amount"},
                              {"sigma_amount"},
                              {"support_points"},
                              {"rmse"}}};

inline const Table kJob{"parcel_job",
                        {{"parcel_id"},
                         {"layer_index"},
                         {"status"},
                         {"reason"},
                         {"inputs_key"},
                         {"run_id"},
                         {"roof_points"},
                         {"wall_points"},
                         {"timings"},
                         {"updated"}}};

inline const Table kRun{"run",
                        {{"tool_version"},
                         {"parameters"},
                         {"crs_epsg"},
                         {"origin_x"},
                         {"origin_y"},
                         {"origin_z"},
                         {"shard", "NULL"},
                         {"started"},
                         {"finished"},
                         {"parcels_ok"},
                         {"parcels_empty"},
                         {"parcels_failed"},
                         {"parcels_suspect", "0"}}};

// A store from before roles has none: merge judges those by the file's name.
inline const Table kRunInput{"run_input", {{"run_id"}, {"path"}, {"sha256"}, {"bytes"}, {"role", "NULL"}}};

}  // namespace c3d::store_columns
