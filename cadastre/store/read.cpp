// Reading a store back: the batch model, valuations, jobs and runs.
#include "cadastre/store/store.h"

#include <algorithm>
#include <filesystem>
#include <unordered_map>
#include <nlohmann/json.hpp>

#include "cadastre/store/columns.h"
#include "cadastre/store/gpkg_geometry.h"
#include "cadastre/store/lods.h"
#include "cadastre/store/meshes.h"
#include "cadastre/store/schema.h"
#include "cadastre/store/sql_db.h"
#include "core/error.h"
#include "core/primitives/exact_shape.h"

namespace c3d {

namespace {

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
  throw std::invalid_argument("unknown element type '" + s + "'");
}

WallEvidence evidence_from(const std::string& s) {
  for (WallEvidence e : {WallEvidence::None, WallEvidence::Measured, WallEvidence::Propagated,
                         WallEvidence::Default, WallEvidence::ParcelBoundary, WallEvidence::RoofStep})
    if (s == to_string(e)) return e;
  return WallEvidence::None;
}

// What parse() makes of a row's text; text it refuses (std::invalid_argument)
// is an InputError naming the store and the row.
template <class Parse>
auto parsed(const sql::Db& db, const std::string& row, Parse parse) {
  try {
    return parse();
  } catch (const std::invalid_argument& e) {
    throw InputError(sql::display_name(db.path()), row + ": " + e.what());
  }
}

// A job's status: none while pending (and where a store from before jobs has
// no row); other text must name a ParcelStatus.
std::optional<ParcelStatus> job_status(const sql::Db& db, const std::string& parcel_id, const std::string& text) {
  if (text.empty() || text == "pending") return std::nullopt;
  return parsed(db, "parcel " + parcel_id, [&] { return parcel_status_from(text); });
}

// A building's level of detail; a row from before LoDs were recorded holds a 2.2 model.
Lod building_lod(const sql::Db& db, const std::string& building_id, const std::string& text) {
  return parsed(db, "building " + building_id, [&] { return text.empty() ? Lod::Lod22 : lod_from(text); });
}

using namespace store_columns;

sql::Db open_store(const std::string& path) {
  if (sql::is_postgres_url(path)) {
    sql::Db db(path, true);
    if (!db.has_table("la_spatialunit") || !db.has_table("parcel_job"))
      throw InputError(sql::display_name(path), "not a Cadastre3D store (no la_spatialunit / parcel_job table)");
    return db;
  }
  if (!std::filesystem::exists(path)) throw InputError(path, "store not found");
  // Read-write but query-only where possible: the last connection to close
  // then folds the WAL away instead of leaving -wal / -shm files behind.
  sql::Db db;
  try {
    db = sql::Db(path, false);
    db.exec("PRAGMA query_only = 1");
    db.has_table("parcel_job");  // the first read: on read-only media it fails for a WAL-mode file
  } catch (const InputError&) {
    db = sql::Db(path, true);
  }
  if (!db.has_table("la_spatialunit") || !db.has_table("parcel_job")) throw InputError(path, "not a Cadastre3D store");
  return db;
}

LocalFrame latest_frame(const sql::Db& db) {
  LocalFrame f;
  sql::Stmt q(db, "SELECT origin_x, origin_y, origin_z FROM run ORDER BY fid DESC LIMIT 1");
  if (q.step() && !q.is_null(0)) f.origin = Vec3(q.get_double(0), q.get_double(1), q.get_double(2));
  return f;
}

void read_crs(const sql::Db& db, BatchModel& m) {
  sql::Stmt q(db, db.postgres()
                      ? "SELECT g.srid, upper(s.auth_name), coalesce(s.srtext, 'undefined') FROM geometry_columns g "
                        "LEFT JOIN spatial_ref_sys s ON s.srid=g.srid WHERE g.f_table_schema = current_schema() "
                        "AND g.f_table_name='la_spatialunit'"
                      : "SELECT s.srs_id, s.organization, s.definition FROM gpkg_geometry_columns g "
                        "JOIN gpkg_spatial_ref_sys s ON s.srs_id=g.srs_id WHERE g.table_name='la_spatialunit'");
  if (!q.step()) return;
  if (q.get_text(1) == "EPSG") m.epsg = int(q.get_int(0));
  std::string def = q.get_text(2);
  if (def != "undefined") m.crs_wkt = def;
}

std::vector<Face> read_faces(const sql::Stmt& q, const Vec3& origin) {
  std::size_t n;
  const std::uint8_t* b = q.blob("geom", &n);
  return gpkg_read_faces(b, n, origin);
}

Deviation read_deviation(const sql::Stmt& q, const std::string& prefix) {
  return {long(q.get_int(prefix + "_n")), q.get_double(prefix + "_max"), q.get_double(prefix + "_mean"),
          q.get_double(prefix + "_std"), q.get_double(prefix + "_rmse")};
}

Element read_element(const sql::Db& db, const sql::Stmt& q, const Building& b, const Vec3& origin) {
  Element e;
  e.faces = read_faces(q, origin);
  e.type = parsed(db, "building " + b.id, [&] { return element_type_from(q.get_text("element_type")); });
  e.area = q.get_double("area");
  e.plan_area = q.get_double("plan_area");
  e.slope_deg = q.get_double("slope_deg");
  e.azimuth_deg = q.get_double("azimuth_deg");
  e.sigma_area = q.get_double("sigma_area");
  e.support_points = int(q.get_int("support_points"));
  e.rmse = q.get_double("rmse");
  e.evidence = evidence_from(q.get_text("wall_evidence"));
  e.sigma_shared = q.is_null("sigma_shared") ? 0.0 : q.get_double("sigma_shared");
  return e;
}

Building read_building(const sql::Db& db, const sql::Stmt& q, const LocalFrame& frame) {
  Building b;
  if (q.get_text("geom_kind") == "solid") b.solid = read_faces(q, frame.origin);
  b.id = q.get_text("building_id");
  b.volume = q.get_double("volume");
  b.eave_height = q.get_double("eave_height");
  b.ridge_height = q.get_double("ridge_height");
  b.terrain_z = q.get_double("terrain_z") - frame.origin.z();
  b.storeys = int(q.get_int("storeys"));
  b.solid_valid = q.get_int("solid_valid") != 0;
  b.solid_problem = q.get_text("solid_problem");
  b.roof_deviation = read_deviation(q, "roof_dev");
  b.wall_deviation = read_deviation(q, "wall_dev");
  b.lod = building_lod(db, b.id, q.get_text("lod"));
  b.lod_note = q.get_text("lod_note");
  b.exact = parsed(db, "building " + b.id, [&] { return exact_shape_from_json(q.get_text("exact_shape"), frame.origin); });
  MeshRefinement& m = b.refinement;
  m.triangles = int(q.get_int("refine_triangles"));
  m.snapped_share = q.get_double("refine_snapped_share");
  m.chamfer_before_m = q.get_double("refine_chamfer_before");
  m.chamfer_after_m = q.get_double("refine_chamfer_after");
  m.cloud_before_m = q.get_double("refine_cloud_before");
  m.cloud_after_m = q.get_double("refine_cloud_after");
  return b;
}

// The statements that read a parcel's buildings, prepared once for all the
// parcels one query gives: each asks the schema what it may select, and a
// page of thousands of parcels would otherwise ask it thousands of times.
class BuildingRows {
 public:
  explicit BuildingRows(const sql::Db& db)
      : db_(db),
        building_(db, "SELECT " + select_list(db, kBuilding) +
                          " FROM building WHERE spatialunit_id=? ORDER BY building_index"),
        element_(db, "SELECT " + select_list(db, kElement) +
                         " FROM building_element WHERE building_fid=? ORDER BY element_index"),
        lods_(db),
        meshes_(db) {}

