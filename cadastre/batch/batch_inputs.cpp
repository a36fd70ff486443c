#include "cadastre/batch/batch_inputs.h"

#include <algorithm>
#include <cmath>

#include "core/classify/classify.h"
#include "cadastre/parcel_checks.h"
#include "core/error.h"
#include "core/gdal_messages.h"
#include "core/geometry/unique_points.h"
#include "core/io/crs.h"
#include "core/io/point_io.h"
#include "core/log.h"

namespace c3d {
namespace {

void split_classes(const PointCloud& cloud, const ClassMapping& m, LoadedInputs& in,
                   std::vector<Vec3>& ground) {
  if (cloud.classes.empty()) {  // an unclassified cloud is taken as roof points
    in.roof.insert(in.roof.end(), cloud.points.begin(), cloud.points.end());
    in.warnings.push_back(cloud.source + ": no classification, all points taken as roof");
    return;
  }
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    int c = cloud.classes[i];
    if (m.is_roof(c)) in.roof.push_back(cloud.points[i]);
    else if (m.is_wall(c)) in.wall.push_back(cloud.points[i]);
    else if (m.is_ground(c)) ground.push_back(cloud.points[i]);
  }
}

// Replaces the classes of every classified cloud by the forest's (batch --classify).
void classify_clouds(const std::string& model, std::vector<PointCloud>& clouds, size_t n, const Dtm* dtm,
                     const ClassMapping& classes, std::vector<std::string>& warnings) {
  const PointForest forest = PointForest::load(model);
  for (size_t i = 0; i < n; ++i) {
    std::string note;
    const Dtm terrain = dtm ? Dtm{} : terrain_from_cloud(clouds[i], classes, &note);
    if (note.rfind("no DTM", 0) == 0) warnings.push_back(clouds[i].source + ": " + note);
    const Classification c = classify_points(forest, clouds[i].points, dtm ? *dtm : terrain);
    write_classes(clouds[i], c.classes, classes);
    log::info(clouds[i].source + ": classified " + std::to_string(c.classes.size()) + " points: ground " +
              std::to_string(c.counts[0]) + ", roof " + std::to_string(c.counts[1]) + ", wall " +
              std::to_string(c.counts[2]) + ", other " + std::to_string(c.counts[3]));
  }
}

// Parcels the clouds or the DTM do not reach fail one by one; reaching none
// is an error naming the file (a wrong CRS, a wrong tile).
void check_reach(const BatchInputs& inputs, const LoadedInputs& in) {
  const auto& parcels = in.layer.parcels;
  if (!parcels.empty() && std::none_of(parcels.begin(), parcels.end(),
                                       [&](const Parcel& p) { return in.coverage.near(p.shape); }))
    throw InputError(inputs.clouds.empty() ? inputs.walls.front() : inputs.clouds.front(),
                     "no point lies within " + std::to_string(int(kCoverageReachM)) + " m of any parcel of " +
                         in.layer.source + " (points " + in.coverage.extent() + "): check the CRS and the files");
  if (std::all_of(parcels.begin(), parcels.end(),
                  [&](const Parcel& p) { return !dtm_gap(in.dtm, p, in.layer.source).empty(); }))
    check_dtm_covers(in.dtm, in.layer);
}

// One point per place: copies of a point (a writer repeating records, strips
// merged twice) carry nothing more, and every neighbourhood, count and
// spacing downstream would read them as density.
void fold_copies(std::vector<Vec3>& pts, const char* what) {
  std::vector<Vec3> kept = one_per_place(pts);
  if (kept.size() == pts.size()) return;
  log::info(std::string(what) + " points: " + std::to_string(pts.size() - kept.size()) +
            " copies of another point's place folded into it, " + std::to_string(kept.size()) + " kept");
  pts = std::move(kept);
}

}  // namespace

