#include "cadastre/store/schema.h"

#include <cpl_conv.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <regex>

#include "cadastre/store/gpkg_geometry.h"
#include "cadastre/store/gpkg_rtree.h"
#include "cadastre/store/styles.h"
#include "core/error.h"

namespace c3d::store_schema {

namespace {

constexpr int kCustomSrsId = 100000;

const char* kWgs84Wkt =
    "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563,"
    "AUTHORITY[\"EPSG\",\"7030\"]],AUTHORITY[\"EPSG\",\"6326\"]],PRIMEM[\"Greenwich\",0,"
    "AUTHORITY[\"EPSG\",\"8901\"]],UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\","
    "\"9122\"]],AXIS[\"Latitude\",NORTH],AXIS[\"Longitude\",EAST],AUTHORITY[\"EPSG\",\"4326\"]]";

// GeoPackage core tables, exactly as GDAL creates them (validate_gpkg.py
// compares column types, defaults and keys).
const char* kGpkgSchema = R"SQL(
CREATE TABLE IF NOT EXISTS gpkg_spatial_ref_sys (srs_name TEXT NOT NULL, srs_id INTEGER NOT NULL PRIMARY KEY,
  organization TEXT NOT NULL, organization_coordsys_id INTEGER NOT NULL, definition TEXT NOT NULL, description TEXT);
CREATE TABLE IF NOT EXISTS gpkg_contents (table_name TEXT NOT NULL PRIMARY KEY, data_type TEXT NOT NULL,
  identifier TEXT UNIQUE, description TEXT DEFAULT '',
  last_change DATETIME NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ','now')),
  min_x DOUBLE, min_y DOUBLE, max_x DOUBLE, max_y DOUBLE, srs_id INTEGER,
  CONSTRAINT fk_gc_r_srs_id FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys(srs_id));
CREATE TABLE IF NOT EXISTS gpkg_geometry_columns (table_name TEXT NOT NULL, column_name TEXT NOT NULL,
  geometry_type_name TEXT NOT NULL, srs_id INTEGER NOT NULL, z TINYINT NOT NULL, m TINYINT NOT NULL,
  CONSTRAINT pk_geom_cols PRIMARY KEY (table_name, column_name),
  CONSTRAINT uk_gc_table_name UNIQUE (table_name),
  CONSTRAINT fk_gc_tn FOREIGN KEY (table_name) REFERENCES gpkg_contents(table_name),
  CONSTRAINT fk_gc_srs FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys (srs_id));
CREATE TABLE IF NOT EXISTS gpkg_extensions (table_name TEXT, column_name TEXT, extension_name TEXT NOT NULL,
  definition TEXT NOT NULL, scope TEXT NOT NULL,
  CONSTRAINT ge_tce UNIQUE (table_name, column_name, extension_name));
)SQL";

// LADM / valuation tables. Only GeoPackage column types; every child key has
// an index so the cascading delete of a parcel stays cheap.
const char* kLadmSchema = R"SQL(
CREATE TABLE IF NOT EXISTS run (fid INTEGER PRIMARY KEY, tool_version TEXT NOT NULL, parameters TEXT,
  crs_epsg INTEGER, origin_x DOUBLE, origin_y DOUBLE, origin_z DOUBLE,
  started DATETIME NOT NULL, finished DATETIME,
  parcels_ok INTEGER, parcels_empty INTEGER, parcels_failed INTEGER);
CREATE TABLE IF NOT EXISTS run_input (fid INTEGER PRIMARY KEY,
  run_id INTEGER NOT NULL REFERENCES run(fid) ON DELETE CASCADE,
  path TEXT NOT NULL, sha256 TEXT NOT NULL, bytes INTEGER, role TEXT);
CREATE TABLE IF NOT EXISTS la_party (fid INTEGER PRIMARY KEY, party_key TEXT NOT NULL UNIQUE,
  name TEXT, party_type TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS la_baunit (fid INTEGER PRIMARY KEY, parcel_id TEXT NOT NULL UNIQUE,
  name TEXT, baunit_type TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS la_spatialunit (fid INTEGER PRIMARY KEY, geom MULTIPOLYGON,
  baunit_id INTEGER NOT NULL REFERENCES la_baunit(fid) ON DELETE CASCADE,
  parcel_id TEXT NOT NULL UNIQUE, layer_index INTEGER, official_area DOUBLE, computed_area DOUBLE,
  repair_note TEXT);
CREATE TABLE IF NOT EXISTS building (fid INTEGER PRIMARY KEY, geom MULTIPOLYGON,
  spatialunit_id INTEGER NOT NULL REFERENCES la_spatialunit(fid) ON DELETE CASCADE,
  building_id TEXT NOT NULL UNIQUE, building_index INTEGER NOT NULL, geom_kind TEXT,
  volume DOUBLE, eave_height DOUBLE, ridge_height DOUBLE, terrain_z DOUBLE, storeys INTEGER,
  solid_valid BOOLEAN, solid_problem TEXT, lod TEXT, lod_note TEXT,
  roof_area DOUBLE, roof_plan_area DOUBLE, wall_area DOUBLE, party_wall_area DOUBLE,
  ground_area DOUBLE, outer_ceiling_area DOUBLE,
  roof_dev_n INTEGER, roof_dev_max DOUBLE, roof_dev_mean DOUBLE, roof_dev_std DOUBLE, roof_dev_rmse DOUBLE,
  wall_dev_n INTEGER, wall_dev_max DOUBLE, wall_dev_mean DOUBLE, wall_dev_std DOUBLE, wall_dev_rmse DOUBLE,
  exact_shape TEXT, refine_triangles INTEGER, refine_snapped_share DOUBLE, refine_chamfer_before DOUBLE,
  refine_chamfer_after DOUBLE, refine_cloud_before DOUBLE, refine_cloud_after DOUBLE);
CREATE TABLE IF NOT EXISTS building_element (fid INTEGER PRIMARY KEY, geom MULTIPOLYGON,
  building_fid INTEGER NOT NULL REFERENCES building(fid) ON DELETE CASCADE,
  element_index INTEGER NOT NULL,
  element_type TEXT NOT NULL CHECK (element_type IN ('roof','wall','party_wall','ground','outer_ceiling')),
  area DOUBLE, plan_area DOUBLE, slope_deg DOUBLE, azimuth_deg DOUBLE, sigma_area DOUBLE,
  support_points INTEGER, rmse DOUBLE, wall_evidence TEXT, sigma_shared DOUBLE,
  UNIQUE (building_fid, element_index));
CREATE TABLE IF NOT EXISTS building_lod (fid INTEGER PRIMARY KEY, geom MULTIPOLYGON,
  building_fid INTEGER NOT NULL REFERENCES building(fid) ON DELETE CASCADE,
  lod TEXT NOT NULL, face_types TEXT NOT NULL, volume DOUBLE, roof_rmse DOUBLE,
  UNIQUE (building_fid, lod));
CREATE TABLE IF NOT EXISTS building_mesh (fid INTEGER PRIMARY KEY,
  building_fid INTEGER NOT NULL UNIQUE REFERENCES building(fid) ON DELETE CASCADE,
  building_id TEXT NOT NULL, method TEXT, points INTEGER, spacing DOUBLE,
  model_volume DOUBLE, hull_volume DOUBLE, volume_diff DOUBLE,
  model_roof_area DOUBLE, hull_roof_area DOUBLE, roof_area_diff DOUBLE, flag TEXT, problem TEXT);
CREATE TABLE IF NOT EXISTS building_mesh_level (fid INTEGER PRIMARY KEY,
  building_fid INTEGER NOT NULL REFERENCES building(fid) ON DELETE CASCADE,
  level INTEGER NOT NULL, faces INTEGER, vertices INTEGER, seconds DOUBLE,
  c2m_mean DOUBLE, c2m_std DOUBLE, c2m_p95 DOUBLE, c2m_max DOUBLE, mesh_to_cloud DOUBLE, far_share DOUBLE,
  closed INTEGER, manifold INTEGER, volume DOUBLE, roof_area DOUBLE,
  planar_regions INTEGER, planar_lost INTEGER, extent_change DOUBLE, thickness DOUBLE,
  ply TEXT, ply_sha256 TEXT, glb TEXT, glb_sha256 TEXT, picture TEXT, picture_sha256 TEXT,
  UNIQUE (building_fid, level));
CREATE TABLE IF NOT EXISTS vm_valuationunit (fid INTEGER PRIMARY KEY,
  baunit_id INTEGER NOT NULL REFERENCES la_baunit(fid) ON DELETE CASCADE,
  spatialunit_id INTEGER NOT NULL REFERENCES la_spatialunit(fid) ON DELETE CASCADE,
  parcel_id TEXT NOT NULL UNIQUE, zone TEXT, quality TEXT, land_area DOUBLE, land_area_source TEXT);
CREATE TABLE IF NOT EXISTS vm_valuation (fid INTEGER PRIMARY KEY,
  valuationunit_id INTEGER NOT NULL REFERENCES vm_valuationunit(fid) ON DELETE CASCADE,
  run_id INTEGER REFERENCES run(fid), approach TEXT NOT NULL, currency TEXT NOT NULL,
  land_price_per_m2 DOUBLE, land_value DOUBLE, building_cost DOUBLE, sigma_building_cost DOUBLE,
  age_years DOUBLE, depreciation_share DOUBLE, depreciation DOUBLE, building_value DOUBLE,
  sigma_building_value DOUBLE, njop DOUBLE, sigma_njop DOUBLE, tax_rate DOUBLE, njoptkp DOUBLE,
  taxable DOUBLE, tax DOUBLE, sigma_tax DOUBLE, note TEXT, valued DATETIME);
CREATE TABLE IF NOT EXISTS vm_cost_item (fid INTEGER PRIMARY KEY,
  valuation_id INTEGER NOT NULL REFERENCES vm_valuation(fid) ON DELETE CASCADE,
  element_fid INTEGER REFERENCES building_element(fid) ON DELETE CASCADE,
  building_id TEXT, element_index INTEGER, element_type TEXT NOT NULL, quality TEXT,
  area DOUBLE, sigma_area DOUBLE, unit_cost DOUBLE, amount DOUBLE, sigma_amount DOUBLE,
  support_points INTEGER, rmse DOUBLE);
CREATE INDEX IF NOT EXISTS ix_run_input_run ON run_input(run_id);
CREATE INDEX IF NOT EXISTS ix_su_baunit ON la_spatialunit(baunit_id);
CREATE INDEX IF NOT EXISTS ix_building_su ON building(spatialunit_id);
CREATE INDEX IF NOT EXISTS ix_vu_baunit ON vm_valuationunit(baunit_id);
CREATE INDEX IF NOT EXISTS ix_vu_su ON vm_valuationunit(spatialunit_id);
CREATE INDEX IF NOT EXISTS ix_val_vu ON vm_valuation(valuationunit_id);
CREATE INDEX IF NOT EXISTS ix_val_run ON vm_valuation(run_id);
CREATE INDEX IF NOT EXISTS ix_ci_val ON vm_cost_item(valuation_id);
CREATE INDEX IF NOT EXISTS ix_ci_element ON vm_cost_item(element_fid);
)SQL";

// LA_RRR by itself: stores written before it used the code lists get it
// rebuilt (migrate_rrr). party_id may be NULL: ISO 19152 lets a right have
// no party (LA_RRR - LA_Party is 0..1), which is what a parcel layer without
// owners gives; rrr_type is an LA_RightType value, local_type the layer's name.
// The GIS layers (gis.h): 2D, each row hanging on its 3D source row.
const char* kGisSchema = R"SQL(
CREATE TABLE IF NOT EXISTS parcel (fid INTEGER PRIMARY KEY, geom MULTIPOLYGON,
  spatialunit_id INTEGER NOT NULL REFERENCES la_spatialunit(fid) ON DELETE CASCADE,
  parcel_id TEXT NOT NULL UNIQUE, layer_index INTEGER, status TEXT, reason TEXT,
  right_type TEXT, ladm_right_type TEXT, official_area DOUBLE, computed_area DOUBLE, repair_note TEXT,
  buildings INTEGER, roof_area DOUBLE, wall_area DOUBLE, ground_area DOUBLE, volume DOUBLE,
  zone TEXT, quality TEXT, land_area DOUBLE, land_area_source TEXT, land_price_per_m2 DOUBLE,
  land_value DOUBLE, building_cost DOUBLE, building_value DOUBLE, sigma_building_value DOUBLE,
  njop DOUBLE, sigma_njop DOUBLE, njop_per_m2 DOUBLE, taxable DOUBLE, tax DOUBLE, sigma_tax DOUBLE,
  currency TEXT, valuation_note TEXT);
CREATE TABLE IF NOT EXISTS building_footprint (fid INTEGER PRIMARY KEY, geom MULTIPOLYGON,
  building_fid INTEGER NOT NULL REFERENCES building(fid) ON DELETE CASCADE,
  building_id TEXT NOT NULL UNIQUE, parcel_id TEXT NOT NULL, lod TEXT, lod_note TEXT,
  roof_type TEXT, data_quality TEXT, footprint_area DOUBLE, volume DOUBLE,
  eave_height DOUBLE, ridge_height DOUBLE, ground_z DOUBLE, roof_z_min DOUBLE, roof_z_50p DOUBLE,
  roof_z_70p DOUBLE, roof_z_max DOUBLE, storeys INTEGER, roof_points INTEGER, point_density DOUBLE,
  roof_rmse DOUBLE, wall_rmse DOUBLE, solid_valid BOOLEAN, roof_planes INTEGER,
  roof_area DOUBLE, sigma_roof_area DOUBLE, roof_plan_area DOUBLE, wall_area DOUBLE,
  sigma_wall_area DOUBLE, party_wall_area DOUBLE, sigma_party_wall_area DOUBLE, ground_area DOUBLE,
  sigma_ground_area DOUBLE, outer_ceiling_area DOUBLE, sigma_outer_ceiling_area DOUBLE,
  building_cost DOUBLE, parcel_njop DOUBLE, parcel_tax DOUBLE, currency TEXT);
CREATE TABLE IF NOT EXISTS roof_part (fid INTEGER PRIMARY KEY, geom MULTIPOLYGON,
  element_fid INTEGER NOT NULL REFERENCES building_element(fid) ON DELETE CASCADE,
  building_id TEXT NOT NULL, parcel_id TEXT NOT NULL, element_index INTEGER NOT NULL,
  area DOUBLE, plan_area DOUBLE, sigma_area DOUBLE, slope_deg DOUBLE, azimuth_deg DOUBLE,
  support_points INTEGER, rmse DOUBLE, plan_note TEXT);
CREATE INDEX IF NOT EXISTS ix_parcel_su ON parcel(spatialunit_id);
CREATE INDEX IF NOT EXISTS ix_footprint_building ON building_footprint(building_fid);
CREATE INDEX IF NOT EXISTS ix_roof_part_element ON roof_part(element_fid);
)SQL";

const char* kRrrColumns = R"SQL( (fid INTEGER PRIMARY KEY,
  baunit_id INTEGER NOT NULL REFERENCES la_baunit(fid) ON DELETE CASCADE,
  party_id INTEGER REFERENCES la_party(fid) ON DELETE CASCADE,
  rrr_class TEXT NOT NULL CHECK (rrr_class IN ('right','restriction','responsibility')),
  rrr_type TEXT, share DOUBLE, local_type TEXT))SQL";

