#include "cadastre/store/store.h"

#include <sqlite3.h>

#include <map>
#include <set>
#include <nlohmann/json.hpp>

#include "cadastre/store/columns.h"
#include "cadastre/store/gis.h"
#include "cadastre/store/gpkg_geometry.h"
#include "cadastre/store/gpkg_rtree.h"
#include "cadastre/store/lods.h"
#include "cadastre/store/meshes.h"
#include "cadastre/store/schema.h"
#include "cadastre/store/sql_db.h"
#include "cadastre/store/styles.h"
#include "core/error.h"
#include "core/geometry/geometry.h"
#include "core/io/sha256.h"
#include "core/primitives/exact_shape.h"

namespace c3d {

namespace {

std::string timings_json(const std::vector<Timing>& t) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& s : t) j.push_back({{"stage", s.stage}, {"seconds", s.seconds}});
  return j.dump();
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

// Fills the GIS layers of parcels stored before they existed (a store of an
// earlier version, opened to resume) from their 3D rows and valuations, in
// one transaction; does nothing when every parcel has its row.
void backfill_gis(sql::Db& db, store_gis::Writer& w) {
  {
    sql::Stmt q(db, "SELECT count(*) FROM la_spatialunit su WHERE NOT EXISTS "
                    "(SELECT 1 FROM parcel p WHERE p.spatialunit_id = su.fid)");
    if (!q.step() || q.get_int(0) == 0) return;
  }
  const BatchModel m = load_batch_model(db.path());
  const std::vector<ParcelValuation> values = load_valuations(db.path());
  sql::Stmt su(db, "SELECT su.fid FROM la_spatialunit su WHERE parcel_id=? AND NOT EXISTS "
                   "(SELECT 1 FROM parcel p WHERE p.spatialunit_id = su.fid)");
  sql::Stmt building(db, "SELECT fid FROM building WHERE building_id=?");
  sql::Stmt element(db, "SELECT fid FROM building_element WHERE building_fid=? AND element_index=?");
  auto fid_of = [](sql::Stmt& q) {
    const std::int64_t fid = q.step() ? q.get_int(0) : 0;
    q.reset();
    return fid;
  };
  sql::Transaction tx(db);
  for (size_t i = 0; i < m.parcels.size(); ++i) {
    const Parcel& p = m.parcels[i];
    const std::int64_t unit = fid_of(su.bind(p.id));
    if (unit == 0) continue;  // has its row
    ParcelValuation v;
    for (const ParcelValuation& x : values)
      if (x.parcel_id == p.id) v = x;
    w.parcel(p, unit, m.results[i], v);
    for (const Building& b : m.results[i].buildings) {
      const std::int64_t bfid = fid_of(building.bind(b.id));
      w.building(b, bfid, p.id, m.frame.origin, v);
      for (int k = 0; k < int(b.elements.size()); ++k)
        if (b.elements[size_t(k)].type == ElementType::Roof)
          w.roof_part(b.elements[size_t(k)], fid_of(element.bind(bfid).bind(k)), k, b.id, p.id, m.frame.origin);
    }
  }
  tx.commit();
}

}  // namespace

// ---------------------------------------------------------------------------

struct Store::Impl {
  sql::Db db;
  int srs = 0;
  std::int64_t run_id = 0;
  // Prepared once: writing a parcel is a handful of bound inserts.
  sql::Stmt del_baunit, ins_baunit, ins_rrr, ins_su, ins_building,
      ins_element, ins_vu, ins_val, ins_item, upsert_job, pending_job, done_job, parcel_lock;
  store_gis::Writer gis;  // the 2D layers, written beside the 3D rows
  store_lods::Writer lods;  // attributes and lower LoDs
  store_meshes::Writer meshes;  // batch --mesh ladders

  void prepare();
  void insert_run(const std::string& params_json, const std::vector<InputFile>& inputs, const LocalFrame& frame,
                  const std::string& shard);
  void add_columns(const std::vector<Parcel>& parcels);
  void insert_pending(const std::vector<Parcel>& parcels, const std::vector<std::string>& keys);
  void refuse_other_runs(const Claim& claim);
  std::int64_t write_building(const Building& b, int index, std::int64_t su, const Vec3& off,
                              const std::string& parcel_id, const ParcelValuation& v,
                              std::map<std::pair<std::string, int>, std::int64_t>& elements);
  void write_valuation(const ParcelValuation& v, std::int64_t baunit, std::int64_t su,
                       const std::map<std::pair<std::string, int>, std::int64_t>& elements);
};

Store::Store() = default;
Store::~Store() { close(); }

