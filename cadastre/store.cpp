#include "cadastre/store.h"

#include <cpl_conv.h>
#include <ogr_srs_api.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "cadastre/gpkg_geometry.h"
#include "cadastre/sqlite_util.h"
#include "core/error.h"
#include "core/geometry/geometry.h"
#include "core/io/sha256.h"

namespace c3d {

namespace {

constexpr int kCustomSrsId = 100000;
constexpr const char* kNow = "strftime('%Y-%m-%dT%H:%M:%fZ','now')";

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
  path TEXT NOT NULL, sha256 TEXT NOT NULL, bytes INTEGER);
CREATE TABLE IF NOT EXISTS la_party (fid INTEGER PRIMARY KEY, party_key TEXT NOT NULL UNIQUE,
  name TEXT, party_type TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS la_baunit (fid INTEGER PRIMARY KEY, parcel_id TEXT NOT NULL UNIQUE,
  name TEXT, baunit_type TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS la_rrr (fid INTEGER PRIMARY KEY,
  baunit_id INTEGER NOT NULL REFERENCES la_baunit(fid) ON DELETE CASCADE,
  party_id INTEGER NOT NULL REFERENCES la_party(fid) ON DELETE CASCADE,
  rrr_class TEXT NOT NULL CHECK (rrr_class IN ('right','restriction','responsibility')),
  rrr_type TEXT, share DOUBLE);
CREATE TABLE IF NOT EXISTS la_spatialunit (fid INTEGER PRIMARY KEY, geom MULTIPOLYGON,
  baunit_id INTEGER NOT NULL REFERENCES la_baunit(fid) ON DELETE CASCADE,
  parcel_id TEXT NOT NULL UNIQUE, layer_index INTEGER, official_area DOUBLE, computed_area DOUBLE,
  repair_note TEXT);
CREATE TABLE IF NOT EXISTS building (fid INTEGER PRIMARY KEY, geom MULTIPOLYGON,
  spatialunit_id INTEGER NOT NULL REFERENCES la_spatialunit(fid) ON DELETE CASCADE,
  building_id TEXT NOT NULL UNIQUE, building_index INTEGER NOT NULL, geom_kind TEXT,
  volume DOUBLE, eave_height DOUBLE, ridge_height DOUBLE, terrain_z DOUBLE, storeys INTEGER,
  solid_valid BOOLEAN, solid_problem TEXT,
  roof_area DOUBLE, roof_plan_area DOUBLE, wall_area DOUBLE, party_wall_area DOUBLE,
  ground_area DOUBLE, outer_ceiling_area DOUBLE,
  roof_dev_n INTEGER, roof_dev_max DOUBLE, roof_dev_mean DOUBLE, roof_dev_std DOUBLE, roof_dev_rmse DOUBLE,
  wall_dev_n INTEGER, wall_dev_max DOUBLE, wall_dev_mean DOUBLE, wall_dev_std DOUBLE, wall_dev_rmse DOUBLE);
CREATE TABLE IF NOT EXISTS building_element (fid INTEGER PRIMARY KEY, geom MULTIPOLYGON,
  building_fid INTEGER NOT NULL REFERENCES building(fid) ON DELETE CASCADE,
  element_index INTEGER NOT NULL,
  element_type TEXT NOT NULL CHECK (element_type IN ('roof','wall','party_wall','ground','outer_ceiling')),
  area DOUBLE, plan_area DOUBLE, slope_deg DOUBLE, azimuth_deg DOUBLE, sigma_area DOUBLE,
  support_points INTEGER, rmse DOUBLE, wall_evidence TEXT,
  UNIQUE (building_fid, element_index));
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
CREATE TABLE IF NOT EXISTS parcel_job (fid INTEGER PRIMARY KEY, parcel_id TEXT NOT NULL UNIQUE,
  layer_index INTEGER,
  status TEXT NOT NULL CHECK (status IN ('pending','ok','empty','failed')),
  reason TEXT, inputs_key TEXT, run_id INTEGER REFERENCES run(fid),
  roof_points INTEGER, wall_points INTEGER, timings TEXT, updated DATETIME);
CREATE INDEX IF NOT EXISTS ix_run_input_run ON run_input(run_id);
CREATE INDEX IF NOT EXISTS ix_rrr_baunit ON la_rrr(baunit_id);
CREATE INDEX IF NOT EXISTS ix_rrr_party ON la_rrr(party_id);
CREATE INDEX IF NOT EXISTS ix_su_baunit ON la_spatialunit(baunit_id);
CREATE INDEX IF NOT EXISTS ix_building_su ON building(spatialunit_id);
CREATE INDEX IF NOT EXISTS ix_vu_baunit ON vm_valuationunit(baunit_id);
CREATE INDEX IF NOT EXISTS ix_vu_su ON vm_valuationunit(spatialunit_id);
CREATE INDEX IF NOT EXISTS ix_val_vu ON vm_valuation(valuationunit_id);
CREATE INDEX IF NOT EXISTS ix_val_run ON vm_valuation(run_id);
CREATE INDEX IF NOT EXISTS ix_ci_val ON vm_cost_item(valuation_id);
CREATE INDEX IF NOT EXISTS ix_ci_element ON vm_cost_item(element_fid);
CREATE INDEX IF NOT EXISTS ix_job_run ON parcel_job(run_id);
)SQL";

struct Layer {
  const char* table;
  const char* description;
  bool features;
  int z;  // gpkg_geometry_columns.z
};

const Layer kLayers[] = {
    {"la_spatialunit", "LADM spatial units: cadastral parcels", true, 0},
    {"building", "LoD2 buildings (closed solid, or footprint when none)", true, 1},
    {"building_element", "Building elements: roof, wall, party wall, ground, outer ceiling", true, 1},
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

std::string timings_json(const std::vector<Timing>& t) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& s : t) j.push_back({{"stage", s.stage}, {"seconds", s.seconds}});
  return j.dump();
}

std::vector<Timing> parse_timings(const std::string& text) {
  std::vector<Timing> out;
  if (text.empty()) return out;
  auto j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_array()) return out;
  for (const auto& e : j) out.push_back({e.value("stage", ""), e.value("seconds", 0.0)});
  return out;
}