// Indonesian land rights (UUPA 5/1960) by their LA_RightType (ISO 19152 Annex
// J); names already in the code list pass as they are. docs/design.md.
const std::pair<const char*, const char*> kRightTypes[] = {
    {"hak milik", "ownership"},          {"hak guna bangunan", "superficies"},
    {"hak guna usaha", "lease"},         {"hak pakai", "usufruct"},
    {"hak sewa untuk bangunan", "lease"}, {"hak sewa", "lease"},
};
const char* const kLaRightTypes[] = {"agriActivity", "commonOwnership", "customaryType", "fishing",
                                     "grazing", "informalOccupation", "lease", "occupation", "ownership",
                                     "ownershipAssumed", "superficies", "tenancy", "usufruct",
                                     "waterrights"};

// The same mapping in SQL, for rows written before (CASE over lower(x)).
std::string right_type_sql(const std::string& x) {
  std::string sql = "CASE lower(trim(" + x + "))";
  for (const auto& [local, code] : kRightTypes) sql += std::string(" WHEN '") + local + "' THEN '" + code + "'";
  for (const char* code : kLaRightTypes) sql += std::string(" WHEN lower('") + code + "') THEN '" + code + "'";
  return sql + " END";
}

void create_rrr(sql::Db& db) {
  bool old = false;
  {
    sql::Stmt q(db, "SELECT sql FROM sqlite_master WHERE type='table' AND name='la_rrr'");
    old = q.step() && q.get_text(0).find("local_type") == std::string::npos;
  }
  if (old) {
    db.exec(std::string("CREATE TABLE la_rrr_v2") + kRrrColumns + ";"
            "INSERT INTO la_rrr_v2 (fid, baunit_id, party_id, rrr_class, rrr_type, share, local_type) "
            "SELECT fid, baunit_id, party_id, rrr_class, " + right_type_sql("rrr_type") + ", share, rrr_type "
            "FROM la_rrr; DROP TABLE la_rrr; ALTER TABLE la_rrr_v2 RENAME TO la_rrr;"
            // 'unknown' is no LA_PartyType: the placeholder owners go, their rights stay without a party.
            "UPDATE la_rrr SET party_id = NULL WHERE party_id IN "
            "(SELECT fid FROM la_party WHERE party_type = 'unknown');"
            "DELETE FROM la_party WHERE party_type = 'unknown';");
  }
  db.exec(std::string("CREATE TABLE IF NOT EXISTS la_rrr") + kRrrColumns + ";"
          "CREATE INDEX IF NOT EXISTS ix_rrr_baunit ON la_rrr(baunit_id);"
          "CREATE INDEX IF NOT EXISTS ix_rrr_party ON la_rrr(party_id);");
}