bool Store::is_open() const { return impl_ != nullptr; }
int Store::srs_id() const { return impl_ ? impl_->srs : 0; }

void Store::open(const std::string& path, const std::string& crs_wkt, int epsg) {
  close();
  auto impl = std::make_unique<Impl>();
  impl->db = sql::Db(path, false);
  if (!impl->db.postgres()) {
    gpkg_rtree::register_functions(impl->db);  // before any statement compiles the index triggers
    // Header fields first, while still in rollback-journal mode: they land in the
    // main file at once, where validate_gpkg.py reads them.
    impl->db.exec("PRAGMA application_id = 1196444487; PRAGMA user_version = 10300;");
    impl->db.exec("PRAGMA journal_mode = WAL; PRAGMA synchronous = NORMAL; PRAGMA foreign_keys = ON;");
  }
  impl->srs = store_schema::create(impl->db, crs_wkt, epsg);
  impl->prepare();
  impl->gis = store_gis::Writer(impl->db, impl->srs);
  backfill_gis(impl->db, impl->gis);  // a store of an earlier version
  impl_ = std::move(impl);
}

void Store::Impl::prepare() {
  const std::string now = store_schema::now(db);
  del_baunit = sql::Stmt(db, "DELETE FROM la_baunit WHERE parcel_id=?");
  using namespace store_columns;
  ins_baunit = sql::Stmt(db, insert_sql(kBaunit));
  ins_rrr = sql::Stmt(db, insert_sql(kRrr, {{"party_id", "NULL"}, {"rrr_class", "'right'"}, {"share", "1.0"}}));
  ins_su = sql::Stmt(db, insert_sql(kSpatialUnit));
  ins_building = sql::Stmt(db, insert_sql(kBuilding));
  ins_element = sql::Stmt(db, insert_sql(kElement));
  ins_vu = sql::Stmt(db, insert_sql(kValuationUnit));
  ins_val = sql::Stmt(db, insert_sql(kValuation, {{"approach", "'cost'"}, {"valued", now}}));
  ins_item = sql::Stmt(db, insert_sql(kCostItem));
  upsert_job = sql::Stmt(db, upsert_sql(kJob, "parcel_id", {{"updated", now}}));
  // A pending row keeps what an earlier run measured until the parcel is written again.
  pending_job = sql::Stmt(
      db,
      insert_sql(kJob, {{"status", "'pending'"}, {"reason", "NULL"}, {"roof_points", "NULL"}, {"wall_points", "NULL"},
                        {"timings", "NULL"}, {"updated", now}}) +
      " ON CONFLICT(parcel_id) DO UPDATE SET "
      "status='pending', reason=NULL, layer_index=excluded.layer_index, "
      "inputs_key=excluded.inputs_key, run_id=excluded.run_id, updated=excluded.updated "
      "WHERE parcel_job.status NOT IN ('ok','empty') OR parcel_job.inputs_key IS DISTINCT FROM excluded.inputs_key");
  done_job = sql::Stmt(db,
                       "SELECT 1 FROM parcel_job WHERE parcel_id=? AND inputs_key=? AND "
                       "status IN ('ok','empty')");
  lods = store_lods::Writer(db);
  meshes = store_meshes::Writer(db);
  if (db.postgres()) parcel_lock = sql::Stmt(db, "SELECT pg_advisory_xact_lock(3, hashtext(?))");
}

std::int64_t Store::begin_run(const std::string& params_json, const std::vector<InputFile>& inputs,
                              const LocalFrame& frame, const std::string& shard) {
  if (!impl_) throw InputError("store", "begin_run before open");
  sql::Transaction tx(impl_->db);
  impl_->insert_run(params_json, inputs, frame, shard);
  tx.commit();
  return impl_->run_id;
}

void Store::Impl::insert_run(const std::string& params_json, const std::vector<InputFile>& inputs,
                             const LocalFrame& frame, const std::string& shard) {
  // The parcel counts are written when the run ends.
  sql::Stmt run(db, store_columns::insert_sql(store_columns::kRun, {{"started", store_schema::now(db)},
                                                                    {"finished", "NULL"},
                                                                    {"parcels_ok", "NULL"},
                                                                    {"parcels_empty", "NULL"},
                                                                    {"parcels_failed", "NULL"},
                                                                    {"parcels_suspect", "NULL"}}));
  run.bind(std::string("cadastre3d ") + C3D_VERSION).bind(params_json).bind(srs)
      .bind(frame.origin.x()).bind(frame.origin.y()).bind(frame.origin.z());
  if (shard.empty()) run.bind_null();
  else run.bind(shard);
  run.run();
  run_id = db.last_id();
  sql::Stmt in(db, store_columns::insert_sql(store_columns::kRunInput));
  for (const auto& f : inputs) {
    in.bind(run_id).bind(f.path).bind(f.sha256).bind(f.bytes);
    if (f.role.empty()) in.bind_null();  // a merged record from before roles
    else in.bind(f.role);
    in.run();
  }
}

