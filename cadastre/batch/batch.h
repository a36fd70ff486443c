#pragma once
// The parcel batch as a library call: inputs and a configuration in, one
// result per parcel out to a sink. The CLI, the tests and a shard runner all
// run a batch through run_batch; the GeoPackage store is one sink of many.
//
//   BatchInputs in{{"cloud.las"}, {}, "parcels.gpkg", "dtm.tif"};
//   StoreSink sink("out/cadastre.gpkg");
//   BatchReport r = run_batch(in, default_config(), sink);  // the models are in the store
//   write_outputs(r, sink.path(), "out", cfg, {"cityjson"});
//   mark_run_finished(sink.path());
#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "cadastre/batch/shard.h"
#include "cadastre/parcels.h"
#include "core/config/config.h"
#include "core/evaluate/ruler.h"
#include "core/io/sha256.h"
#include "core/types.h"
#include "valuation/valuation_types.h"

namespace c3d {

// The files a batch reads. Clouds hold classified points (config [classes]);
// walls hold wall points only (a terrestrial scanner); no DTM: one is built
// from the ground-class points.
struct BatchInputs {
  std::vector<std::string> clouds;
  std::vector<std::string> walls;
  std::string parcels;  // any OGR vector source: a file, folder or connection string
  std::string dtm;      // any GDAL raster; may be empty
  // A point classifier model (core/classify): when set, every --cloud is
  // classified before clipping and its own classes are replaced; empty: none.
  std::string classifier_model;
  // Last, so that an initialiser {clouds, walls, parcels, dtm} keeps its meaning:
  ParcelSelection parcel_selection;  // --layer, --where, --bbox
  std::string crs;  // the working CRS the user names (docs/inputs.md); empty: chosen by the policy
  std::string tile_index;  // where tiles' decoded extents are kept (tile_extents.h); empty: none
};

// What each input file is to a run, as its record names it (run_input.role):
// the --cloud, --walls, --parcels, --dtm and classifier model files.
namespace input_role {
constexpr char kCloud[] = "cloud", kWalls[] = "walls", kParcels[] = "parcels", kDtm[] = "dtm",
               kClassifier[] = "classifier";
}  // namespace input_role

// How the batch runs; none of it changes a result.
struct BatchSettings {
  int jobs = 0;         // parallel parcels; 0: all cores; more than kMaxJobsPerCore per core: clamped
  bool resume = false;  // skip parcels the sink already holds from the same key
  Shard shard;          // --shard K/N: model and store only shard K's parcels (cadastre/batch/shard.h)
  // Where the files beside the store go (OUT): the mesh ladders of config
  // [mesh] ladder (cadastre/batch/building_meshes.h); required with it.
  std::string out_dir;
  // Stage "ingest" (steps: inputs read and the tiles surveyed, frame, inputs hashed), "reconstruct" (after
  // each parcel modelled and stored), "store" (every parcel read back, one
  // step), "deviation" (one step).
  std::function<void(const char* stage, size_t done, size_t total)> progress;
};

// More threads than this per core only add memory and contention.
constexpr int kMaxJobsPerCore = 4;

// What a sink learns before the first parcel.
struct BatchRun {
  std::string crs_wkt;
  LocalFrame frame;                       // local = world - frame.origin
  std::string parameters;                 // the effective configuration, JSON text
  std::vector<InputFile> inputs;          // every input file with its SHA-256 (read once)
  const std::vector<Parcel>* parcels = nullptr;  // the layer, world coordinates
  std::vector<std::string> parcel_keys;   // per parcel: what its result depends on (resume key)
  std::vector<size_t> in_shard;           // layer positions this run models: all, or its shard's
  std::string shard;                      // "K/N", or "" when not sharded
};

// What a sink holds after a run, resumed parcels (and another run's kept
// with --resume) included: how many, by status (index: ParcelStatus).
struct SinkCounts {
  size_t parcels = 0;
  std::array<size_t, 4> by_status{};
};

// Where results go. Calls come from one thread at a time.
class BatchSink {
 public:
  virtual ~BatchSink() = default;
  virtual void begin(const BatchRun& run) = 0;
  // True when the sink holds parcel i's result from the same key (--resume).
  virtual bool has_parcel(size_t i, const std::string& key) = 0;
  virtual void write_parcel(size_t i, const ParcelResult& result, const ParcelValuation& valuation) = 0;
  // Every parcel is written (a store closes); what the sink now holds.
  virtual SinkCounts end() = 0;
  // After end(): the models of the parcels of these layer indices as the sink
  // holds them, resumed ones included, in layer order (none for a parcel it
  // lacks). The batch reads them a chunk at a time, never all at once.
  virtual BatchModel models(const std::vector<int>& layer_indices) = 0;
};

struct BatchTimings {
  double ingest_s = 0, reconstruct_s = 0, sink_s = 0;
  std::map<std::string, double> stages;  // summed over parcels (CPU seconds)
};

struct BatchReport {
  BatchTimings timings;
  std::vector<std::string> warnings;  // about the inputs (also logged)
  size_t parcels = 0, reconstructed = 0, failed = 0;  // failed among the reconstructed
  size_t suspect = 0;  // among the reconstructed: modelled outside the plausible bounds
  // Every roof point inside any parcel against the nearest roof of any model,
  // and every wall point within kWallPointReachM of a parcel against the
  // nearest wall: the models' fit, free of which parcel a point counted for.
  Deviation any_model_roof, any_model_wall;
  // The same points by the shared judge's rulers (core/evaluate/ruler.h): the
  // roof points inside the parcels, and the wall points of modelled buildings
  // (within kFootprintReachM of a footprint edge), with their share.
  RulerFigures roof_ruler, wall_ruler;
  double wall_points_measured = 0;  // share of the wall points near the parcels the wall ruler measures
  // Why the whole-run fit above was not computed (a merge without the batch's
  // inputs: cadastre/batch/run_fit.h); "" when it was.
  std::string fit_missing;
  // The parcels the sink holds after the run (SinkCounts), by status (index: ParcelStatus).
  size_t held = 0;
  std::array<size_t, 4> held_by_status{};
};

// Runs the batch. Bad inputs throw InputError naming the file; a parcel that
// cannot be modelled is written `failed` with its reason and the batch goes on.
BatchReport run_batch(const BatchInputs& inputs, const Config& cfg, BatchSink& sink,
                      const BatchSettings& settings = {});

}  // namespace c3d