ElementType element_type_from(const std::string& s) {
  for (ElementType t : {ElementType::Roof, ElementType::Wall, ElementType::PartyWall,
                        ElementType::Ground, ElementType::OuterCeiling})
    if (s == to_string(t)) return t;
  throw InputError("store", "unknown element type '" + s + "'");
}

WallEvidence evidence_from(const std::string& s) {
  for (WallEvidence e : {WallEvidence::None, WallEvidence::Measured, WallEvidence::Propagated,
                         WallEvidence::Default, WallEvidence::ParcelBoundary, WallEvidence::RoofStep})
    if (s == to_string(e)) return e;
  return WallEvidence::None;
}

ParcelStatus status_from(const std::string& s) {
  if (s == "ok") return ParcelStatus::Ok;
  if (s == "failed") return ParcelStatus::Failed;
  return ParcelStatus::Empty;
}

// What the building layer shows: the closed solid, else the ground faces.
std::vector<Face> building_geometry(const Building& b, std::string* kind) {
  if (!b.solid.empty()) {
    *kind = "solid";
    return b.solid;
  }
  std::vector<Face> faces;
  for (const Element& e : b.elements)
    if (e.type == ElementType::Ground) faces.insert(faces.end(), e.faces.begin(), e.faces.end());
  *kind = faces.empty() ? "none" : "footprint";
  return faces;
}

}  // namespace

// ---------------------------------------------------------------------------

struct Store::Impl {
  sql::Db db;
  int srs = 0;
  std::int64_t run_id = 0;
  // Prepared once: writing a parcel is a handful of bound inserts.
  sql::Stmt del_baunit, del_party, ins_party, ins_baunit, ins_rrr, ins_su, ins_building,
      ins_element, ins_vu, ins_val, ins_item, upsert_job, pending_job, done_job;

  void create_schema(const std::string& crs_wkt, int epsg);
  void register_srs(const std::string& crs_wkt, int epsg);
  void prepare();
  std::int64_t write_building(const Building& b, int index, std::int64_t su, const Vec3& off,
                              std::map<std::pair<std::string, int>, std::int64_t>& elements);
  void write_valuation(const ParcelValuation& v, std::int64_t baunit, std::int64_t su,
                       const std::map<std::pair<std::string, int>, std::int64_t>& elements);
  void update_extents();
};

