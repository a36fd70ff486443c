#include "cli/batch.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <thread>
#include <tuple>

#include "cadastre/clip.h"
#include "cadastre/parcels.h"
#include "core/io/sha256.h"
#include "cadastre/store.h"
#include "cli/commands.h"
#include "cli/outputs.h"
#include "cli/progress.h"
#include "core/config/config.h"
#include "core/io/crs.h"
#include "core/io/dtm_io.h"
#include "core/error.h"
#include "core/evaluate/evaluate.h"
#include "core/geometry/polygon_ops.h"
#include "core/geometry/geometry.h"
#include "core/io/point_io.h"
#include "core/reconstruct/ownership/ownership.h"
#include "core/reconstruct/reconstruct.h"
#include "valuation/valuation.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace c3d::cli {
namespace {

constexpr double kOwnershipContextM = 1.5;

struct Inputs {
  Config cfg;
  ParcelLayer layer;
  Dtm dtm;
  std::vector<Vec3> roof, wall;  // world coordinates
  std::string crs_wkt;
  std::vector<std::string> warnings;
};

bool has_class(const std::vector<int>& set, int c) {
  return std::find(set.begin(), set.end(), c) != set.end();
}

void split_classes(const PointCloud& cloud, const ClassMapping& m, Inputs& in,
                   std::vector<Vec3>& ground) {
  if (cloud.classes.empty()) {  // an unclassified cloud is taken as roof points
    in.roof.insert(in.roof.end(), cloud.points.begin(), cloud.points.end());
    in.warnings.push_back(cloud.source + ": no classification, all points taken as roof");
    return;
  }
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    int c = cloud.classes[i];
    if (has_class(m.roof, c)) in.roof.push_back(cloud.points[i]);
    else if (has_class(m.wall, c)) in.wall.push_back(cloud.points[i]);
    else if (has_class(m.ground, c)) ground.push_back(cloud.points[i]);
  }
}

Inputs load_inputs(const BatchOptions& opt) {
  Inputs in;
  in.cfg = opt.config.empty() ? default_config() : load_config(opt.config);
  in.layer = read_parcels(opt.parcels, in.cfg.fields, &in.warnings);
  std::vector<PointCloud> clouds;
  for (const auto& f : opt.clouds) clouds.push_back(read_point_cloud(f));
  size_t n_class_clouds = clouds.size();
  for (const auto& f : opt.walls) clouds.push_back(read_point_cloud(f));
  bool have_dtm = !opt.dtm.empty();
  if (have_dtm) in.dtm = read_dtm(opt.dtm);
  auto rec = reconcile_crs(in.layer, clouds, have_dtm ? &in.dtm : nullptr);
  in.crs_wkt = rec.crs_wkt;
  in.warnings.insert(in.warnings.end(), rec.warnings.begin(), rec.warnings.end());
  std::vector<Vec3> ground;
  for (size_t i = 0; i < clouds.size(); ++i) {
    if (i < n_class_clouds) {
      split_classes(clouds[i], in.cfg.classes, in, ground);
    } else {
      in.wall.insert(in.wall.end(), clouds[i].points.begin(), clouds[i].points.end());
    }
    clouds[i].points.clear();
    clouds[i].points.shrink_to_fit();
  }
  if (!have_dtm) {
    if (ground.empty())
      throw InputError("--dtm", "no DTM given and no ground-class points to build one from");
    in.dtm = dtm_from_points(ground, in.crs_wkt, 1.0, DtmCell::Min, "ground-class points");
  }
  check_dtm_covers(in.dtm, in.layer);
  if (in.roof.empty() && in.wall.empty())
    throw InputError(opt.clouds.empty() ? opt.parcels : opt.clouds.front(),
                     "no roof or wall points (check the class mapping)");
  return in;
}

LocalFrame make_frame(const ParcelLayer& layer) {
  Vec2 lo(1e300, 1e300);
  for (const auto& p : layer.parcels)
    for (const auto& poly : p.shape)
      for (const auto& v : poly.outer) lo = lo.cwiseMin(v);
  LocalFrame f;
  f.origin = Vec3(std::floor(lo.x() / 10) * 10, std::floor(lo.y() / 10) * 10, 0.0);
  return f;
}