  std::vector<Building> of(std::int64_t su, const LocalFrame& frame) {
    std::vector<Building> out;
    building_.bind(su);
    while (building_.step()) {
      Building b = read_building(db_, building_, frame);
      const std::int64_t fid = building_.get_int("fid");
      lods_.read(fid, frame.origin, b);
      meshes_.read(fid, b);
      element_.bind(fid);
      while (element_.step()) b.elements.push_back(read_element(db_, element_, b, frame.origin));
      element_.reset();
      out.push_back(std::move(b));
    }
    building_.reset();
    return out;
  }

 private:
  const sql::Db& db_;
  sql::Stmt building_, element_;
  store_lods::Reader lods_;
  store_meshes::Reader meshes_;
};

// At most this many ids bound in one query: well under SQLite's (32766) and
// libpq's (65535) limits on bound parameters; a page of parcels is one query.
constexpr size_t kIdsPerQuery = 1000;

// Reads in one snapshot: a parcel's row and its buildings' rows agree while
// another writer rewrites it (PostgreSQL: REPEATABLE READ; SQLite: a deferred
// read transaction, which holds no lock a writer waits on in WAL mode).
class ReadSnapshot {
 public:
  explicit ReadSnapshot(sql::Db& db) : db_(db) {
    db_.exec(db_.postgres() ? "BEGIN ISOLATION LEVEL REPEATABLE READ READ ONLY" : "BEGIN");
  }
  ~ReadSnapshot() {
    try {
      db_.exec("COMMIT");
    } catch (const std::exception&) {  // nothing was written: nothing to lose
    }
  }
  ReadSnapshot(const ReadSnapshot&) = delete;
  ReadSnapshot& operator=(const ReadSnapshot&) = delete;

