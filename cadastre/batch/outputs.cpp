#include "cadastre/batch/outputs.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>

#include "core/evaluate/evaluate.h"
#include "core/io/crs.h"
#include "core/geometry/geometry.h"
#include "ifc_citygml/export.h"
#include "cadastre/batch/out_dir.h"
#include "cadastre/store.h"
#include "cadastre/report/report.h"
#include "core/error.h"
#include "core/io/file_names.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace c3d {
namespace {

json to_json(const RulerFigures& r) {
  return {{"n", r.n}, {"rmse", r.rmse}, {"median", r.median}, {"nmad", r.nmad}, {"p95", r.p95}, {"max", r.max},
          {"rmse_within_1m", r.rmse_within_1m}, {"share_over_0_3m", r.share_over_0_3m},
          {"share_over_1m", r.share_over_1m}};
}

json to_json(const Deviation& d) {
  return {{"n", d.n}, {"max", d.max}, {"mean", d.mean}, {"std", d.std}, {"rmse", d.rmse}};
}

double r4(double v) { return std::round(v * 1e4) / 1e4; }

json building_json(const Building& b) {
  BuildingTotals t = totals(b);
  return {{"building_id", b.id},
          {"roof_area_m2", r4(t.roof)},
          {"roof_plan_area_m2", r4(t.roof_plan)},
          {"wall_area_m2", r4(t.wall)},
          {"party_wall_area_m2", r4(t.party_wall)},
          {"ground_area_m2", r4(t.ground)},
          {"outer_ceiling_area_m2", r4(t.outer_ceiling)},
          {"volume_m3", r4(b.volume)},
          {"eave_height_m", r4(b.eave_height)},
          {"ridge_height_m", r4(b.ridge_height)},
          {"storeys", b.storeys},
          {"roof_planes", t.roof_planes},
          {"sigma",
           {{"roof_area_m2", r4(t.sigma_roof)},
            {"wall_area_m2", r4(t.sigma_wall)},
            {"party_wall_area_m2", r4(t.sigma_party_wall)},
            {"ground_area_m2", r4(t.sigma_ground)},
            {"outer_ceiling_area_m2", r4(t.sigma_outer_ceiling)}}},
          {"solid_valid", b.solid_valid},
          {"solid_problem", b.solid_problem},
          {"lod", b.lod},
          {"lod_note", b.lod_note},
          {"roof_deviation", to_json(b.roof_deviation)},
          {"wall_deviation", to_json(b.wall_deviation)}};
}

}  // namespace

void write_summary(const BatchReport& report, const BatchModel& model, const std::string& path) {
  const BatchTimings& timings = report.timings;
  json parcels = json::array();
  std::vector<Deviation> roof_devs, wall_devs;
  int ok = 0, empty = 0, failed = 0, suspect = 0;
  for (size_t i = 0; i < model.parcels.size(); ++i) {
    const ParcelResult& r = model.results[i];
    json buildings = json::array();
    for (const auto& b : r.buildings) {
      buildings.push_back(building_json(b));
      roof_devs.push_back(b.roof_deviation);
      wall_devs.push_back(b.wall_deviation);
    }
    ok += r.status == ParcelStatus::Ok;
    empty += r.status == ParcelStatus::Empty;
    failed += r.status == ParcelStatus::Failed;
    suspect += r.status == ParcelStatus::Suspect;
    parcels.push_back({{"parcel_index", i},
                       {"parcel_id", model.parcels[i].id},
                       {"status", to_string(r.status)},
                       {"reason", r.reason},
                       {"buildings", buildings}});
  }
  json stages = json::object();
  for (const auto& [k, v] : timings.stages) stages[k] = v;
  json j = {{"tool", "cadastre3d " C3D_VERSION},
            {"crs_epsg", model.epsg},
            {"areas_crs", areas_crs_text(model.crs_wkt)},
            {"parcels_total", model.parcels.size()},
            {"parcels_ok", ok},
            {"parcels_empty", empty},
            {"parcels_failed", failed},
            {"parcels_suspect", suspect},
            {"pooled_roof_deviation", to_json(pool(roof_devs))},
            {"pooled_wall_deviation", to_json(pool(wall_devs))},
            {"any_model_roof_deviation", to_json(report.any_model_roof)},
            {"any_model_wall_deviation", to_json(report.any_model_wall)},
            {"roof_ruler", to_json(report.roof_ruler)},
            {"wall_ruler", to_json(report.wall_ruler)},
            {"wall_points_measured_share", report.wall_points_measured},
            {"timings_s",
             {{"ingest_and_clip", timings.ingest_s},
              {"reconstruct_and_store", timings.reconstruct_s},
              {"stages_cpu", stages}}},
            {"parcels", parcels}};
  std::ofstream f(path);
  f << j.dump(2) << "\n";
  if (!f.flush()) throw InputError(path, "cannot write");
}

namespace {

// The same relative path under `to` as `path` has under `from`.
std::string moved(const std::string& path, const std::string& from, const std::string& to) {
  return (fs::path(to) / fs::relative(path, from)).string();
}

// One standalone picture per parcel with buildings, coloured by element type,
// named by file_stem_for_id (an id can neither leave the folder nor share a file).
void write_previews(const BatchModel& model, const std::string& dir, const std::function<void()>& step) {
  fs::create_directories(dir);
  for (size_t i = 0; i < model.parcels.size(); ++i) {
    if (model.results[i].buildings.empty()) continue;
    const fs::path path = fs::path(dir) / (file_stem_for_id(model.parcels[i].id) + ".svg");
    std::ofstream svg(path, std::ios::binary);
    std::string pic = parcel_svg(model.parcels[i], model.results[i], model.frame, 720, 520);
    // Inline in the report it needs no namespace; a standalone file does.
    if (pic.rfind("<svg ", 0) == 0) pic.insert(5, "xmlns=\"http://www.w3.org/2000/svg\" ");
    svg << pic;
    if (!svg.flush()) throw InputError(path.string(), "cannot write the preview");
    step();
  }
}

}  // namespace

WrittenOutputs write_outputs(const BatchReport& report, const std::string& store_path,
                             const std::string& out_dir, const Config& cfg,
                             const std::vector<std::string>& formats, const OutputProgress& progress) {
  const BatchModel model = load_batch_model(store_path);
  size_t done = 0, total = 2 + formats.size();
  for (const auto& r : model.results) total += !r.buildings.empty();
  auto step = [&] {
    if (progress) progress(++done, total);
  };
  // Everything is written under OUT/.staging, then each file is renamed into
  // place: a killed batch leaves no half-written file in OUT.
  const std::string stage = staging_dir(out_dir);
  fs::remove_all(stage);
  fs::create_directories(stage);
  write_summary(report, model, (fs::path(stage) / "summary.json").string());
  step();
  write_report_from_store(model, store_path, stage, cfg, false, true);
  step();
  WrittenOutputs out;
  for (const auto& f : formats) {
    for (const auto& p : export_formats(model, stage, {f})) out.exports.push_back(moved(p, stage, out_dir));
    step();
  }
  write_previews(model, (fs::path(stage) / "preview").string(), step);
  publish_staged(stage, out_dir);
  out.summary = (fs::path(out_dir) / "summary.json").string();
  out.report = (fs::path(out_dir) / "report.html").string();
  out.preview_dir = (fs::path(out_dir) / "preview").string();
  return out;
}

}  // namespace c3d