MultiPolygon2 to_local(const MultiPolygon2& mp, const LocalFrame& f) {
  MultiPolygon2 out = mp;
  for (auto& p : out) {
    for (auto& v : p.outer) v = f.to_local(v);
    for (auto& h : p.holes)
      for (auto& v : h) v = f.to_local(v);
  }
  return out;
}

std::pair<Vec2, Vec2> bbox(const MultiPolygon2& mp) {
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& p : mp)
    for (const auto& v : p.outer) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return {lo, hi};
}

// Parcels whose buffered boxes overlap: the candidates for shared roofs.
std::vector<std::vector<int>> neighbour_lists(const ParcelLayer& layer, double reach) {
  size_t n = layer.parcels.size();
  std::vector<std::pair<Vec2, Vec2>> boxes(n);
  for (size_t i = 0; i < n; ++i) boxes[i] = bbox(layer.parcels[i].shape);
  std::vector<int> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = int(i);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return boxes[a].first.x() < boxes[b].first.x(); });
  std::vector<std::vector<int>> out(n);
  for (size_t a = 0; a < n; ++a) {
    int i = order[a];
    for (size_t b = a + 1; b < n; ++b) {
      int j = order[b];
      if (boxes[j].first.x() > boxes[i].second.x() + reach) break;
      if (boxes[j].first.y() > boxes[i].second.y() + reach ||
          boxes[i].first.y() > boxes[j].second.y() + reach)
        continue;
      out[i].push_back(j);
      out[j].push_back(i);
    }
  }
  return out;
}

// One order for one set of points, whatever order the files hold them in:
// region growing and the neighbour searches under it break ties by point
// order, so the same points saved in another order gave other models (a
// shuffle of cimahi.las changed 27 of its 30 buildings). Rows of 2 m cells,
// then coordinates within a cell: points near one another stay near in
// memory, which the searches need to run fast (a plain x-y-z order slowed
// Cimahi's reconstruction from 2.5 to 3.0 s).
std::vector<size_t> in_one_order(std::vector<size_t> idx, const std::vector<Vec3>& pts) {
  auto key = [&](size_t k) {
    const Vec3& p = pts[k];
    return std::make_tuple(std::floor(p.y() / 2.0), std::floor(p.x() / 2.0), p.x(), p.y(), p.z());
  };
  std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return key(a) < key(b); });
  return idx;
}

ParcelScene make_scene(const Inputs& in, const LocalFrame& frame, size_t i,
                       const std::vector<size_t>& roof_idx, const std::vector<size_t>& wall_idx,
                       const std::vector<int>& neighbours, int roof_points_per_cell) {
  const Parcel& p = in.layer.parcels[i];
  ParcelScene s;
  s.parcel_index = int(i);
  s.parcel_id = p.id;
  s.parcel = to_local(p.shape, frame);
  for (int n : neighbours) s.neighbours.push_back(to_local(in.layer.parcels[n].shape, frame));
  for (size_t k : in_one_order(roof_idx, in.roof)) s.roof_points.push_back(frame.to_local(in.roof[k]));
  for (size_t k : in_one_order(wall_idx, in.wall)) s.wall_points.push_back(frame.to_local(in.wall[k]));
  s.overhang_buffer_m = in.cfg.clip.overhang_buffer_m;
  s.context_m = in.cfg.clip.overhang_buffer_m + kOwnershipContextM;
  s.roof_points_per_cell = roof_points_per_cell;
  const Dtm* dtm = &in.dtm;
  Vec3 o = frame.origin;
  s.terrain = [dtm, o](double x, double y) { return dtm->height_at(x + o.x(), y + o.y()) - o.z(); };
  return s;
}

std::string params_json(const Config& cfg, const BatchOptions& opt) {
  const auto& r = cfg.reconstruction;
  json j = {{"config", cfg.source},
            {"overhang_buffer_m", cfg.clip.overhang_buffer_m},
            {"optimize", opt.optimize},
            {"reconstruction",
             {{"component_smoothness_deg", r.component_smoothness_deg},
              {"component_curvature", r.component_curvature},
              {"min_component_points", r.min_component_points},
              {"min_component_area_m2", r.min_component_area_m2},
              {"plane_inlier_m", r.plane_inlier_m},
              {"loose_point_reach_m", r.loose_point_reach_m},
              {"default_overhang_m", r.default_overhang_m},
              {"storey_height_m", r.storey_height_m},
              {"shared_roof_depth_m", r.shared_roof_depth_m},
              {"roof_cluster_m", r.roof_cluster_m},
              {"partition_cell_m", r.partition_cell_m}}}};
  return j.dump();
}