// The job table by itself: stores written before `suspect` existed get it
// rebuilt with the wider status check (migrate_parcel_job).
const char* kParcelJobColumns = R"SQL( (fid INTEGER PRIMARY KEY, parcel_id TEXT NOT NULL UNIQUE,
  layer_index INTEGER,
  status TEXT NOT NULL CHECK (status IN ('pending','ok','empty','failed','suspect')),
  reason TEXT, inputs_key TEXT, run_id INTEGER REFERENCES run(fid),
  roof_points INTEGER, wall_points INTEGER, timings TEXT, updated DATETIME))SQL";

void create_parcel_job(sql::Db& db) {
  bool old_check = false;
  {
    sql::Stmt q(db, "SELECT sql FROM sqlite_master WHERE type='table' AND name='parcel_job'");
    old_check = q.step() && q.get_text(0).find("'suspect'") == std::string::npos;
  }
  if (old_check) {
    db.exec(std::string("CREATE TABLE parcel_job_v2") + kParcelJobColumns + ";"
            "INSERT INTO parcel_job_v2 SELECT * FROM parcel_job; DROP TABLE parcel_job;"
            "ALTER TABLE parcel_job_v2 RENAME TO parcel_job;");
  }
  db.exec(std::string("CREATE TABLE IF NOT EXISTS parcel_job") + kParcelJobColumns +
          "; CREATE INDEX IF NOT EXISTS ix_job_run ON parcel_job(run_id);");
}

