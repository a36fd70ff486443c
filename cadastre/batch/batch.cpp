#include "cadastre/batch/batch.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <filesystem>
#include <mutex>
#include <thread>

#include "cadastre/batch/batch_inputs.h"
#include "cadastre/batch/plausibility.h"
#include "cadastre/batch/resume_key.h"
#include "cadastre/batch/scenes.h"
#include "core/evaluate/evaluate.h"
#include "core/log.h"

namespace c3d {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// A parcel source that is no file (a database, a folder, a /vsizip/ path) is
// known by what was read from it.
InputFile describe_parcel_source(const std::string& source, const ParcelLayer& layer) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(source, ec)) return describe_input_file(source);
  std::string s = source;
  for (const Parcel& p : layer.parcels) {
    s += "|" + p.id + "|" + p.right_type + "|" + std::to_string(p.official_area);
    for (const auto& poly : p.shape)
      for (const auto& v : poly.outer) s += "|" + std::to_string(v.x()) + "," + std::to_string(v.y());
  }
  return {source, sha256_hex(s), -1};
}

BatchRun describe_run(const LoadedInputs& in, const BatchInputs& inputs, const Config& cfg,
                      const LocalFrame& frame) {
  BatchRun run;
  run.crs_wkt = in.crs_wkt;
  run.frame = frame;
  run.parameters = run_parameters(cfg);
  for (const auto& f : inputs.files())
    run.inputs.push_back(f == inputs.parcels ? describe_parcel_source(f, in.layer) : describe_input_file(f));
  run.parcels = &in.layer.parcels;
  const std::string key = run_key(cfg, run.inputs);
  for (const auto& p : in.layer.parcels) run.parcel_keys.push_back(parcel_key(key, p));
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

// Models the parcels on threads; the sink is written under one lock. The
// first exception (a store write failing, the disk full) stops every worker
// and is rethrown here; the failed parcel's transaction has rolled back.
void model_parcels(const std::vector<size_t>& todo, const SceneSource& scenes, const Config& cfg,
                   BatchSink& sink, const BatchSettings& settings, BatchReport& report) {
  const auto& parcels = scenes.inputs->layer.parcels;
  std::atomic<size_t> next{0};
  std::mutex sink_mutex;
  std::exception_ptr error;
  auto worker = [&] {
    for (size_t k = next++; k < todo.size(); k = next++) try {
      const size_t i = todo[k];
      const std::string gap = unreachable(*scenes.inputs, i);
      ParcelResult r = gap.empty() ? reconstruct_parcel(make_scene(scenes, i), cfg.reconstruction)
                                   : failed_parcel(i, parcels[i].id, gap);
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
      if (settings.progress) settings.progress("reconstruct", report.reconstructed, todo.size());
    } catch (...) {
      std::lock_guard<std::mutex> lock(sink_mutex);
      if (!error) error = std::current_exception();
      next = todo.size();
      return;
    }
  };
  std::vector<std::thread> pool;
  const int jobs = job_count(settings.jobs, todo.size());
  for (int k = 0; k < jobs; ++k) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

std::vector<Face> world_faces(const BatchModel& model, const std::vector<ElementType>& types) {
  std::vector<Face> out;
  for (const auto& r : model.results)
    for (const auto& b : r.buildings)
      for (Face f : faces_of(b, types)) {
        for (auto& v : f.ring) v = model.frame.to_world(v);
        for (auto& h : f.holes)
          for (auto& v : h) v = model.frame.to_world(v);
        out.push_back(std::move(f));
      }
  return out;
}

std::vector<double> distances_to(const std::vector<Vec3>& points, const std::vector<Face>& faces) {
  const FaceIndex index(faces);
  std::vector<double> d;
  if (index.empty()) return d;
  for (const auto& hit : index.nearest(points)) d.push_back(hit.distance);
  return d;
}

std::vector<Ring3> footprint_rings(const BatchModel& model) {
  std::vector<Ring3> rings;
  for (const Face& f : world_faces(model, {ElementType::Ground})) rings.push_back(f.ring);
  return rings;
}

// Every roof point inside a parcel against the nearest roof of any model, and
// every wall point within kWallPointReachM of a parcel against the nearest
// wall; then the same by the judge's rulers.
void any_model_deviation(const LoadedInputs& in, const ClipParams& clip,
                         const SceneSource& scenes, BatchReport& report) {
  const std::vector<Face> roofs = world_faces(report.model, {ElementType::Roof});
  const std::vector<Face> walls = world_faces(report.model, {ElementType::Wall, ElementType::PartyWall});
  // inside() reads the parcels as they are: no buffer to build.
  ClipParams exact = clip;
  exact.overhang_buffer_m = 0;
  const ParcelClipper clipper(in.layer, exact);
  const ParcelClipper::IndexLists& roof_lists = scenes.roof_lists;
  std::vector<Vec3> roof_in;
  std::vector<char> taken(in.roof.size(), 0);
  for (size_t k = 0; k < roof_lists.size(); ++k)
    for (size_t i : roof_lists[k])
      if (!taken[i] && clipper.inside(k, in.roof[i].x(), in.roof[i].y())) {
        taken[i] = 1;
        roof_in.push_back(in.roof[i]);
      }
  // The scenes' wall lists reach kWallPointReachM unless the overhang buffer reaches further.
  ClipParams near = clip;
  near.overhang_buffer_m = kWallPointReachM;
  const bool scenes_reach = clip.overhang_buffer_m <= kWallPointReachM;
  const ParcelClipper::IndexLists wall_lists =
      scenes_reach ? ParcelClipper::IndexLists{} : ParcelClipper(in.layer, near).clip(in.wall);
  std::vector<Vec3> wall_near;
  std::vector<char> seen(in.wall.size(), 0);
  for (const auto& list : scenes_reach ? scenes.wall_lists : wall_lists)
    for (size_t k : list)
      if (!seen[k]) seen[k] = 1, wall_near.push_back(in.wall[k]);
  const std::vector<double> roof_d = distances_to(roof_in, roofs);
  if (!roofs.empty()) report.any_model_roof = deviation(roof_d), report.roof_ruler = ruler_figures(roof_d);
  if (walls.empty()) return;
  const std::vector<double> wall_d = distances_to(wall_near, walls);
  report.any_model_wall = deviation(wall_d);
  if (wall_d.empty()) return;  // no wall face with an area
  const std::vector<char> of_building = near_rings(wall_near, footprint_rings(report.model), kFootprintReachM);
  std::vector<double> measured;  // the wall points of modelled buildings
  for (size_t k = 0; k < wall_near.size(); ++k)
    if (of_building[k]) measured.push_back(wall_d[k]);
  report.wall_ruler = ruler_figures(measured);
  if (!wall_near.empty()) report.wall_points_measured = double(measured.size()) / double(wall_near.size());
}

}  // namespace

BatchReport run_batch(const BatchInputs& inputs, const Config& cfg, BatchSink& sink,
                      const BatchSettings& settings) {
  const auto t_start = Clock::now();
  BatchReport report;
  auto progress = [&](const char* stage, size_t done, size_t total) {
    if (settings.progress) settings.progress(stage, done, total);
  };
  progress("ingest", 0, 3);
  const LoadedInputs in = load_inputs(inputs, cfg);
  progress("ingest", 1, 3);
  report.warnings = in.warnings;
  for (const auto& w : in.warnings) log::warn(w);
  report.parcels = in.layer.parcels.size();
  const LocalFrame frame = frame_of(in.layer);
  const SceneSource scenes = prepare_scenes(in, cfg.clip, frame);
  report.timings.ingest_s = seconds_since(t_start);
  progress("ingest", 2, 3);

  BatchRun run = describe_run(in, inputs, cfg, frame);
  run.in_shard = shard_parcels(in.layer.parcels, settings.shard);
  run.shard = to_string(settings.shard);
  progress("ingest", 3, 3);
  sink.begin(run);
  const std::vector<size_t> todo = parcels_to_model(sink, run, settings.resume);
  model_parcels(todo, scenes, cfg, sink, settings, report);
  progress("store", 0, 1);
  report.model = sink.end();
  progress("store", 1, 1);
  report.timings.reconstruct_s = seconds_since(t_start) - report.timings.ingest_s;
  progress("deviation", 0, 1);
  // A shard holds part of the models: the whole fit is for a whole run's outputs.
  if (!settings.shard.active()) any_model_deviation(in, cfg.clip, scenes, report);
  progress("deviation", 1, 1);
  return report;
}

}  // namespace c3d