Store::Store() = default;
Store::~Store() { close(); }

bool Store::is_open() const { return impl_ != nullptr; }
int Store::srs_id() const { return impl_ ? impl_->srs : 0; }

void Store::open(const std::string& path, const std::string& crs_wkt, int epsg) {
  close();
  auto impl = std::make_unique<Impl>();
  impl->db = sql::Db(path, false);
  // Header fields first, while still in rollback-journal mode: they land in the
  // main file at once, where validate_gpkg.py reads them.
  impl->db.exec("PRAGMA application_id = 1196444487; PRAGMA user_version = 10300;");
  impl->db.exec("PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL; PRAGMA foreign_keys = ON;");
  impl->create_schema(crs_wkt, epsg);
  impl->prepare();
  impl_ = std::move(impl);
}

void Store::Impl::register_srs(const std::string& crs_wkt, int epsg) {
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
}

void Store::Impl::create_schema(const std::string& crs_wkt, int epsg) {
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
  register_srs(crs_wkt, epsg);
  db.exec(kLadmSchema);
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
  }
  tx.commit();
}

void Store::Impl::prepare() {
  const std::string now = kNow;
  del_baunit = sql::Stmt(db, "DELETE FROM la_baunit WHERE parcel_id=?");
  del_party = sql::Stmt(db, "DELETE FROM la_party WHERE party_key=?");
  ins_party = sql::Stmt(db, "INSERT INTO la_party (party_key, name, party_type) VALUES (?,?,?)");
  ins_baunit = sql::Stmt(db, "INSERT INTO la_baunit (parcel_id, name, baunit_type) VALUES (?,?,?)");
  ins_rrr = sql::Stmt(db,
                      "INSERT INTO la_rrr (baunit_id, party_id, rrr_class, rrr_type, share) "
                      "VALUES (?,?,'right',?,1.0)");
  ins_su = sql::Stmt(db,
                     "INSERT INTO la_spatialunit (geom, baunit_id, parcel_id, layer_index, "
                     "official_area, computed_area, repair_note) VALUES (?,?,?,?,?,?,?)");
  ins_building = sql::Stmt(
      db,
      "INSERT INTO building (geom, spatialunit_id, building_id, building_index, geom_kind, volume, "
      "eave_height, ridge_height, terrain_z, storeys, solid_valid, solid_problem, roof_area, "
      "roof_plan_area, wall_area, party_wall_area, ground_area, outer_ceiling_area, roof_dev_n, "
      "roof_dev_max, roof_dev_mean, roof_dev_std, roof_dev_rmse, wall_dev_n, wall_dev_max, "
      "wall_dev_mean, wall_dev_std, wall_dev_rmse) "
      "VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
  ins_element = sql::Stmt(
      db,
      "INSERT INTO building_element (geom, building_fid, element_index, element_type, area, "
      "plan_area, slope_deg, azimuth_deg, sigma_area, support_points, rmse, wall_evidence) "
      "VALUES (?,?,?,?,?,?,?,?,?,?,?,?)");
  ins_vu = sql::Stmt(db,
                     "INSERT INTO vm_valuationunit (baunit_id, spatialunit_id, parcel_id, zone, "
                     "quality, land_area, land_area_source) VALUES (?,?,?,?,?,?,?)");
  ins_val = sql::Stmt(
      db,
      "INSERT INTO vm_valuation (valuationunit_id, run_id, approach, currency, land_price_per_m2, "
      "land_value, building_cost, sigma_building_cost, age_years, depreciation_share, "
      "depreciation, building_value, sigma_building_value, njop, sigma_njop, tax_rate, njoptkp, "
      "taxable, tax, sigma_tax, note, valued) "
      "VALUES (?,?,'cost',?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?," + now + ")");
  ins_item = sql::Stmt(
      db,
      "INSERT INTO vm_cost_item (valuation_id, element_fid, building_id, element_index, "
      "element_type, quality, area, sigma_area, unit_cost, amount, sigma_amount, support_points, "
      "rmse) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?)");
  upsert_job = sql::Stmt(
      db,
      "INSERT INTO parcel_job (parcel_id, layer_index, status, reason, inputs_key, run_id, "
      "roof_points, wall_points, timings, updated) VALUES (?,?,?,?,?,?,?,?,?," + now + ") "
      "ON CONFLICT(parcel_id) DO UPDATE SET layer_index=excluded.layer_index, "
      "status=excluded.status, reason=excluded.reason, inputs_key=excluded.inputs_key, "
      "run_id=excluded.run_id, roof_points=excluded.roof_points, "
      "wall_points=excluded.wall_points, timings=excluded.timings, updated=excluded.updated");
  pending_job = sql::Stmt(
      db,
      "INSERT INTO parcel_job (parcel_id, layer_index, status, inputs_key, run_id, updated) "
      "VALUES (?,?,'pending',?,?," + now + ") ON CONFLICT(parcel_id) DO UPDATE SET "
      "status='pending', reason=NULL, layer_index=excluded.layer_index, "
      "inputs_key=excluded.inputs_key, run_id=excluded.run_id, updated=excluded.updated "
      "WHERE parcel_job.status NOT IN ('ok','empty') OR parcel_job.inputs_key IS NOT excluded.inputs_key");
  done_job = sql::Stmt(db,
                       "SELECT 1 FROM parcel_job WHERE parcel_id=? AND inputs_key=? AND "
                       "status IN ('ok','empty')");
}

std::int64_t Store::begin_run(const std::string& params_json,
                              const std::vector<std::string>& input_files, const LocalFrame& frame) {
  if (!impl_) throw InputError("store", "begin_run before open");
  std::vector<InputFile> inputs;
  for (const auto& f : input_files) {
    std::error_code ec;
    auto bytes = std::filesystem::file_size(f, ec);
    inputs.push_back({f, sha256_file(f), ec ? -1 : std::int64_t(bytes)});
  }
  auto& db = impl_->db;
  sql::Transaction tx(db);
  sql::Stmt run(db, std::string("INSERT INTO run (tool_version, parameters, crs_epsg, origin_x, "
                                "origin_y, origin_z, started) VALUES (?,?,?,?,?,?,") + kNow + ")");
  run.bind(std::string("cadastre3d ") + C3D_VERSION).bind(params_json).bind(impl_->srs)
      .bind(frame.origin.x()).bind(frame.origin.y()).bind(frame.origin.z()).run();
  impl_->run_id = db.last_id();
  sql::Stmt in(db, "INSERT INTO run_input (run_id, path, sha256, bytes) VALUES (?,?,?,?)");
  for (const auto& f : inputs) in.bind(impl_->run_id).bind(f.path).bind(f.sha256).bind(f.bytes).run();
  tx.commit();
  return impl_->run_id;
}

void Store::mark_pending(const std::vector<Parcel>& parcels, const std::vector<std::string>& keys) {
  if (!impl_) throw InputError("store", "mark_pending before open");
  sql::Transaction tx(impl_->db);
  for (size_t i = 0; i < parcels.size(); ++i) {
    auto& s = impl_->pending_job;
    s.bind(parcels[i].id).bind(parcels[i].index).bind(i < keys.size() ? keys[i] : "");
    if (impl_->run_id) s.bind(impl_->run_id);
    else s.bind_null();
    s.run();
  }
  tx.commit();
}

bool Store::parcel_done(const std::string& parcel_id, const std::string& inputs_key) {
  if (!impl_) return false;
  auto& s = impl_->done_job;
  s.bind(parcel_id).bind(inputs_key);
  bool done = s.step();
  s.reset();
  return done;
}

std::int64_t Store::Impl::write_building(
    const Building& b, int index, std::int64_t su, const Vec3& off,
    std::map<std::pair<std::string, int>, std::int64_t>& elements) {
  std::string kind;
  BuildingTotals t = totals(b);
  auto& s = ins_building;
  s.bind_blob(gpkg_faces_blob(building_geometry(b, &kind), off, srs)).bind(su).bind(b.id)
      .bind(index).bind(kind).bind(b.volume).bind(b.eave_height).bind(b.ridge_height)
      .bind(b.terrain_z + off.z()).bind(b.storeys).bind(b.solid_valid ? 1 : 0)
      .bind(b.solid_problem).bind(t.roof).bind(t.roof_plan).bind(t.wall).bind(t.party_wall)
      .bind(t.ground).bind(t.outer_ceiling);
  for (const Deviation* d : {&b.roof_deviation, &b.wall_deviation})
    s.bind(d->n).bind(d->max).bind(d->mean).bind(d->std).bind(d->rmse);
  s.run();
  std::int64_t fid = db.last_id();
  for (int i = 0; i < int(b.elements.size()); ++i) {
    const Element& e = b.elements[size_t(i)];
    ins_element.bind_blob(gpkg_faces_blob(e.faces, off, srs)).bind(fid).bind(i)
        .bind(to_string(e.type)).bind(e.area).bind(e.plan_area).bind(e.slope_deg)
        .bind(e.azimuth_deg).bind(e.sigma_area).bind(e.support_points).bind(e.rmse)
        .bind(to_string(e.evidence)).run();
    elements[{b.id, i}] = db.last_id();
  }
  return fid;
}

void Store::Impl::write_valuation(
    const ParcelValuation& v, std::int64_t baunit, std::int64_t su,
    const std::map<std::pair<std::string, int>, std::int64_t>& elements) {
  ins_vu.bind(baunit).bind(su).bind(v.parcel_id).bind(v.zone).bind(v.quality).bind(v.land_area)
      .bind(v.land_area_source).run();
  std::int64_t vu = db.last_id();
  ins_val.bind(vu);
  if (run_id) ins_val.bind(run_id);
  else ins_val.bind_null();
  ins_val.bind(v.currency).bind(v.land_price_per_m2).bind(v.land_value).bind(v.building_cost)
      .bind(v.sigma_building_cost).bind(v.age_years).bind(v.depreciation_share)
      .bind(v.depreciation).bind(v.building_value).bind(v.sigma_building_value).bind(v.njop)
      .bind(v.sigma_njop).bind(v.tax_rate).bind(v.njoptkp).bind(v.taxable).bind(v.tax)
      .bind(v.sigma_tax).bind(v.note).run();
  std::int64_t val = db.last_id();
  for (const CostItem& c : v.items) {
    ins_item.bind(val);
    auto it = elements.find({c.building_id, c.element_index});
    if (it != elements.end()) ins_item.bind(it->second);
    else ins_item.bind_null();
    ins_item.bind(c.building_id).bind(c.element_index).bind(c.element_type).bind(c.quality)
        .bind(c.area).bind(c.sigma_area).bind(c.unit_cost).bind(c.amount).bind(c.sigma_amount)
        .bind(c.support_points).bind(c.rmse).run();
  }
}

void Store::write_parcel(const Parcel& parcel, const ParcelResult& result,
                         const ParcelValuation& valuation, const LocalFrame& frame,
                         const std::string& inputs_key) {
  if (!impl_) throw InputError("store", "write_parcel before open");
  Impl& m = *impl_;
  sql::Transaction tx(m.db);
  const std::string party_key = "owner:" + parcel.id;
  m.del_baunit.bind(parcel.id).run();  // cascades to every row of this parcel
  m.del_party.bind(party_key).run();
  m.ins_party.bind(party_key).bind("owner of parcel " + parcel.id + " (not in the parcel layer)")
      .bind("unknown").run();
  std::int64_t party = m.db.last_id();
  m.ins_baunit.bind(parcel.id).bind("parcel " + parcel.id).bind("basicPropertyUnit").run();
  std::int64_t baunit = m.db.last_id();
  m.ins_rrr.bind(baunit).bind(party).bind(parcel.right_type).run();
  m.ins_su.bind_blob(gpkg_multipolygon_blob(parcel.shape, m.srs)).bind(baunit).bind(parcel.id)
      .bind(parcel.index).bind(parcel.official_area).bind(area(parcel.shape))
      .bind(parcel.repair_note).run();
  std::int64_t su = m.db.last_id();
  std::map<std::pair<std::string, int>, std::int64_t> elements;
  for (int k = 0; k < int(result.buildings.size()); ++k)
    m.write_building(result.buildings[size_t(k)], k, su, frame.origin, elements);
  m.write_valuation(valuation, baunit, su, elements);
  m.upsert_job.bind(parcel.id).bind(parcel.index).bind(to_string(result.status))
      .bind(result.reason).bind(inputs_key);
  if (m.run_id) m.upsert_job.bind(m.run_id);
  else m.upsert_job.bind_null();
  m.upsert_job.bind(result.roof_points).bind(result.wall_points)
      .bind(timings_json(result.timings)).run();
  tx.commit();
}

void Store::Impl::update_extents() {
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

void Store::end_run() {
  if (!impl_) return;
  auto& db = impl_->db;
  sql::Transaction tx(db);
  if (impl_->run_id) {
    sql::Stmt upd(db, std::string("UPDATE run SET finished=") + kNow +
                          ", parcels_ok=(SELECT count(*) FROM parcel_job WHERE run_id=?1 AND status='ok'),"
                          " parcels_empty=(SELECT count(*) FROM parcel_job WHERE run_id=?1 AND status='empty'),"
                          " parcels_failed=(SELECT count(*) FROM parcel_job WHERE run_id=?1 AND status='failed')"
                          " WHERE fid=?1");
    upd.bind(impl_->run_id).run();
  }
  impl_->update_extents();
  tx.commit();
  impl_->run_id = 0;
}

void Store::close() {
  if (!impl_) return;
  // Fold the WAL back so the .gpkg alone is complete for copying / QGIS.
  sqlite3_wal_checkpoint_v2(impl_->db.get(), nullptr, SQLITE_CHECKPOINT_TRUNCATE, nullptr, nullptr);
  impl_.reset();
}

// ---------------------------------------------------------------------------
// Reading back

namespace {

sql::Db open_store(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path, "store not found");
  // Read-write but query-only where possible: the last connection to close
  // then folds the WAL away instead of leaving -wal / -shm files behind.
  sql::Db db;
  try {
    db = sql::Db(path, false);
    db.exec("PRAGMA query_only = 1");
  } catch (const InputError&) {
    db = sql::Db(path, true);
  }
  sql::Stmt q(db, "SELECT count(*) FROM sqlite_master WHERE name IN ('la_spatialunit','parcel_job')");
  if (!q.step() || q.get_int(0) != 2) throw InputError(path, "not a Cadastre3D store");
  return db;
}

LocalFrame latest_frame(const sql::Db& db) {
  LocalFrame f;
  sql::Stmt q(db, "SELECT origin_x, origin_y, origin_z FROM run ORDER BY fid DESC LIMIT 1");
  if (q.step() && !q.is_null(0)) f.origin = Vec3(q.get_double(0), q.get_double(1), q.get_double(2));
  return f;
}

void read_crs(const sql::Db& db, BatchModel& m) {
  sql::Stmt q(db,
              "SELECT s.srs_id, s.organization, s.definition FROM gpkg_geometry_columns g "
              "JOIN gpkg_spatial_ref_sys s ON s.srs_id=g.srs_id WHERE g.table_name='la_spatialunit'");
  if (!q.step()) return;
  if (q.get_text(1) == "EPSG") m.epsg = int(q.get_int(0));
  std::string def = q.get_text(2);
  if (def != "undefined") m.crs_wkt = def;
}

std::vector<Face> read_faces(const sql::Stmt& q, int col, const Vec3& origin) {
  std::size_t n;
  const std::uint8_t* b = q.blob(col, &n);
  return gpkg_read_faces(b, n, origin);
}

std::vector<Building> read_buildings(const sql::Db& db, std::int64_t su, const LocalFrame& frame) {
  sql::Stmt qb(db,
               "SELECT fid, geom, geom_kind, building_id, volume, eave_height, ridge_height, "
               "terrain_z, storeys, solid_valid, solid_problem, roof_dev_n, roof_dev_max, "
               "roof_dev_mean, roof_dev_std, roof_dev_rmse, wall_dev_n, wall_dev_max, wall_dev_mean, "
               "wall_dev_std, wall_dev_rmse FROM building WHERE spatialunit_id=? ORDER BY building_index");
  sql::Stmt qe(db,
               "SELECT geom, element_type, area, plan_area, slope_deg, azimuth_deg, sigma_area, "
               "support_points, rmse, wall_evidence FROM building_element WHERE building_fid=? "
               "ORDER BY element_index");
  std::vector<Building> out;
  qb.bind(su);
  while (qb.step()) {
    Building b;
    if (qb.get_text(2) == "solid") b.solid = read_faces(qb, 1, frame.origin);
    b.id = qb.get_text(3);
    b.volume = qb.get_double(4);
    b.eave_height = qb.get_double(5);
    b.ridge_height = qb.get_double(6);
    b.terrain_z = qb.get_double(7) - frame.origin.z();
    b.storeys = int(qb.get_int(8));
    b.solid_valid = qb.get_int(9) != 0;
    b.solid_problem = qb.get_text(10);
    Deviation* devs[2] = {&b.roof_deviation, &b.wall_deviation};
    for (int k = 0; k < 2; ++k) {
      int c = 11 + 5 * k;
      *devs[k] = {long(qb.get_int(c)), qb.get_double(c + 1), qb.get_double(c + 2),
                  qb.get_double(c + 3), qb.get_double(c + 4)};
    }
    qe.bind(qb.get_int(0));
    while (qe.step()) {
      Element e;
      e.faces = read_faces(qe, 0, frame.origin);
      e.type = element_type_from(qe.get_text(1));
      e.area = qe.get_double(2);
      e.plan_area = qe.get_double(3);
      e.slope_deg = qe.get_double(4);
      e.azimuth_deg = qe.get_double(5);
      e.sigma_area = qe.get_double(6);
      e.support_points = int(qe.get_int(7));
      e.rmse = qe.get_double(8);
      e.evidence = evidence_from(qe.get_text(9));
      b.elements.push_back(std::move(e));
    }
    qe.reset();
    out.push_back(std::move(b));
  }
  return out;
}

}  // namespace

BatchModel load_batch_model(const std::string& path) {
  sql::Db db = open_store(path);
  BatchModel m;
  m.frame = latest_frame(db);
  read_crs(db, m);
  sql::Stmt q(db,
              "SELECT su.fid, su.geom, su.parcel_id, su.layer_index, su.official_area, "
              "su.repair_note, r.rrr_type, j.status, j.reason, j.roof_points, j.wall_points, "
              "j.timings FROM la_spatialunit su "
              "LEFT JOIN la_rrr r ON r.baunit_id = su.baunit_id "
              "LEFT JOIN parcel_job j ON j.parcel_id = su.parcel_id "
              "ORDER BY su.layer_index, su.parcel_id");
  try {
    while (q.step()) {
      Parcel p;
      std::size_t n;
      const std::uint8_t* b = q.blob(1, &n);
      p.shape = gpkg_read_multipolygon(b, n);
      p.id = q.get_text(2);
      p.index = int(q.get_int(3));
      p.official_area = q.get_double(4);
      p.repair_note = q.get_text(5);
      p.right_type = q.get_text(6);
      ParcelResult r;
      r.parcel_index = p.index;
      r.parcel_id = p.id;
      r.status = status_from(q.get_text(7));
      r.reason = q.get_text(8);
      r.roof_points = long(q.get_int(9));
      r.wall_points = long(q.get_int(10));
      r.timings = parse_timings(q.get_text(11));
      r.buildings = read_buildings(db, q.get_int(0), m.frame);
      m.parcels.push_back(std::move(p));
      m.results.push_back(std::move(r));
    }
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const InputError*>(&e)) throw;
    throw InputError(path, e.what());  // malformed geometry blob
  }
  return m;
}