// Columns added to a table after stores were written with it: a store
// written before gets them on opening, so its later parcels record them too.
struct AddedColumn {
  const char* table;
  const char* column;
  const char* type;
};
const AddedColumn kAddedColumns[] = {
    {"building", "lod", "TEXT"},
    {"building", "lod_note", "TEXT"},
    {"building_element", "sigma_shared", "DOUBLE"},
    {"run", "parcels_suspect", "INTEGER"},
    {"run", "shard", "TEXT"},  // "K/N" of a shard's run (docs/scale.md)
    {"run_input", "role", "TEXT"},  // cloud, walls, parcels, dtm, classifier (cadastre/batch/batch.h)
    // 3DBAG-style attributes (docs/design.md, "Building attributes"); heights world z.
    {"building", "roof_type", "TEXT"},
    {"building", "roof_z_min", "DOUBLE"},
    {"building", "roof_z_50p", "DOUBLE"},
    {"building", "roof_z_70p", "DOUBLE"},
    {"building", "roof_z_max", "DOUBLE"},
    {"building", "roof_points", "INTEGER"},
    {"building", "point_density", "DOUBLE"},
    {"building", "roof_rmse", "DOUBLE"},
    {"building", "data_quality", "TEXT"},
    {"building", "exact_shape", "TEXT"},  // a curved building's exact surfaces, JSON (docs/store.md)
    // What the optimizer did to a curved building's dense mesh (docs/geopackage.md).
    {"building", "refine_triangles", "INTEGER"},
    {"building", "refine_snapped_share", "DOUBLE"},
    {"building", "refine_chamfer_before", "DOUBLE"},
    {"building", "refine_chamfer_after", "DOUBLE"},
    {"building", "refine_cloud_before", "DOUBLE"},
    {"building", "refine_cloud_after", "DOUBLE"},
    // Level 4's planar regions at each mesh level (docs/meshes.md).
    {"building_mesh_level", "planar_regions", "INTEGER"},
    {"building_mesh_level", "planar_lost", "INTEGER"},
    {"building_mesh_level", "extent_change", "DOUBLE"},
    {"building_mesh_level", "thickness", "DOUBLE"},
};