// What identifies a parcel's inputs: run parameters, input files, its own shape.
std::string parcel_key(const std::string& run_key, const Parcel& p) {
  std::string s = run_key + "|" + p.id;
  for (const auto& poly : p.shape)
    for (const auto& v : poly.outer) s += "|" + std::to_string(v.x()) + "," + std::to_string(v.y());
  return sha256_hex(s);
}

std::string run_key_of(const std::string& params, const BatchOptions& opt) {
  std::string s = params;
  std::vector<std::string> files = opt.clouds;
  files.insert(files.end(), opt.walls.begin(), opt.walls.end());
  files.push_back(opt.parcels);
  if (!opt.dtm.empty()) files.push_back(opt.dtm);
  for (const auto& f : files) s += "|" + sha256_file(f);
  return sha256_hex(s);
}

// Every roof point inside a parcel against the nearest roof of any model, and
// every wall point within kWallPointReachM of a parcel against the nearest wall.
void any_model_deviation(const BatchModel& model, const Inputs& in, const ParcelClipper& clipper,
                         const ParcelClipper::IndexLists& roof_lists, OutputTimings& t) {
  std::vector<Face> roofs, walls;
  for (const auto& r : model.results)
    for (const auto& b : r.buildings) {
      auto rf = faces_of(b, {ElementType::Roof});
      auto wf = faces_of(b, {ElementType::Wall, ElementType::PartyWall});
      roofs.insert(roofs.end(), rf.begin(), rf.end());
      walls.insert(walls.end(), wf.begin(), wf.end());
    }
  auto shift = [&](std::vector<Face>& faces) {
    for (auto& f : faces) {
      for (auto& v : f.ring) v = model.frame.to_world(v);
      for (auto& h : f.holes)
        for (auto& v : h) v = model.frame.to_world(v);
    }
  };
  shift(roofs);
  shift(walls);
  std::vector<Vec3> roof_in;
  std::vector<char> taken(in.roof.size(), 0);
  for (size_t k = 0; k < roof_lists.size(); ++k)
    for (size_t i : roof_lists[k])
      if (!taken[i] && clipper.inside(k, in.roof[i].x(), in.roof[i].y())) {
        taken[i] = 1;
        roof_in.push_back(in.roof[i]);
      }
  ClipParams near = in.cfg.clip;
  near.overhang_buffer_m = kWallPointReachM;
  std::vector<Vec3> wall_near;
  std::vector<char> seen(in.wall.size(), 0);
  for (const auto& list : ParcelClipper(in.layer, near).clip(in.wall))
    for (size_t k : list)
      if (!seen[k]) seen[k] = 1, wall_near.push_back(in.wall[k]);
  if (!roofs.empty()) t.any_model_roof = deviation_to_faces(roof_in, roofs);
  if (!walls.empty()) t.any_model_wall = deviation_to_faces(wall_near, walls);
}

}  // namespace

