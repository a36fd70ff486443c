#pragma once
// The LADM-style cadastre store: one GeoPackage (OUT/cadastre.gpkg) written with
// SQLite directly. Tables use ISO 19152 names (la_party, la_baunit, la_rrr,
// la_spatialunit, vm_valuationunit, vm_valuation) plus building,
// building_element, vm_cost_item, run, run_input and parcel_job. Geometries are
// GeoPackage blobs in world coordinates (parcels 2D MultiPolygon, buildings and
// elements MultiPolygonZ), so QGIS and GDAL open every layer.
//
// Each parcel is written in one transaction that first deletes that parcel's
// earlier rows (foreign keys cascade): a rerun is idempotent and a crash leaves
// whole parcels only.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/io/sha256.h"
#include "core/types.h"
#include "valuation/valuation_types.h"

namespace c3d {

struct RunRecord {
  std::int64_t id = 0;
  std::string tool_version, parameters, started, finished;  // parameters: JSON text
  int epsg = 0;
  Vec3 origin = Vec3::Zero();
  int parcels_ok = 0, parcels_empty = 0, parcels_failed = 0, parcels_suspect = 0;
  std::vector<InputFile> inputs;
  std::string shard;  // "K/N" for a shard's run (--shard), else ""
};

struct JobRecord {
  std::string parcel_id;
  int layer_index = 0;
  std::optional<ParcelStatus> status;  // none while pending
  std::string reason, inputs_key, updated;
  std::int64_t run_id = 0;
};

class Store {
 public:
  Store();
  ~Store();
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  // Creates the GeoPackage (or opens an existing one, whose CRS must match).
  // epsg 0 with a WKT registers a custom CRS; both empty: undefined Cartesian.
  void open(const std::string& path, const std::string& crs_wkt, int epsg);
  // Starts a run record: parameters (JSON text), input files (with their
  // SHA-256), the batch's local frame, the shard ("K/N"; "" for a whole run).
  // Returns the run id.
  std::int64_t begin_run(const std::string& params_json, const std::vector<InputFile>& inputs,
                         const LocalFrame& frame = {}, const std::string& shard = "");
  // Marks parcels pending (one transaction) unless already done with the same key.
  void mark_pending(const std::vector<Parcel>& parcels, const std::vector<std::string>& inputs_keys);
  // begin_run and mark_pending of the run's own parcels in one transaction
  // under the store's run lock (PostgreSQL: an advisory lock; SQLite: its
  // write lock), after refusing a store where another run holds a parcel of
  // `checked` under a key not among `run_keys`: two writers starting at once
  // cannot both pass and then mix their settings.
  struct Claim {
    std::string params_json, shard;
    std::vector<InputFile> inputs;
    LocalFrame frame;
    std::vector<Parcel> parcels;       // the run's own, marked pending
    std::vector<std::string> keys;     // theirs
    bool refuse_others = true;         // false: keep other runs' parcels (--resume)
    std::vector<std::string> checked;  // parcel ids whose jobs must hold a key of run_keys; none: all
    std::vector<std::string> run_keys;  // every key the run has (its whole layer's)
  };
  std::int64_t claim_run(const Claim& claim);
  // True when the parcel was stored ok/empty from the same inputs (for --resume).
  bool parcel_done(const std::string& parcel_id, const std::string& inputs_key);
  // Replaces every row of this parcel in one transaction. Geometry in result is
  // local; frame gives local -> world.
  void write_parcel(const Parcel& parcel, const ParcelResult& result,
                    const ParcelValuation& valuation, const LocalFrame& frame,
                    const std::string& inputs_key = "");
  // Closes the run record (counts; the end time unless !finished, when the
  // caller sets it with mark_run_finished once its outputs are in place) and
  // refreshes layer extents.
  void end_run(bool finished = true);
  void close();
  bool is_open() const;
  int srs_id() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A store location is a GeoPackage path or a PostgreSQL URL
// (postgresql://user@host:port/db, libpq's URI form): the same tables in
// PostGIS, shared by many writers (docs/postgis.md). Every function below
// that takes `path` takes either.
bool is_database_url(const std::string& loc);
// Whether a store is there: the file, or the database's tables.
bool store_exists(const std::string& loc);

// Sets the end time of run `run_id` (0: the store's latest run): a batch
// calls it last, once every output is in place, so a set `finished` means a
// complete output folder. Writers sharing a database each name their own run.
void mark_run_finished(const std::string& path, std::int64_t run_id = 0);

// Everything the report and the exports need, read back from a store alone.
// Parcels in layer order; building geometry in local coordinates of the frame
// of the latest run. Throws InputError when the file is not a Cadastre3D store.
BatchModel load_batch_model(const std::string& path);
// One valuation per parcel, same order as load_batch_model().parcels.
std::vector<ParcelValuation> load_valuations(const std::string& path);
// The same for the parcels of these ids only, in the order given (an id the
// store lacks is left out): a streaming reader takes the store a page at a
// time. A parcel's id (la_spatialunit.parcel_id, the layer's identifier) is
// unique in a store; its layer index is not where writers with different
// parcel selections (--where) share one. Each call reads one snapshot.
BatchModel load_batch_model(const std::string& path, const std::vector<std::string>& parcel_ids);
std::vector<ParcelValuation> load_valuations(const std::string& path, const std::vector<std::string>& parcel_ids);
std::vector<JobRecord> load_jobs(const std::string& path);
std::vector<RunRecord> load_runs(const std::string& path);

}  // namespace c3d
