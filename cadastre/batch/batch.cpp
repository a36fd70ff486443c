#include "cadastre/batch/batch.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <malloc.h>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "cadastre/batch/batch_deviation.h"
#include "cadastre/batch/batch_inputs.h"
#include "cadastre/batch/building_meshes.h"
#include "cadastre/batch/chunks.h"
#include "cadastre/batch/plausibility.h"
#include "cadastre/batch/resume_key.h"
#include "cadastre/batch/scenes.h"
#include "core/log.h"

namespace c3d {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

BatchRun describe_run(const LoadedInputs& in, const BatchInputs& inputs, const Config& cfg,
                      const LocalFrame& frame) {
  BatchRun run;
  run.crs_wkt = in.crs_wkt;
  run.frame = frame;
  run.parameters = run_parameters(cfg);
  run.inputs = describe_inputs(in, inputs);
  run.parcels = &in.layer.parcels;
  run.parcel_keys = parcel_keys(in, inputs, cfg, run.inputs);
  return run;
}

// The parcels to model: the run's (all, or its shard's), or with --resume those the sink lacks.
std::vector<size_t> parcels_to_model(BatchSink& sink, const BatchRun& run, bool resume) {
  std::vector<size_t> todo;
  for (size_t i : run.in_shard)
    if (!resume || !sink.has_parcel(i, run.parcel_keys[i])) todo.push_back(i);
  return todo;
}

// Threads to start: `jobs` (0: one per core), at most kMaxJobsPerCore per core
// (with a warning) and no more than there are parcels.
int job_count(int jobs, size_t parcels) {
  const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
  if (jobs <= 0) jobs = cores;
  if (jobs > kMaxJobsPerCore * cores) {
    log::warn("--jobs " + std::to_string(jobs) + " is more than " + std::to_string(kMaxJobsPerCore) +
              " per core; using " + std::to_string(kMaxJobsPerCore * cores) + " (" + std::to_string(cores) +
              " cores)");
    jobs = kMaxJobsPerCore * cores;
  }
  return int(std::min<size_t>(size_t(jobs), std::max<size_t>(parcels, 1)));
}

// Keeps what glibc holds of freed memory from growing with the parcels a run
// goes through (docs/scale.md, stops 44-45):
// - a thread that finds an arena locked gets one of its own, up to 8 per
//   core, and each keeps what was freed in it: as many arenas as workers;
// - after a large block is freed, glibc raises its mmap threshold to that
//   size (up to 32 MB), so later chunk-sized buffers come from the arenas and
//   stay there between live blocks: a fixed threshold returns every buffer
//   over 4 MB to the system when it is freed.
void bound_malloc(int jobs) {
  mallopt(M_ARENA_MAX, std::max(2, jobs));
  mallopt(M_MMAP_THRESHOLD, 4 << 20);
}

// Parcel i modelled in its own frame, and with [mesh] ladder its buildings
// meshed into out_dir.
ParcelResult modelled_parcel(const SceneSource& scenes, size_t i, const Config& cfg, const std::string& out_dir) {
  const ParcelScene scene = make_scene(scenes, i);
  ParcelResult r = reconstruct_parcel(scene, cfg.reconstruction);
  if (cfg.mesh.ladder)
    mesh_buildings(scene, parcel_frame(scenes.inputs->layer.parcels[i], scenes.frame),
                   {out_dir, dense_method_named(cfg.mesh.method), simplifier_named(cfg.mesh.simplify)}, r);
  return r;
}

// Models the parcels on threads; the sink is written under one lock. The
// first exception (a store write failing, the disk full) stops every worker
// and is rethrown here; the failed parcel's transaction has rolled back.
void model_parcels(const std::vector<size_t>& todo, size_t total, int jobs, const SceneSource& scenes,
                   const Config& cfg, BatchSink& sink, const BatchSettings& settings, BatchReport& report) {
  const auto& parcels = scenes.inputs->layer.parcels;
  std::atomic<size_t> next{0};
  std::mutex sink_mutex;
  std::exception_ptr error;
  auto worker = [&] {
    for (size_t k = next++; k < todo.size(); k = next++) try {
      const size_t i = todo[k];
      const std::string gap = unreachable(*scenes.inputs, i);
      ParcelResult r = gap.empty() ? modelled_parcel(scenes, i, cfg, settings.out_dir)
                                   : failed_parcel(i, parcels[i].id, gap);
      move_result(r, parcel_frame(parcels[i], scenes.frame), scenes.frame);
      check_model(r, scenes.frame.origin.z());
      ParcelValuation v = value_checked(parcels[i], r, cfg.valuation);
      std::lock_guard<std::mutex> lock(sink_mutex);
      if (error) return;
      const auto t_write = Clock::now();
      sink.write_parcel(i, r, v);
      report.timings.sink_s += seconds_since(t_write);
      for (const auto& t : r.timings) report.timings.stages[t.stage] += t.seconds;
      ++report.reconstructed;
      if (r.status == ParcelStatus::Failed) {
        ++report.failed;
        log::error("parcel " + r.parcel_id + " failed: " + r.reason);
      }
      if (r.status == ParcelStatus::Suspect) {
        ++report.suspect;
        log::warn("parcel " + r.parcel_id + " suspect: " + r.reason);
      }
      if (settings.progress) settings.progress("reconstruct", report.reconstructed, total);
    } catch (...) {
      std::lock_guard<std::mutex> lock(sink_mutex);
      if (!error) error = std::current_exception();
      next = todo.size();
      return;
    }
  };
  std::vector<std::thread> pool;
  for (size_t k = 0; k < std::min(size_t(jobs), todo.size()); ++k) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

// Models the to-do parcels a chunk at a time: the chunk's region read from
// the tiles, its scenes, its models to the sink; then it is freed.
void model_chunks(const LoadedInputs& in, const std::vector<size_t>& todo, const LocalFrame& frame,
                  const Config& cfg, BatchSink& sink, const BatchSettings& settings, BatchReport& report) {
  const SceneGeometry geometry = scene_geometry(in.layer, cfg.clip);
  const int jobs = job_count(settings.jobs, todo.size());
  bound_malloc(jobs);
  DensityBlocks density(in.tiles, cfg.classes);
  const double reach = geometry.reach_m + kRegionMarginM;
  const ChunkLimits limits{size_t(cfg.batch.chunk_parcels), double(cfg.batch.chunk_points), reach};
  for (const auto& chunk : spatial_chunks(in.boxes, in.tiles, todo, limits)) {
    const auto t_read = Clock::now();
    const Region region = chunk_region(in.boxes, chunk, reach);
    const RegionPoints points = read_region(in.tiles, region, cfg.classes);
    const Dtm terrain = dtm_window(in, region.box);
    SceneSource scenes = prepare_scenes(in, points, region.box, geometry, frame);
    if (in.dtm_source) scenes.terrain = &terrain;
    scenes.density = density.around(region.box);
    report.timings.stages["read points"] += seconds_since(t_read);
    model_parcels(chunk, todo.size(), jobs, scenes, cfg, sink, settings, report);
    malloc_trim(0);  // the chunk's freed pages back to the system: the next chunk starts from the base
  }
}

}  // namespace

BatchReport run_batch(const BatchInputs& inputs, const Config& cfg, BatchSink& sink,
                      const BatchSettings& settings) {
  const auto t_start = Clock::now();
  if (cfg.mesh.ladder && settings.out_dir.empty())
    throw std::invalid_argument("run_batch: [mesh] ladder needs BatchSettings::out_dir for its files");
  BatchReport report;
  auto progress = [&](const char* stage, size_t done, size_t total) {
    if (settings.progress) settings.progress(stage, done, total);
  };
  progress("ingest", 0, 3);
  const LoadedInputs in = load_inputs(inputs, cfg, settings.shard);
  progress("ingest", 1, 3);
  report.warnings = in.warnings;
  for (const auto& w : in.warnings) log::warn(w);
  report.parcels = in.layer.parcels.size();
  const LocalFrame frame = frame_of(in.layer);
  progress("ingest", 2, 3);
  BatchRun run = describe_run(in, inputs, cfg, frame);
  run.in_shard = shard_parcels(in.layer.parcels, settings.shard);
  run.shard = to_string(settings.shard);
  report.timings.ingest_s = seconds_since(t_start);
  progress("ingest", 3, 3);
  sink.begin(run);
  const std::vector<size_t> todo = parcels_to_model(sink, run, settings.resume);
  model_chunks(in, todo, frame, cfg, sink, settings, report);
  progress("store", 0, 1);
  const SinkCounts held = sink.end();
  report.held = held.parcels;
  report.held_by_status = held.by_status;
  progress("store", 1, 1);
  report.timings.reconstruct_s = seconds_since(t_start) - report.timings.ingest_s;
  progress("deviation", 0, 1);
  // A shard holds part of the models: the whole fit is for a whole run's outputs.
  if (!settings.shard.active()) any_model_deviation(in, cfg, sink, report);
  progress("deviation", 1, 1);
  return report;
}

}  // namespace c3d