int run_batch(const BatchOptions& opt) {
  auto t_start = std::chrono::steady_clock::now();
  fs::create_directories(opt.out);
  Inputs in = load_inputs(opt);
  in.cfg.reconstruction.optimize = in.cfg.reconstruction.optimize || opt.optimize;
  if (!opt.device.empty()) in.cfg.reconstruction.optimize_device = opt.device;
  for (const auto& w : in.warnings) std::cerr << "cadastre3d batch: warning: " << w << "\n";
  LocalFrame frame = make_frame(in.layer);
  const size_t n = in.layer.parcels.size();

  ParcelClipper clipper(in.layer, in.cfg.clip);
  // Wall points reach as far as the deviation counts them, at least.
  ClipParams wall_reach = in.cfg.clip;
  wall_reach.overhang_buffer_m = std::max(wall_reach.overhang_buffer_m, kWallPointReachM);
  auto wall_lists = ParcelClipper(in.layer, wall_reach).clip(in.wall);
  // Roof points come with a wider context than the overhang buffer so that a
  // roof running across a parcel boundary is seen well enough to tell an
  // overhang (whole to the parcel holding most of it) from a shared roof of
  // attached houses (split at the boundary).
  ClipParams context = in.cfg.clip;
  context.overhang_buffer_m += kOwnershipContextM;
  auto roof_lists = ParcelClipper(in.layer, context).clip(in.roof);
  // One density for every scene, so two parcels judge the roof at their
  // boundary alike.
  const int roof_points_per_cell = typical_roof_points_per_cell(in.roof);
  auto neighbours =
      neighbour_lists(in.layer, 2.0 * (in.cfg.clip.overhang_buffer_m + kOwnershipContextM) + 0.5);
  double t_ingest =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();

  Store store;
  std::string store_path = (fs::path(opt.out) / "cadastre.gpkg").string();
  store.open(store_path, in.crs_wkt, epsg_of(in.crs_wkt));
  std::string params = params_json(in.cfg, opt);
  std::vector<std::string> files = opt.clouds;
  files.insert(files.end(), opt.walls.begin(), opt.walls.end());
  files.push_back(opt.parcels);
  if (!opt.dtm.empty()) files.push_back(opt.dtm);
  store.begin_run(params, files, frame);
  std::string run_key = run_key_of(params, opt);
  std::vector<std::string> keys(n);
  for (size_t i = 0; i < n; ++i) keys[i] = parcel_key(run_key, in.layer.parcels[i]);
  store.mark_pending(in.layer.parcels, keys);

  std::vector<char> todo(n, 1);
  if (opt.resume)
    for (size_t i = 0; i < n; ++i) todo[i] = !store.parcel_done(in.layer.parcels[i].id, keys[i]);

  std::map<std::string, double> stage_seconds;
  double store_seconds = 0;
  std::atomic<size_t> next{0};
  std::mutex store_mutex;
  Progress progress("reconstruct", size_t(std::count(todo.begin(), todo.end(), 1)), opt.quiet);
  int failed = 0;
  auto worker = [&] {
    for (size_t i = next++; i < n; i = next++) {
      if (!todo[i]) continue;
      ParcelScene scene = make_scene(in, frame, i, roof_lists[i], wall_lists[i], neighbours[i], roof_points_per_cell);
      ParcelResult r = reconstruct_parcel(scene, in.cfg.reconstruction);
      ParcelValuation v = value_parcel(in.layer.parcels[i], r, in.cfg.valuation);
      std::lock_guard<std::mutex> lock(store_mutex);
      auto t_write = std::chrono::steady_clock::now();
      store.write_parcel(in.layer.parcels[i], r, v, frame, keys[i]);
      store_seconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t_write).count();
      for (const auto& t : r.timings) stage_seconds[t.stage] += t.seconds;
      if (r.status == ParcelStatus::Failed) {
        ++failed;
        std::cerr << "cadastre3d batch: parcel " << r.parcel_id << " failed: " << r.reason << "\n";
      }
      progress.step();
    }
  };
  int jobs = opt.jobs > 0 ? opt.jobs : int(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> pool;
  for (int k = 0; k < jobs; ++k) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  progress.done();
  store.end_run();
  store.close();
  double t_recon =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() - t_ingest;

  OutputTimings timings{t_ingest, t_recon, stage_seconds, {}, {}};
  BatchModel model = load_batch_model(store_path);  // resumed parcels come from the store too
  any_model_deviation(model, in, clipper, roof_lists, timings);
  write_outputs(model, store_path, opt.out, in.cfg, opt.formats, timings, opt.quiet);
  auto t_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (!opt.quiet) {
    std::cout << "batch: " << n << " parcels in " << t_total << " s; outputs in " << opt.out << "\n";
    std::printf("timing: ingest+clip %.3f s, reconstruction %.3f s, store writes %.3f s, "
                "summary+report+exports %.3f s, total %.3f s\n",
                t_ingest, t_recon - store_seconds, store_seconds, t_total - t_ingest - t_recon,
                t_total);
  }
  return failed > 0 ? kExitPartial : kExitOk;
}

}  // namespace c3d::cli