std::string unreachable(const LoadedInputs& in, size_t i) {
  const Parcel& p = in.layer.parcels[i];
  if (!in.coverage.near(p.shape))
    return "no points of the cloud within " + std::to_string(int(kCoverageReachM)) + " m of the parcel";
  const std::string gap = dtm_gap(in.dtm, p, in.layer.source);
  return gap.empty() ? gap : "DTM " + in.dtm.source + " " + gap;
}

std::vector<std::string> BatchInputs::files() const {
  std::vector<std::string> out = clouds;
  out.insert(out.end(), walls.begin(), walls.end());
  out.push_back(parcels);
  if (!dtm.empty()) out.push_back(dtm);
  if (!classifier_model.empty()) out.push_back(classifier_model);
  return out;
}

namespace {

// load_inputs without the GDAL message capture.
LoadedInputs load_all(const BatchInputs& inputs, const Config& cfg) {
  LoadedInputs in;
  in.layer = read_parcels(inputs.parcels, inputs.parcel_selection, cfg.fields, &in.warnings);
  const ParcelSelection& sel = inputs.parcel_selection;
  check_override_ids(cfg.valuation.parcels, in.layer, cfg.source, !sel.where.empty() || !sel.bbox.empty(),
                     in.warnings);
  std::vector<PointCloud> clouds;
  for (const auto& f : inputs.clouds) clouds.push_back(read_point_cloud(f));
  const size_t n_class_clouds = clouds.size();
  for (const auto& f : inputs.walls) clouds.push_back(read_point_cloud(f));
  const bool have_dtm = !inputs.dtm.empty();
  if (have_dtm) in.dtm = read_dtm(inputs.dtm);
  const std::string wanted = inputs.crs.empty() ? "" : user_crs_wkt(inputs.crs, "--crs");
  auto rec = reconcile_crs(in.layer, clouds, have_dtm ? &in.dtm : nullptr, wanted);
  in.crs_wkt = rec.crs_wkt;
  in.warnings.insert(in.warnings.end(), rec.warnings.begin(), rec.warnings.end());
  for (std::string& w : overlap_warnings(in.layer)) in.warnings.push_back(std::move(w));
  log::info("areas in " + areas_crs_text(in.crs_wkt));
  if (!inputs.classifier_model.empty())
    classify_clouds(inputs.classifier_model, clouds, n_class_clouds, have_dtm ? &in.dtm : nullptr, cfg.classes,
                    in.warnings);
  for (auto& c : clouds) keep_plausible_elevations(c, in.warnings);
  std::vector<Vec3> ground;
  for (size_t i = 0; i < clouds.size(); ++i) {
    in.coverage.add(clouds[i].points);
    if (i < n_class_clouds) split_classes(clouds[i], cfg.classes, in, ground);
    else in.wall.insert(in.wall.end(), clouds[i].points.begin(), clouds[i].points.end());
    clouds[i].points.clear();
    clouds[i].points.shrink_to_fit();
  }
  if (!have_dtm) {
    if (ground.empty())
      throw InputError("--dtm", "no DTM given and no ground-class points to build one from");
    in.dtm = dtm_from_points(ground, in.crs_wkt, 1.0, DtmCell::Min, "ground-class points");
  }
  check_dtm_elevations(in.dtm, in.warnings);
  fold_copies(in.roof, "roof");
  fold_copies(in.wall, "wall");
  if (in.roof.empty() && in.wall.empty())
    throw InputError(inputs.clouds.empty() ? inputs.parcels : inputs.clouds.front(),
                     "no roof or wall points (check the class mapping)");
  check_reach(inputs, in);
  return in;
}

}  // namespace

LoadedInputs load_inputs(const BatchInputs& inputs, const Config& cfg) {
  GdalMessages gdal;  // GDAL prints nothing; its last word joins the error
  try {
    return load_all(inputs, cfg);
  } catch (const InputError& e) {
    throw gdal.fold(e);
  }
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
