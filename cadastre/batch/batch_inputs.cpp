#include "cadastre/batch/batch_inputs.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "cadastre/batch/resume_key.h"
#include "cadastre/batch/scenes.h"
#include "cadastre/batch/tile_extents.h"
#include "core/classify/classify.h"
#include "core/evaluate/evaluate.h"
#include "cadastre/parcel_checks.h"
#include "core/error.h"
#include "core/gdal_messages.h"
#include "core/io/crs.h"
#include "core/io/point_io.h"
#include "core/log.h"

namespace c3d {
namespace {

// Replaces the classes of every classified cloud by the forest's (batch --classify).
void classify_clouds(const std::string& model, std::vector<PointCloud>& clouds, size_t n, const Dtm* dtm,
                     const ClassMapping& classes, std::vector<std::string>& warnings) {
  const PointForest forest = PointForest::load(model);
  for (size_t i = 0; i < n; ++i) {
    std::string note;
    const Dtm terrain = dtm ? Dtm{} : terrain_from_cloud(clouds[i], classes, &note);
    if (note.rfind("no DTM", 0) == 0) warnings.push_back(clouds[i].source + ": " + note);
    const Classification c = classify_points(forest, clouds[i], dtm ? *dtm : terrain);
    write_classes(clouds[i], c.classes, classes);
    log::info(clouds[i].source + ": classified " + std::to_string(c.classes.size()) + " points: ground " +
              std::to_string(c.counts[0]) + ", roof " + std::to_string(c.counts[1]) + ", wall " +
              std::to_string(c.counts[2]) + ", other " + std::to_string(c.counts[3]));
  }
}

// A cloud that reaches no parcel: a wrong CRS or a wrong tile.
InputError far_from_parcels(const std::string& file, const ParcelLayer& layer, const std::string& extent) {
  return InputError(file, "no point lies within " + std::to_string(int(kCoverageReachM)) + " m of any parcel of " +
                              layer.source + " (points " + extent + "): check the CRS and the files");
}

// Parcels the clouds or the DTM do not reach fail one by one; reaching none
// is an error naming the file (a wrong CRS, a wrong tile).
void check_reach(const BatchInputs& inputs, const LoadedInputs& in) {
  const auto& parcels = in.layer.parcels;
  if (!parcels.empty() && std::none_of(parcels.begin(), parcels.end(),
                                       [&](const Parcel& p) { return in.coverage.near(p.shape); }))
    throw far_from_parcels(inputs.clouds.empty() ? inputs.walls.front() : inputs.clouds.front(), in.layer,
                           in.coverage.extent());
  if (std::all_of(parcels.begin(), parcels.end(),
                  [&](const Parcel& p) { return !dtm_gap(in.dtm, p, in.layer.source).empty(); }))
    check_dtm_covers(in.dtm, in.layer);
}

}  // namespace

std::string unreachable(const LoadedInputs& in, size_t i) {
  const Parcel& p = in.layer.parcels[i];
  if (!in.coverage.near(p.shape))
    return "no points of the cloud within " + std::to_string(int(kCoverageReachM)) + " m of the parcel";
  const std::string gap = dtm_gap(in.dtm, p, in.layer.source);
  return gap.empty() ? gap : "DTM " + in.dtm.source + " " + gap;
}

namespace {

// The CRS a file's points are in: its own, or the one reconcile_crs assumes
// for a file without (the layer's when metric, else the working CRS).
std::string points_crs(const std::string& own, const std::string& layer_crs, const std::vector<CloudExtent>& all,
                       const std::string& working) {
  if (!own.empty()) return own;
  std::string reference = layer_crs;
  for (size_t i = 0; reference.empty() && i < all.size(); ++i) reference = all[i].crs_wkt;
  return is_metric(reference) ? reference : working;
}

// The extent in the working CRS: corners and edge midpoints reprojected, a metre to spare.
Box working_extent(const CloudExtent& e, const std::string& from, const std::string& to, const std::string& path) {
  std::vector<Vec3> edge;
  for (double fx : {0.0, 0.5, 1.0})
    for (double fy : {0.0, 0.5, 1.0})
      edge.emplace_back(e.min_x + fx * (e.max_x - e.min_x), e.min_y + fy * (e.max_y - e.min_y), 0.0);
  if (!same_crs(from, to)) reproject_points(edge, from, to, path);
  Box b;
  for (const Vec3& p : edge) b.add(p.x(), p.y());
  return b.grown(same_crs(from, to) ? 0.0 : 1.0);
}

// A tile's extent. LAS and LAZ: the header's bounds, then the points as
// decoded (tile_extents.h), which a header a little too small leaves out;
// other formats are read once for theirs.
CloudExtent tile_extent(const std::string& f, const std::string& tile_index, LoadedInputs& in) {
  const CloudExtent header = read_cloud_extent(f);
  if (!header.note.empty()) in.warnings.push_back(f + ": " + header.note);
  if (!header.from_header) return header;
  const InputFile& file = in.described.emplace(f, describe_input_file(f)).first->second;
  const CloudExtent points = TileExtentIndex(tile_index).decoded(f, file.sha256, header);
  const std::string note = header_short_note(header, points);
  if (!note.empty()) in.warnings.push_back(f + ": " + note);
  return points;
}

// The tiles and the working CRS: each file's extent and CRS read (a header,
// or one pass), the layer brought into the working CRS (reconcile_crs) and
// its boxes taken.
void index_tiles(const BatchInputs& inputs, const std::string& wanted, bool have_dtm, LoadedInputs& in) {
  in.cloud_files = expand_point_files(inputs.clouds);
  in.wall_files = expand_point_files(inputs.walls);
  std::vector<std::string> files = in.cloud_files;
  files.insert(files.end(), in.wall_files.begin(), in.wall_files.end());
  std::vector<CloudExtent> extents;
  std::vector<PointCloud> named;  // what reconcile_crs reads of a cloud: its name and CRS
  for (const auto& f : files) {
    extents.push_back(tile_extent(f, inputs.tile_index, in));
    named.push_back(PointCloud{f, {}, {}, extents.back().crs_wkt});
  }
  const std::string layer_crs = in.layer.crs_wkt;
  auto rec = reconcile_crs(in.layer, named, have_dtm ? &in.dtm : nullptr, wanted);
  in.crs_wkt = rec.crs_wkt;
  in.warnings.insert(in.warnings.end(), rec.warnings.begin(), rec.warnings.end());
  for (size_t i = 0; i < files.size(); ++i) {
    Tile t;
    t.path = files[i];
    t.walls = i >= in.cloud_files.size();
    t.crs_wkt = points_crs(extents[i].crs_wkt, layer_crs, extents, in.crs_wkt);
    t.working = in.crs_wkt;
    t.extent = working_extent(extents[i], t.crs_wkt, t.working, t.path);
    t.points = extents[i].points;
    if (extents[i].points > 0) in.tiles.push_back(std::move(t));
  }
  in.boxes = ParcelBoxes(in.layer);  // the layer is in the working CRS now
}

// --classify: each cloud read whole, classified and kept in memory (classes
// depend on the whole cloud's neighbourhoods, as without tiles).
void classify_tiles(const BatchInputs& inputs, const Config& cfg, LoadedInputs& in) {
  std::vector<PointCloud> clouds;
  std::vector<Tile*> held;
  for (Tile& t : in.tiles) {
    if (t.walls) continue;
    clouds.push_back(read_point_cloud(t.path));
    clouds.back().crs_wkt = t.crs_wkt;
    if (!same_crs(t.crs_wkt, t.working)) reproject(clouds.back(), t.working);
    held.push_back(&t);
  }
  Box extent;
  for (const Tile* t : held) extent.add(t->extent);
  const Dtm terrain = dtm_window(in, extent);
  classify_clouds(inputs.classifier_model, clouds, clouds.size(), in.dtm_source ? &terrain : nullptr,
                  cfg.classes, in.warnings);
  for (size_t i = 0; i < clouds.size(); ++i) {
    keep_plausible_elevations(clouds[i], in.warnings);
    held[i]->held = std::make_shared<const PointCloud>(std::move(clouds[i]));
  }
}

// How far from a parcel the run reads points: its scene, its wall points for
// the deviation, and the coverage check's reach.
double work_reach(const Config& cfg) {
  return std::max({kCoverageReachM, cfg.clip.overhang_buffer_m + kOwnershipContextM, kWallPointReachM}) +
         kRegionMarginM;
}

// The boxes of the parcels `work` picks, grown by the run's reach.
std::vector<Box> work_boxes(const Shard& work, const Config& cfg, const LoadedInputs& in) {
  std::vector<Box> out;
  for (size_t i : shard_parcels(in.layer.parcels, work)) out.push_back(in.boxes[i].grown(work_reach(cfg)));
  return out;
}

// With --dtm, keeps the tiles a run on the parcels `work` picks can read:
// those touching the roof-density blocks within reach of them (the blocks
// are read whole), so a shard or a --bbox reads its own area of a national
// cloud, not all of it. The file lists follow (the run record hashes them).
void keep_tiles_in_reach(const Shard& work, const Config& cfg, LoadedInputs& in) {
  const std::set<CellIndex> blocks = cells_touched(work_boxes(work, cfg, in), kDensityBlockM);
  std::set<std::string> dropped;
  std::vector<Tile> kept;
  for (Tile& t : in.tiles)
    if (touches_any(t.extent, blocks, kDensityBlockM)) kept.push_back(std::move(t));
    else dropped.insert(t.path);
  if (kept.empty() && !in.tiles.empty() && !work.active()) {  // a shard off the survey: its parcels fail
    Box all;
    for (const Tile& t : in.tiles) all.add(t.extent);
    throw far_from_parcels(in.tiles.front().path, in.layer, extent_text(all.min_x, all.max_x, all.min_y, all.max_y));
  }
  in.tiles = std::move(kept);
  const auto drop = [&](std::vector<std::string>& files) {
    files.erase(std::remove_if(files.begin(), files.end(), [&](const std::string& f) { return dropped.count(f) > 0; }),
                files.end());
  };
  drop(in.cloud_files);
  drop(in.wall_files);
  if (!dropped.empty()) log::info(std::to_string(dropped.size()) + " point file(s) out of the parcels' reach, not read");
}

// The coverage, the warnings and the counts of the tiles near the parcels in work.
TileSurvey survey_near(const Shard& work, const Config& cfg, const LoadedInputs& in, bool all) {
  if (all) return survey_tiles(in.tiles, cfg.classes);
  const std::set<CellIndex> cells = cells_touched(work_boxes(work, cfg, in), kCoverageReachM);
  std::vector<Tile> tiles;
  for (const Tile& t : in.tiles)
    if (touches_any(t.extent, cells, kCoverageReachM)) tiles.push_back(t);
  return survey_tiles(tiles, cfg.classes);
}

// load_inputs without the GDAL message capture.
LoadedInputs load_all(const BatchInputs& inputs, const Config& cfg, const Shard& work) {
  LoadedInputs in;
  in.layer = read_parcels(inputs.parcels, inputs.parcel_selection, cfg.fields, &in.warnings);
  const ParcelSelection& sel = inputs.parcel_selection;
  check_override_ids(cfg.valuation.parcels, in.layer, cfg.source, !sel.where.empty() || !sel.bbox.empty(),
                     in.warnings);
  const bool have_dtm = !inputs.dtm.empty();
  if (have_dtm) in.dtm_source = std::make_shared<const DtmSource>(inputs.dtm);
  if (have_dtm) in.dtm = in.dtm_source->header();
  index_tiles(inputs, inputs.crs.empty() ? "" : user_crs_wkt(inputs.crs, "--crs"), have_dtm, in);
  if (have_dtm) keep_tiles_in_reach(work, cfg, in);
  for (std::string& w : overlap_warnings(in.layer)) in.warnings.push_back(std::move(w));
  log::info("areas in " + areas_crs_text(in.crs_wkt));
  log::info(std::to_string(in.tiles.size()) + " point file(s) with points");
  if (!inputs.classifier_model.empty()) classify_tiles(inputs, cfg, in);
  TileSurvey survey = survey_near(work, cfg, in, !have_dtm);
  in.warnings.insert(in.warnings.end(), survey.warnings.begin(), survey.warnings.end());
  in.coverage = std::move(survey.coverage);
  if (!have_dtm) in.dtm = ground_dtm(in.tiles, survey, cfg.classes, in.crs_wkt);
  if (in.dtm_source)
    check_dtm_elevations(*in.dtm_source, in.warnings);
  else
    check_dtm_elevations(in.dtm, in.warnings);
  // A shard whose area holds no points is no sign of a wrong input: its parcels fail one by one.
  if (survey.roof == 0 && survey.wall == 0 && !(work.active() && in.coverage.empty()))
    throw InputError(inputs.clouds.empty() ? inputs.parcels : inputs.clouds.front(),
                     "no roof or wall points (check the class mapping)");
  if (!work.active()) check_reach(inputs, in);
  return in;
}

}  // namespace

LoadedInputs load_inputs(const BatchInputs& inputs, const Config& cfg, const Shard& work) {
  GdalMessages gdal;  // GDAL prints nothing; its last word joins the error
  try {
    return load_all(inputs, cfg, work);
  } catch (const InputError& e) {
    throw gdal.fold(e);
  }
}

LoadedInputs load_fit_inputs(const BatchInputs& inputs, const Config& cfg) {
  GdalMessages gdal;
  try {
    LoadedInputs in;
    in.layer = read_parcels(inputs.parcels, inputs.parcel_selection, cfg.fields, &in.warnings);
    if (!inputs.dtm.empty()) in.dtm = read_dtm_header(inputs.dtm);  // its CRS may choose the working CRS
    index_tiles(inputs, inputs.crs.empty() ? "" : user_crs_wkt(inputs.crs, "--crs"), !inputs.dtm.empty(), in);
    if (!inputs.classifier_model.empty()) {  // the classes the batch modelled from (reads the DTM under the clouds)
      if (!inputs.dtm.empty()) in.dtm_source = std::make_shared<const DtmSource>(inputs.dtm);
      classify_tiles(inputs, cfg, in);
    }
    return in;
  } catch (const InputError& e) {
    throw gdal.fold(e);
  }
}

namespace {

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

}  // namespace

std::vector<InputFile> describe_inputs(const LoadedInputs& in, const BatchInputs& inputs) {
  std::vector<InputFile> out;  // every file the folders and globs name, each hashed once, with its role
  const auto describe = [&in](const std::string& f) {
    const auto known = in.described.find(f);
    return known != in.described.end() ? known->second : describe_input_file(f);
  };
  const auto add = [&out](InputFile f, const char* role) {
    f.role = role;
    out.push_back(std::move(f));
  };
  for (const auto& f : in.cloud_files) add(describe(f), input_role::kCloud);
  for (const auto& f : in.wall_files) add(describe(f), input_role::kWalls);
  add(describe_parcel_source(inputs.parcels, in.layer), input_role::kParcels);
  if (!inputs.dtm.empty()) add(describe_input_file(inputs.dtm), input_role::kDtm);
  if (!inputs.classifier_model.empty()) add(describe_input_file(inputs.classifier_model), input_role::kClassifier);
  return out;
}

std::vector<std::string> parcel_keys(const LoadedInputs& in, const BatchInputs& inputs, const Config& cfg,
                                     const std::vector<InputFile>& files) {
  std::map<std::string, std::string> tile_sha;  // tile path -> SHA-256
  for (const Tile& t : in.tiles) tile_sha[t.path];
  std::vector<InputFile> shared;  // what every parcel reads: the layer, the DTM, a classifier
  for (const InputFile& f : files)
    if (tile_sha.count(f.path)) tile_sha[f.path] = f.sha256;
    else shared.push_back(f);
  const std::string key = run_key(cfg, shared);
  std::map<CellIndex, std::vector<size_t>> by_block;  // density block -> the tiles touching it
  for (size_t t = 0; t < in.tiles.size(); ++t)
    for (const CellIndex& b : cells_touched({in.tiles[t].extent}, kDensityBlockM)) by_block[b].push_back(t);
  const auto hashes = [&](const std::set<size_t>& tiles) {
    std::vector<std::string> sha;
    for (size_t t : tiles) sha.push_back(tile_sha[in.tiles[t].path]);
    return sha;
  };
  std::set<size_t> every;
  for (size_t t = 0; t < in.tiles.size(); ++t) every.insert(t);
  const std::vector<std::string> all = hashes(every);
  std::vector<std::string> keys;
  for (size_t i = 0; i < in.layer.parcels.size(); ++i) {
    if (inputs.dtm.empty()) {  // the ground DTM is built from every tile
      keys.push_back(parcel_key(key, in.layer.parcels[i], all));
      continue;
    }
    std::set<size_t> read;
    for (const CellIndex& b : cells_touched({in.boxes[i].grown(work_reach(cfg))}, kDensityBlockM))
      if (by_block.count(b)) read.insert(by_block[b].begin(), by_block[b].end());
    keys.push_back(parcel_key(key, in.layer.parcels[i], hashes(read)));
  }
  return keys;
}

Dtm dtm_window(const LoadedInputs& in, const Box& box) {
  return in.dtm_source ? in.dtm_source->window(box.min_x, box.min_y, box.max_x, box.max_y) : Dtm{};
}

LocalFrame frame_of(const ParcelLayer& layer) {
  Vec2 lo(1e300, 1e300);
  for (const auto& p : layer.parcels)
    for (const auto& poly : p.shape)
      for (const auto& v : poly.outer) lo = lo.cwiseMin(v);
  LocalFrame f;
  f.origin = Vec3(std::floor(lo.x() / 10) * 10, std::floor(lo.y() / 10) * 10, 0.0);
  return f;
}

}  // namespace c3d