void Store::mark_pending(const std::vector<Parcel>& parcels, const std::vector<std::string>& keys) {
  if (!impl_) throw InputError("store", "mark_pending before open");
  impl_->add_columns(parcels);
  sql::Transaction tx(impl_->db);
  impl_->insert_pending(parcels, keys);
  tx.commit();
}

// The parcel layer's own fields become columns first, in a transaction of
// their own: an ALTER inside a parcel's would wait on other writers.
void Store::Impl::add_columns(const std::vector<Parcel>& parcels) {
  sql::Transaction tx(db);
  gis.add_input_columns(parcels);
  tx.commit();
}

void Store::Impl::insert_pending(const std::vector<Parcel>& parcels, const std::vector<std::string>& keys) {
  for (size_t i = 0; i < parcels.size(); ++i) {
    auto& s = pending_job;
    s.bind(parcels[i].id).bind(parcels[i].index).bind(i < keys.size() ? keys[i] : "");
    if (run_id) s.bind(run_id);
    else s.bind_null();
    s.run();
  }
}

// Refuses a store holding a parcel of `checked` (every parcel when empty)
// under a key the run does not have: another data set, other settings or
// other inputs. A rerun of the same run (or a killed one's leftovers) passes.
void Store::Impl::refuse_other_runs(const Claim& c) {
  const std::set<std::string> ours(c.run_keys.begin(), c.run_keys.end()), ids(c.checked.begin(), c.checked.end());
  size_t other = 0;
  sql::Stmt jobs(db, "SELECT parcel_id, inputs_key FROM parcel_job");
  while (jobs.step())
    if (ids.empty() || ids.count(jobs.get_text(0))) other += ours.count(jobs.get_text(1)) == 0;
  if (other > 0)
    throw InputError(sql::display_name(db.path()),
                     "holds " + std::to_string(other) +
                         " parcel(s) of another run (other inputs, settings or parcels); --resume keeps them "
                         "and adds this run's, --overwrite replaces the folder's outputs, or choose another --out");
}