struct Layer {
  const char* table;
  const char* description;
  bool features;
  int z;  // gpkg_geometry_columns.z
};

const Layer kLayers[] = {
    {"parcel", "Parcels with their valuation (NJOP, tax) and the parcel layer's own fields (2D, for GIS)", true, 0},
    {"building_footprint", "Buildings for GIS: valid 2D footprint, parcel id, areas and sigma, volume, heights, "
     "LoD, roof type, value", true, 0},
    {"roof_part", "Roof elements for GIS: valid 2D plan, 3D area, slope, azimuth, sigma", true, 0},
    {"la_spatialunit", "LADM spatial units: cadastral parcels", true, 0},
    {"building", "3D buildings: LoD 2.2, or an LoD 1.3 / 1.2 model where 2.2 is not valid (closed solid, or "
     "footprint when none); for 3D use, building_footprint for GIS", true, 1},
    {"building_element", "3D building elements: roof, wall, party wall, ground, outer ceiling; for 3D use, "
     "roof_part for GIS", true, 1},
    {"building_lod", "Lower LoDs of each building: LoD 1.2 prism, LoD 1.3 layers (closed shells)", true, 1},
    {"building_mesh", "batch --mesh: each building's mesh ladder and its element model checked against the "
     "closed hull (flag)", false, 0},
    {"building_mesh_level", "batch --mesh: each mesh level's figures and files (relative to the output folder) "
     "with their SHA-256", false, 0},
    {"la_party", "LADM parties", false, 0},
    {"la_baunit", "LADM basic administrative units", false, 0},
    {"la_rrr", "LADM rights, restrictions, responsibilities", false, 0},
    {"vm_valuationunit", "Valuation units (one per parcel)", false, 0},
    {"vm_valuation", "Valuations: cost approach, NJOP, PBB tax", false, 0},
    {"vm_cost_item", "Priced quantities behind each valuation", false, 0},
    {"run", "Batch runs: tool version, parameters, times", false, 0},
    {"run_input", "Input files of each run with SHA-256", false, 0},
    {"parcel_job", "Per-parcel job status (resume, idempotent reruns)", false, 0},
};