std::vector<ParcelValuation> load_valuations(const std::string& path) {
  sql::Db db = open_store(path);
  sql::Stmt q(db,
              "SELECT v.fid, u.parcel_id, v.currency, u.zone, u.quality, v.note, u.land_area, "
              "u.land_area_source, v.land_price_per_m2, v.land_value, v.building_cost, "
              "v.sigma_building_cost, v.age_years, v.depreciation_share, v.depreciation, "
              "v.building_value, v.sigma_building_value, v.njop, v.sigma_njop, v.tax_rate, "
              "v.njoptkp, v.taxable, v.tax, v.sigma_tax "
              "FROM la_spatialunit su JOIN vm_valuationunit u ON u.spatialunit_id = su.fid "
              "JOIN vm_valuation v ON v.valuationunit_id = u.fid "
              "ORDER BY su.layer_index, su.parcel_id");
  sql::Stmt qi(db,
               "SELECT building_id, element_index, element_type, quality, area, sigma_area, "
               "unit_cost, amount, sigma_amount, support_points, rmse FROM vm_cost_item "
               "WHERE valuation_id=? ORDER BY fid");
  std::vector<ParcelValuation> out;
  while (q.step()) {
    ParcelValuation v;
    v.parcel_id = q.get_text(1);
    v.currency = q.get_text(2);
    v.zone = q.get_text(3);
    v.quality = q.get_text(4);
    v.note = q.get_text(5);
    v.land_area = q.get_double(6);
    v.land_area_source = q.get_text(7);
    double* nums[] = {&v.land_price_per_m2, &v.land_value, &v.building_cost,
                      &v.sigma_building_cost, &v.age_years, &v.depreciation_share,
                      &v.depreciation, &v.building_value, &v.sigma_building_value, &v.njop,
                      &v.sigma_njop, &v.tax_rate, &v.njoptkp, &v.taxable, &v.tax, &v.sigma_tax};
    for (int k = 0; k < 16; ++k) *nums[k] = q.get_double(8 + k);
    qi.bind(q.get_int(0));
    while (qi.step()) {
      CostItem c;
      c.building_id = qi.get_text(0);
      c.element_index = qi.is_null(1) ? -1 : int(qi.get_int(1));
      c.element_type = qi.get_text(2);
      c.quality = qi.get_text(3);
      c.area = qi.get_double(4);
      c.sigma_area = qi.get_double(5);
      c.unit_cost = qi.get_double(6);
      c.amount = qi.get_double(7);
      c.sigma_amount = qi.get_double(8);
      c.support_points = int(qi.get_int(9));
      c.rmse = qi.get_double(10);
      v.items.push_back(std::move(c));
    }
    qi.reset();
    out.push_back(std::move(v));
  }
  return out;
}