 private:
  sql::Db& db_;
};

// " WHERE su.parcel_id IN (?,...)" with n placeholders.
std::string id_filter(size_t n) {
  std::string w = " WHERE su.parcel_id IN (";
  for (size_t k = 0; k < n; ++k) w += k ? ",?" : "?";
  return w + ")";
}

// Calls read(filter, ids) once for the whole store (ids null: no filter) or
// once per piece of at most kIdsPerQuery ids.
template <class Read>
void by_pieces(const std::vector<std::string>* ids, Read read) {
  if (!ids) return read(std::string(), std::vector<std::string>());
  for (size_t at = 0; at < ids->size(); at += kIdsPerQuery) {
    const auto from = ids->begin() + long(at), to = ids->begin() + long(std::min(at + kIdsPerQuery, ids->size()));
    read(id_filter(size_t(to - from)), std::vector<std::string>(from, to));
  }
}

// Positions in `got` in the order of `ids` (ids the store lacks left out).
std::vector<size_t> order_of(const std::vector<std::string>& ids, const std::vector<std::string>& got) {
  std::unordered_map<std::string, std::vector<size_t>> at;
  for (size_t i = 0; i < got.size(); ++i) at[got[i]].push_back(i);
  std::vector<size_t> out;
  for (const std::string& id : ids) {
    auto it = at.find(id);
    if (it == at.end()) continue;
    out.insert(out.end(), it->second.begin(), it->second.end());
    at.erase(it);  // an id asked twice comes once
  }
  return out;
}

template <class T>
std::vector<T> permuted(std::vector<T>& v, const std::vector<size_t>& order) {
  std::vector<T> out;
  out.reserve(order.size());
  for (size_t i : order) out.push_back(std::move(v[i]));
  return out;
}

// Appends the parcels the query with this filter gives (ids bound in order).
void read_parcels(const sql::Db& db, const std::string& filter, const std::vector<std::string>& ids, BatchModel& m) {
  sql::Stmt q(db, "SELECT " + select_list(db, kSpatialUnit, "su") + ", " +
                      select_list(db, kRrr, "r", {"rrr_type", "local_type"}) + ", " +
                      select_list(db, kJob, "j", {"status", "reason", "roof_points", "wall_points", "timings"}) +
                      " FROM la_spatialunit su "
                      "LEFT JOIN la_rrr r ON r.baunit_id = su.baunit_id "
                      "LEFT JOIN parcel_job j ON j.parcel_id = su.parcel_id" + filter +
                      " ORDER BY su.layer_index, su.parcel_id");
  for (const std::string& id : ids) q.bind(id);
  BuildingRows buildings(db);
  while (q.step()) {
    Parcel p;
    std::size_t n;
    const std::uint8_t* b = q.blob("geom", &n);
    p.shape = gpkg_read_multipolygon(b, n);
    p.id = q.get_text("parcel_id");
    p.index = int(q.get_int("layer_index"));
    p.official_area = q.get_double("official_area");
    p.repair_note = q.get_text("repair_note");
    // The layer's own name of the right; a store written before kept it in rrr_type.
    p.right_type = q.get_text(q.is_null("local_type") ? "rrr_type" : "local_type");
    ParcelResult r;
    r.parcel_index = p.index;
    r.parcel_id = p.id;
    r.status = job_status(db, p.id, q.get_text("status")).value_or(ParcelStatus::Empty);  // rewritten now: empty till done
    r.reason = q.get_text("reason");
    r.roof_points = long(q.get_int("roof_points"));
    r.wall_points = long(q.get_int("wall_points"));
    r.timings = parse_timings(q.get_text("timings"));
    r.buildings = buildings.of(q.get_int("fid"), m.frame);
    m.parcels.push_back(std::move(p));
    m.results.push_back(std::move(r));
  }
}

BatchModel read_batch_model(const std::string& path, const std::vector<std::string>* ids) {
  sql::Db db = open_store(path);
  const ReadSnapshot snapshot(db);
  BatchModel m;
  m.frame = latest_frame(db);
  read_crs(db, m);
  try {
    by_pieces(ids, [&](const std::string& filter, const std::vector<std::string>& piece) {
      read_parcels(db, filter, piece, m);
    });
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const InputError*>(&e)) throw;
    throw InputError(path, e.what());  // malformed geometry blob
  }
  if (ids) {
    std::vector<std::string> got;
    for (const Parcel& p : m.parcels) got.push_back(p.id);
    const std::vector<size_t> order = order_of(*ids, got);
    m.parcels = permuted(m.parcels, order);
    m.results = permuted(m.results, order);
  }
  return m;
}