// First quoted name of a WKT ("WGS 84 / UTM zone 48S").
std::string wkt_name(const std::string& wkt) {
  auto a = wkt.find('"');
  auto b = a == std::string::npos ? a : wkt.find('"', a + 1);
  return b == std::string::npos ? "unnamed" : wkt.substr(a + 1, b - a - 1);
}

std::string epsg_wkt(int epsg) {
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  std::string out;
  char* wkt = nullptr;
  if (OSRImportFromEPSG(srs, epsg) == OGRERR_NONE && OSRExportToWkt(srs, &wkt) == OGRERR_NONE)
    out = wkt;
  CPLFree(wkt);
  OSRDestroySpatialReference(srs);
  return out;
}

// Registers the standard SRSs and the inputs' CRS; returns the srs_id of the layers.
int register_srs(sql::Db& db, const std::string& crs_wkt, int epsg) {
  int srs = 0;
  sql::Stmt ins(db,
                "INSERT OR IGNORE INTO gpkg_spatial_ref_sys (srs_name, srs_id, organization, "
                "organization_coordsys_id, definition, description) VALUES (?,?,?,?,?,?)");
  ins.bind("Undefined cartesian SRS").bind(-1).bind("NONE").bind(-1).bind("undefined")
      .bind("undefined cartesian coordinate reference system").run();
  ins.bind("Undefined geographic SRS").bind(0).bind("NONE").bind(0).bind("undefined")
      .bind("undefined geographic coordinate reference system").run();
  ins.bind("WGS 84 geodetic").bind(4326).bind("EPSG").bind(4326).bind(kWgs84Wkt)
      .bind("longitude/latitude coordinates in decimal degrees on the WGS 84 spheroid").run();
  if (epsg > 0) {
    srs = epsg;
    std::string wkt = crs_wkt.empty() ? epsg_wkt(epsg) : crs_wkt;
    if (wkt.empty()) wkt = "undefined";
    ins.bind(wkt_name(wkt)).bind(epsg).bind("EPSG").bind(epsg).bind(wkt).bind("inputs' CRS").run();
  } else if (!crs_wkt.empty()) {
    srs = kCustomSrsId;
    ins.bind(wkt_name(crs_wkt)).bind(srs).bind("NONE").bind(srs).bind(crs_wkt)
        .bind("inputs' CRS (no EPSG code)").run();
  } else {
    srs = -1;  // undefined Cartesian: local metric coordinates
  }
  return srs;
}


// --- PostgreSQL + PostGIS: the same tables, their types in PostgreSQL's words.

// Serialises schema creation between the processes writing one database
// (pg_advisory_xact_lock(1, 0); styles take (2, 0), parcels (3, hash of the id)).
constexpr const char* kSchemaLock = "SELECT pg_advisory_xact_lock(1, 0)";

// The PostGIS type of a layer's geometry column.
std::string pg_geometry(const std::string& table, int srid) {
  for (const Layer& l : kLayers)
    if (l.features && table == l.table)
      return std::string("geometry(MultiPolygon") + (l.z ? "Z" : "") + "," + std::to_string(srid) + ")";
  return "geometry";
}

// GeoPackage DDL -> PostgreSQL DDL: bigserial keys, bigint, double precision,
// text times, typed PostGIS geometry columns. One statement at a time, so
// each `geom MULTIPOLYGON` gets its own table's type.
std::string pg_ddl(const std::string& ddl, int srid) {
  static const std::regex key(R"(INTEGER PRIMARY KEY( AUTOINCREMENT)?( NOT NULL)?)"), integer(R"(\bINTEGER\b)"),
      dbl(R"(\bDOUBLE\b)"), datetime(R"(\bDATETIME\b)"), text_n(R"(TEXT\(\d+\))"),
      table(R"(CREATE TABLE IF NOT EXISTS (\w+))");
  std::string out;
  size_t start = 0;
  while (start < ddl.size()) {
    size_t end = ddl.find(';', start);
    if (end == std::string::npos) end = ddl.size();
    std::string s = ddl.substr(start, end - start);
    start = end + 1;
    std::smatch m;
    if (std::regex_search(s, m, table)) {
      const size_t g = s.find("geom MULTIPOLYGON");
      if (g != std::string::npos) s.replace(g, 17, "geom " + pg_geometry(m[1], srid));
    }
    s = std::regex_replace(s, key, "bigserial PRIMARY KEY");
    s = std::regex_replace(s, integer, "bigint");
    s = std::regex_replace(s, dbl, "double precision");
    s = std::regex_replace(s, datetime, "text");
    s = std::regex_replace(s, text_n, "text");
    if (s.find_first_not_of(" \n\t") != std::string::npos) out += s + ";\n";
  }
  return out;
}