std::vector<JobRecord> load_jobs(const std::string& path) {
  sql::Db db = open_store(path);
  sql::Stmt q(db,
              "SELECT parcel_id, layer_index, status, reason, inputs_key, updated, run_id "
              "FROM parcel_job ORDER BY layer_index, parcel_id");
  std::vector<JobRecord> out;
  while (q.step())
    out.push_back({q.get_text(0), int(q.get_int(1)), q.get_text(2), q.get_text(3), q.get_text(4),
                   q.get_text(5), q.get_int(6)});
  return out;
}

std::vector<RunRecord> load_runs(const std::string& path) {
  sql::Db db = open_store(path);
  sql::Stmt q(db,
              "SELECT fid, tool_version, parameters, started, finished, crs_epsg, origin_x, "
              "origin_y, origin_z, parcels_ok, parcels_empty, parcels_failed FROM run ORDER BY fid");
  sql::Stmt qi(db, "SELECT path, sha256, bytes FROM run_input WHERE run_id=? ORDER BY fid");
  std::vector<RunRecord> out;
  while (q.step()) {
    RunRecord r;
    r.id = q.get_int(0);
    r.tool_version = q.get_text(1);
    r.parameters = q.get_text(2);
    r.started = q.get_text(3);
    r.finished = q.get_text(4);
    r.epsg = int(q.get_int(5));
    r.origin = Vec3(q.get_double(6), q.get_double(7), q.get_double(8));
    r.parcels_ok = int(q.get_int(9));
    r.parcels_empty = int(q.get_int(10));
    r.parcels_failed = int(q.get_int(11));
    qi.bind(r.id);
    while (qi.step()) r.inputs.push_back({qi.get_text(0), qi.get_text(1), qi.get_int(2)});
    qi.reset();
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace c3d