CostItem read_cost_item(const sql::Stmt& q) {
  CostItem c;
  c.building_id = q.get_text("building_id");
  c.element_index = q.is_null("element_index") ? -1 : int(q.get_int("element_index"));
  c.element_type = q.get_text("element_type");
  c.quality = q.get_text("quality");
  c.area = q.get_double("area");
  c.sigma_area = q.get_double("sigma_area");
  c.unit_cost = q.get_double("unit_cost");
  c.amount = q.get_double("amount");
  c.sigma_amount = q.get_double("sigma_amount");
  c.support_points = int(q.get_int("support_points"));
  c.rmse = q.get_double("rmse");
  return c;
}

ParcelValuation read_valuation(const sql::Stmt& q) {
  ParcelValuation v;
  v.parcel_id = q.get_text("parcel_id");
  v.currency = q.get_text("currency");
  v.zone = q.get_text("zone");
  v.quality = q.get_text("quality");
  v.note = q.get_text("note");
  v.land_area = q.get_double("land_area");
  v.land_area_source = q.get_text("land_area_source");
  const std::pair<double*, const char*> numbers[] = {
      {&v.land_price_per_m2, "land_price_per_m2"}, {&v.land_value, "land_value"},
      {&v.building_cost, "building_cost"},         {&v.sigma_building_cost, "sigma_building_cost"},
      {&v.age_years, "age_years"},                 {&v.depreciation_share, "depreciation_share"},
      {&v.depreciation, "depreciation"},           {&v.building_value, "building_value"},
      {&v.sigma_building_value, "sigma_building_value"}, {&v.njop, "njop"},
      {&v.sigma_njop, "sigma_njop"},               {&v.tax_rate, "tax_rate"},
      {&v.njoptkp, "njoptkp"},                     {&v.taxable, "taxable"},
      {&v.tax, "tax"},                             {&v.sigma_tax, "sigma_tax"}};
  for (const auto& [field, name] : numbers) *field = q.get_double(name);
  return v;
}

// Appends the valuations the query with this filter gives (ids bound in order).
void read_valuation_rows(const sql::Db& db, const std::string& filter, const std::vector<std::string>& ids,
                         std::vector<ParcelValuation>& out) {
  sql::Stmt q(db, "SELECT " + select_list(db, kValuation, "v") + ", " +
                      select_list(db, kValuationUnit, "u",
                                  {"parcel_id", "zone", "quality", "land_area", "land_area_source"}) +
                      " FROM la_spatialunit su JOIN vm_valuationunit u ON u.spatialunit_id = su.fid "
                      "JOIN vm_valuation v ON v.valuationunit_id = u.fid" + filter +
                      " ORDER BY su.layer_index, su.parcel_id");
  sql::Stmt qi(db, "SELECT " + select_list(db, kCostItem) + " FROM vm_cost_item WHERE valuation_id=? ORDER BY fid");
  for (const std::string& id : ids) q.bind(id);
  while (q.step()) {
    ParcelValuation v = read_valuation(q);
    qi.bind(q.get_int("fid"));
    while (qi.step()) v.items.push_back(read_cost_item(qi));
    qi.reset();
    out.push_back(std::move(v));
  }
}