std::int64_t Store::claim_run(const Claim& c) {
  if (!impl_) throw InputError("store", "claim_run before open");
  impl_->add_columns(c.parcels);
  sql::Transaction tx(impl_->db);
  if (impl_->db.postgres())  // released at commit; SQLite's BEGIN IMMEDIATE holds its write lock
    impl_->db.exec("SELECT pg_advisory_xact_lock(hashtext('cadastre3d: a run claims its parcels'))");
  if (c.refuse_others) impl_->refuse_other_runs(c);
  impl_->insert_run(c.params_json, c.inputs, c.frame, c.shard);
  impl_->insert_pending(c.parcels, c.keys);
  tx.commit();
  return impl_->run_id;
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
    const Building& b, int index, std::int64_t su, const Vec3& off, const std::string& parcel_id,
    const ParcelValuation& v, std::map<std::pair<std::string, int>, std::int64_t>& elements) {
  std::string kind;
  BuildingTotals t = totals(b);
  auto& s = ins_building;
  s.bind_blob(gpkg_faces_blob(building_geometry(b, &kind), off, srs)).bind(su).bind(b.id)
      .bind(index).bind(kind).bind(b.volume).bind(b.eave_height).bind(b.ridge_height)
      .bind(b.terrain_z + off.z()).bind(b.storeys).bind(b.solid_valid ? 1 : 0)
      .bind(b.solid_problem).bind(to_string(b.lod)).bind(b.lod_note).bind(t.roof).bind(t.roof_plan).bind(t.wall).bind(t.party_wall)
      .bind(t.ground).bind(t.outer_ceiling);
  for (const Deviation* d : {&b.roof_deviation, &b.wall_deviation})
    s.bind(d->n).bind(d->max).bind(d->mean).bind(d->std).bind(d->rmse);
  s.bind(exact_shape_json(b.exact, off));
  const MeshRefinement& m = b.refinement;
  if (m.triangles > 0) s.bind(m.triangles);
  else s.bind_null();
  s.bind(m.snapped_share).bind(m.chamfer_before_m).bind(m.chamfer_after_m).bind(m.cloud_before_m).bind(m.cloud_after_m).run();
  std::int64_t fid = db.last_id();
  gis.building(b, fid, parcel_id, off, v);
  lods.write(fid, b, off, srs);
  meshes.write(fid, b);
  for (int i = 0; i < int(b.elements.size()); ++i) {
    const Element& e = b.elements[size_t(i)];
    ins_element.bind_blob(gpkg_faces_blob(e.faces, off, srs)).bind(fid).bind(i)
        .bind(to_string(e.type)).bind(e.area).bind(e.plan_area).bind(e.slope_deg)
        .bind(e.azimuth_deg).bind(e.sigma_area).bind(e.support_points).bind(e.rmse)
        .bind(to_string(e.evidence)).bind(e.sigma_shared).run();
    elements[{b.id, i}] = db.last_id();
    if (e.type == ElementType::Roof) gis.roof_part(e, db.last_id(), i, b.id, parcel_id, off);
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
  // Two writers of one parcel in a shared database take turns; the second then sees the first's rows.
  if (m.db.postgres()) m.parcel_lock.bind(parcel.id).run();
  m.del_baunit.bind(parcel.id).run();  // cascades to every row of this parcel
  m.ins_baunit.bind(parcel.id).bind("parcel " + parcel.id).bind("basicPropertyUnit").run();
  std::int64_t baunit = m.db.last_id();
  // The parcel layer names no owner: the right has no party (docs/design.md).
  m.ins_rrr.bind(baunit);
  if (const char* code = store_schema::ladm_right_type(parcel.right_type)) m.ins_rrr.bind(code);
  else m.ins_rrr.bind_null();
  m.ins_rrr.bind(parcel.right_type).run();
  m.ins_su.bind_blob(gpkg_multipolygon_blob(parcel.shape, m.srs)).bind(baunit).bind(parcel.id)
      .bind(parcel.index).bind(parcel.official_area).bind(area(parcel.shape))
      .bind(parcel.repair_note).run();
  std::int64_t su = m.db.last_id();
  m.gis.parcel(parcel, su, result, valuation);
  std::map<std::pair<std::string, int>, std::int64_t> elements;
  for (int k = 0; k < int(result.buildings.size()); ++k)
    m.write_building(result.buildings[size_t(k)], k, su, frame.origin, parcel.id, valuation, elements);
  m.write_valuation(valuation, baunit, su, elements);
  m.upsert_job.bind(parcel.id).bind(parcel.index).bind(to_string(result.status))
      .bind(result.reason).bind(inputs_key);
  if (m.run_id) m.upsert_job.bind(m.run_id);
  else m.upsert_job.bind_null();
  m.upsert_job.bind(result.roof_points).bind(result.wall_points)
      .bind(timings_json(result.timings)).run();
  tx.commit();
}

void Store::end_run(bool finished) {
  if (!impl_) return;
  auto& db = impl_->db;
  sql::Transaction tx(db);
  if (impl_->run_id) {
    sql::Stmt upd(db, std::string("UPDATE run SET finished=") + (finished ? store_schema::now(db) : "NULL") +
                          ", parcels_ok=(SELECT count(*) FROM parcel_job WHERE run_id=?1 AND status='ok'),"
                          " parcels_empty=(SELECT count(*) FROM parcel_job WHERE run_id=?1 AND status='empty'),"
                          " parcels_failed=(SELECT count(*) FROM parcel_job WHERE run_id=?1 AND status='failed'),"
                          " parcels_suspect=(SELECT count(*) FROM parcel_job WHERE run_id=?1 AND status='suspect')"
                          " WHERE fid=?1");
    upd.bind(impl_->run_id).run();
  }
  store_schema::update_extents(db);
  store_styles::update(db);
  tx.commit();
  impl_->run_id = 0;
}

void mark_run_finished(const std::string& path, std::int64_t run_id) {
  sql::Db db(path, false);
  db.exec("UPDATE run SET finished=" + store_schema::now(db) + " WHERE fid=" +
          (run_id > 0 ? std::to_string(run_id) : "(SELECT max(fid) FROM run)"));
}

void Store::close() {
  if (!impl_) return;
  // Fold the WAL back so the .gpkg alone is complete for copying / QGIS, and
  // leave WAL mode where no other writer has the file open: a WAL-mode file
  // cannot be read from read-only media (the next writer turns WAL on again).
  if (sqlite3* h = impl_->db.get()) {
    sqlite3_wal_checkpoint_v2(h, nullptr, SQLITE_CHECKPOINT_TRUNCATE, nullptr, nullptr);
    sqlite3_busy_timeout(h, 0);
    sqlite3_exec(h, "PRAGMA journal_mode = DELETE", nullptr, nullptr, nullptr);
  }
  impl_.reset();
}

}  // namespace c3d