// PostGIS in this database (created when missing and allowed).
void require_postgis(sql::Db& db) {
  if (db.has_table("spatial_ref_sys")) return;
  try {
    db.exec("CREATE EXTENSION IF NOT EXISTS postgis");
  } catch (const InputError& e) {
    throw InputError(sql::display_name(db.path()),
                     "PostGIS is not installed in this database and cannot be created (" + std::string(e.what()) +
                         "); run CREATE EXTENSION postgis as its owner");
  }
}

// The SRID of the layers: the EPSG code, a spatial_ref_sys row of our own for
// a CRS without one (srid kCustomSrsId), 0 for undefined Cartesian.
int pg_srid(sql::Db& db, const std::string& crs_wkt, int epsg) {
  const std::string where = sql::display_name(db.path());
  if (epsg > 0) {
    sql::Stmt q(db, "SELECT 1 FROM spatial_ref_sys WHERE srid=?");
    if (!q.bind(epsg).step()) throw InputError(where, "EPSG:" + std::to_string(epsg) + " is not in spatial_ref_sys");
    return epsg;
  }
  if (crs_wkt.empty()) return 0;
  OGRSpatialReferenceH srs = OSRNewSpatialReference(crs_wkt.c_str());
  char* proj4 = nullptr;
  std::string p4;
  if (srs && OSRExportToProj4(srs, &proj4) == OGRERR_NONE && proj4) p4 = proj4;
  CPLFree(proj4);
  OSRDestroySpatialReference(srs);
  sql::Stmt(db, "INSERT INTO spatial_ref_sys (srid, auth_name, auth_srid, srtext, proj4text) "
                "VALUES (?,'cadastre3d',?,?,?) ON CONFLICT (srid) DO NOTHING")
      .bind(kCustomSrsId).bind(kCustomSrsId).bind(crs_wkt).bind(p4).run();
  sql::Stmt q(db, "SELECT srtext FROM spatial_ref_sys WHERE srid=?");
  if (!q.bind(kCustomSrsId).step() || q.get_text(0) != crs_wkt)
    throw InputError(where, "spatial_ref_sys row " + std::to_string(kCustomSrsId) +
                                " holds another custom CRS than the inputs'");
  return kCustomSrsId;
}

// The columns added since a table first came (kAddedColumns) that this store lacks.
void add_missing_columns(sql::Db& db) {
  for (const AddedColumn& c : kAddedColumns)
    if (!has_column(db, c.table, c.column))
      db.exec(std::string("ALTER TABLE ") + c.table + " ADD COLUMN " + c.column + " " + column_type(db, c.type));
}

int create_postgres(sql::Db& db, const std::string& crs_wkt, int epsg) {
  sql::Transaction tx(db);
  db.exec(kSchemaLock);
  require_postgis(db);
  const int srid = pg_srid(db, crs_wkt, epsg);
  {
    sql::Stmt q(db, "SELECT srid FROM geometry_columns WHERE f_table_schema = current_schema() "
                    "AND f_table_name = 'la_spatialunit'");
    if (q.step() && int(q.get_int(0)) != srid)
      throw InputError(sql::display_name(db.path()), "store uses SRID " + std::to_string(q.get_int(0)) +
                                                         " but the inputs have " + std::to_string(srid));
  }
  // The first writer creates everything in this one transaction, layer_styles
  // last; a later writer does no DDL at all: CREATE INDEX / ALTER ... IF NOT
  // EXISTS still lock their tables and would deadlock with writers at work.
  // Only a store from before a column gets it, once, from its first writer since.
  if (db.has_table("layer_styles")) {
    add_missing_columns(db);
    tx.commit();
    return epsg > 0 ? epsg : crs_wkt.empty() ? -1 : kCustomSrsId;
  }
  db.exec(pg_ddl(kLadmSchema, srid));
  db.exec(pg_ddl(std::string("CREATE TABLE IF NOT EXISTS la_rrr") + kRrrColumns +
                     "; CREATE INDEX IF NOT EXISTS ix_rrr_baunit ON la_rrr(baunit_id);"
                     "CREATE INDEX IF NOT EXISTS ix_rrr_party ON la_rrr(party_id);",
                 srid));
  db.exec(pg_ddl(std::string("CREATE TABLE IF NOT EXISTS parcel_job") + kParcelJobColumns +
                     "; CREATE INDEX IF NOT EXISTS ix_job_run ON parcel_job(run_id);",
                 srid));
  db.exec(pg_ddl(kGisSchema, srid));
  add_missing_columns(db);
  for (const Layer& l : kLayers)
    if (l.features)
      db.exec(std::string("CREATE INDEX IF NOT EXISTS ix_") + l.table + "_geom ON " + l.table + " USING gist (geom)");
  store_styles::create(db);
  tx.commit();
  return epsg > 0 ? epsg : crs_wkt.empty() ? -1 : kCustomSrsId;  // the GeoPackage's srs_id numbers
}

}  // namespace

std::string now(const sql::Db& db) {
  return db.postgres() ? "to_char(clock_timestamp() AT TIME ZONE 'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS.MS\"Z\"')"
                       : kNow;
}