std::vector<ParcelValuation> read_valuations(const std::string& path, const std::vector<std::string>* ids) {
  sql::Db db = open_store(path);
  const ReadSnapshot snapshot(db);
  std::vector<ParcelValuation> out;
  by_pieces(ids, [&](const std::string& filter, const std::vector<std::string>& piece) {
    read_valuation_rows(db, filter, piece, out);
  });
  if (!ids) return out;
  std::vector<std::string> got;
  for (const ParcelValuation& v : out) got.push_back(v.parcel_id);
  return permuted(out, order_of(*ids, got));
}

}  // namespace

bool is_database_url(const std::string& loc) { return sql::is_postgres_url(loc); }

bool store_exists(const std::string& loc) {
  if (is_database_url(loc)) return sql::Db(loc, true).has_table("parcel_job");
  if (!std::filesystem::exists(loc)) return false;
  // The schema is written in one transaction: a batch killed before it
  // commits leaves a file without a single table (empty, or a header only),
  // which holds nothing to keep.
  if (std::filesystem::file_size(loc) == 0) return false;
  try {
    const sql::Db db(loc, true);
    sql::Stmt tables(db, "SELECT count(*) FROM sqlite_master WHERE type = 'table'");
    return !tables.step() || tables.get_int(0) > 0;
  } catch (const InputError&) {
    throw InputError(loc, "not a GeoPackage or SQLite file; left as it is: choose another --store or --out");
  }
}

BatchModel load_batch_model(const std::string& path) { return read_batch_model(path, nullptr); }

BatchModel load_batch_model(const std::string& path, const std::vector<std::string>& parcel_ids) {
  return read_batch_model(path, &parcel_ids);
}

std::vector<ParcelValuation> load_valuations(const std::string& path) { return read_valuations(path, nullptr); }

std::vector<ParcelValuation> load_valuations(const std::string& path, const std::vector<std::string>& parcel_ids) {
  return read_valuations(path, &parcel_ids);
}

std::vector<JobRecord> load_jobs(const std::string& path) {
  sql::Db db = open_store(path);
  sql::Stmt q(db, "SELECT " + select_list(db, kJob) + " FROM parcel_job ORDER BY layer_index, parcel_id");
  std::vector<JobRecord> out;
  while (q.step()) {
    const std::string id = q.get_text("parcel_id");
    out.push_back({id, int(q.get_int("layer_index")), job_status(db, id, q.get_text("status")),
                   q.get_text("reason"), q.get_text("inputs_key"), q.get_text("updated"), q.get_int("run_id")});
  }
  return out;
}

RunRecord read_run(const sql::Stmt& q) {
  RunRecord r;
  r.id = q.get_int("fid");
  r.tool_version = q.get_text("tool_version");
  r.parameters = q.get_text("parameters");
  r.started = q.get_text("started");
  r.finished = q.get_text("finished");
  r.epsg = int(q.get_int("crs_epsg"));
  r.origin = Vec3(q.get_double("origin_x"), q.get_double("origin_y"), q.get_double("origin_z"));
  r.parcels_ok = int(q.get_int("parcels_ok"));
  r.parcels_empty = int(q.get_int("parcels_empty"));
  r.parcels_failed = int(q.get_int("parcels_failed"));
  r.parcels_suspect = int(q.get_int("parcels_suspect"));
  r.shard = q.get_text("shard");
  return r;
}

std::vector<RunRecord> load_runs(const std::string& path) {
  sql::Db db = open_store(path);
  sql::Stmt q(db, "SELECT " + select_list(db, kRun) + " FROM run ORDER BY fid");
  sql::Stmt qi(db, "SELECT " + select_list(db, kRunInput) + " FROM run_input WHERE run_id=? ORDER BY fid");
  std::vector<RunRecord> out;
  while (q.step()) {
    RunRecord r = read_run(q);
    qi.bind(r.id);
    while (qi.step())
      r.inputs.push_back({qi.get_text("path"), qi.get_text("sha256"), qi.get_int("bytes"), qi.get_text("role")});
    qi.reset();
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace c3d