std::string column_type(const sql::Db& db, const std::string& gpkg_type) {
  if (!db.postgres()) return gpkg_type;
  if (gpkg_type == "DOUBLE") return "double precision";
  if (gpkg_type == "INTEGER") return "bigint";
  return gpkg_type;
}

int create(sql::Db& db, const std::string& crs_wkt, int epsg) {
  if (db.postgres()) return create_postgres(db, crs_wkt, epsg);
  sql::Transaction tx(db);
  db.exec(kGpkgSchema);
  // An existing store keeps its CRS; mixing CRSs in one file would be silent garbage.
  {
    sql::Stmt q(db, "SELECT srs_id FROM gpkg_geometry_columns WHERE table_name='la_spatialunit'");
    if (q.step()) {
      int existing = int(q.get_int(0));
      int wanted = epsg > 0 ? epsg : crs_wkt.empty() ? -1 : kCustomSrsId;
      if (existing != wanted)
        throw InputError(db.path(), "store uses srs_id " + std::to_string(existing) +
                                        " but the inputs have " + std::to_string(wanted));
    }
  }
  const int srs = register_srs(db, crs_wkt, epsg);
  db.exec(kLadmSchema);
  create_rrr(db);
  create_parcel_job(db);
  db.exec(kGisSchema);
  add_missing_columns(db);
  sql::Stmt contents(db,
                     "INSERT OR IGNORE INTO gpkg_contents (table_name, data_type, identifier, "
                     "description, srs_id) VALUES (?,?,?,?,?)");
  sql::Stmt columns(db,
                    "INSERT OR IGNORE INTO gpkg_geometry_columns (table_name, column_name, "
                    "geometry_type_name, srs_id, z, m) VALUES (?,?,?,?,?,0)");
  for (const Layer& l : kLayers) {
    contents.bind(l.table).bind(l.features ? "features" : "attributes").bind(l.table)
        .bind(l.description);
    if (l.features) contents.bind(srs);
    else contents.bind_null();
    contents.run();
    if (l.features) columns.bind(l.table).bind("geom").bind("MULTIPOLYGON").bind(srs).bind(l.z).run();
    if (l.features) gpkg_rtree::create(db, l.table);
  }
  store_styles::create(db);
  tx.commit();
  return srs;
}

const char* ladm_right_type(const std::string& local) {
  std::string l = local;
  l.erase(0, l.find_first_not_of(" \t"));
  l.erase(l.find_last_not_of(" \t") + 1);
  std::transform(l.begin(), l.end(), l.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (const auto& [name, code] : kRightTypes)
    if (l == name) return code;
  for (const char* code : kLaRightTypes) {
    std::string c = code;
    std::transform(c.begin(), c.end(), c.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    if (l == c) return code;
  }
  return nullptr;
}

bool has_column(const sql::Db& db, const std::string& table, const std::string& column) {
  for (const std::string& c : columns_of(db, table))
    if (c == column) return true;
  return false;
}

std::vector<std::string> columns_of(const sql::Db& db, const std::string& table) {
  // pg_catalog, not information_schema: the readers ask for every parcel.
  sql::Stmt q(db, db.postgres() ? "SELECT attname FROM pg_attribute WHERE attrelid = to_regclass(?) "
                                  "AND attnum > 0 AND NOT attisdropped"
                                : "SELECT name FROM pragma_table_info(?)");
  q.bind(table);
  std::vector<std::string> out;
  while (q.step()) out.push_back(q.get_text(0));
  return out;
}

void update_extents(sql::Db& db) {
  if (db.postgres()) return;  // no gpkg_contents: QGIS asks PostGIS for the extent
  sql::Stmt upd(db, std::string("UPDATE gpkg_contents SET min_x=?, min_y=?, max_x=?, max_y=?, "
                                "last_change=") + kNow + " WHERE table_name=?");
  for (const Layer& l : kLayers) {
    if (!l.features) continue;
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    sql::Stmt q(db, std::string("SELECT geom FROM ") + l.table + " WHERE geom IS NOT NULL");
    while (q.step()) {
      std::size_t n;
      const std::uint8_t* b = q.blob(0, &n);
      double env[4];
      if (!gpkg_envelope_xy(b, n, env)) continue;
      lo[0] = std::min(lo[0], env[0]); lo[1] = std::min(lo[1], env[1]);
      hi[0] = std::max(hi[0], env[2]); hi[1] = std::max(hi[1], env[3]);
    }
    upd.bind(lo[0]).bind(lo[1]).bind(hi[0]).bind(hi[1]).bind(l.table).run();  // inf -> NULL
  }
  db.exec(std::string("UPDATE gpkg_contents SET last_change=") + kNow +
          " WHERE data_type='attributes'");
}

}  // namespace c3d::store_schema
