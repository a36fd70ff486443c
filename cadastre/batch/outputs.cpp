#include "cadastre/batch/outputs.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "core/evaluate/evaluate.h"
#include "core/io/crs.h"
#include "core/geometry/geometry.h"
#include "ifc_citygml/export.h"
#include "ifc_citygml/spool.h"
#include "cadastre/batch/out_dir.h"
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

// What the optimizer did to a curved building's dense mesh (null: not refined).
json refinement_json(const MeshRefinement& m) {
  if (m.triangles == 0) return json();
  return {{"triangles", m.triangles},
          {"snapped_share", r4(m.snapped_share)},
          {"chamfer_to_exact_shape_m", {{"before", r4(m.chamfer_before_m)}, {"after", r4(m.chamfer_after_m)}}},
          {"cloud_to_mesh_m", {{"before", r4(m.cloud_before_m)}, {"after", r4(m.cloud_after_m)}}}};
}

// A finite figure, or null (JSON has no NaN).
json finite(double v) { return std::isfinite(v) ? json(r4(v)) : json(); }

json text_or_null(const std::string& s) { return s.empty() ? json() : json(s); }

json mesh_level_json(const MeshLevelRecord& l) {
  return {{"level", l.level},
          {"faces", l.faces},
          {"vertices", l.vertices},
          {"cpu_s", r4(l.seconds)},
          {"cloud_to_mesh_m", {{"mean", finite(l.mean_m)}, {"std", finite(l.std_m)}, {"p95", finite(l.p95_m)},
                               {"max", finite(l.max_m)}}},
          {"mesh_to_cloud_m", finite(l.mesh_to_cloud_m)},
          {"far_share", finite(l.far_share)},
          {"closed", l.closed},
          {"manifold", l.manifold},
          {"volume_m3", finite(l.volume)},
          {"roof_area_m2", finite(l.roof_area)},
          {"planar_regions", {{"count", l.planar_regions}, {"lost", l.planar_lost},
                              {"extent_change_m", finite(l.extent_change_m)}, {"thickness_m", finite(l.thickness_m)}}},
          {"files", {{"ply", text_or_null(l.ply)}, {"glb", text_or_null(l.glb)}, {"picture", text_or_null(l.picture)}}},
          {"sha256", {{"ply", text_or_null(l.ply_sha256)}, {"glb", text_or_null(l.glb_sha256)},
                      {"picture", text_or_null(l.picture_sha256)}}}};
}

// The building's mesh ladder and the model against its hull (null: not meshed).
json mesh_json(const BuildingMesh& m) {
  if (m.method.empty()) return json();
  json levels = json::array();
  for (const MeshLevelRecord& l : m.levels) levels.push_back(mesh_level_json(l));
  return {{"method", m.method},
          {"points", m.points},
          {"spacing_m", finite(m.spacing_m)},
          {"levels", levels},
          {"model_vs_hull", {{"volume_diff", finite(m.volume_diff)}, {"roof_area_diff", finite(m.roof_area_diff)},
                             {"flag", text_or_null(m.flag)}}},
          {"problem", text_or_null(m.problem)}};
}

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
          {"lod", to_string(b.lod)},
          {"lod_note", b.lod_note},
          {"roof_deviation", to_json(b.roof_deviation)},
          {"wall_deviation", to_json(b.wall_deviation)},
          {"mesh_refinement", refinement_json(b.refinement)},
          {"mesh", mesh_json(b.mesh)}};
}

// Whether the whole-run fit was computed: a merge without the batch's inputs
// has none, and says so rather than give zeros.
std::string fit_text(const BatchReport& r) {
  return r.fit_missing.empty() ? "computed" : "not computed: " + r.fit_missing;
}

// summary.json as the pages come: the parcels' entries go to a spool (the
// counts and pooled deviations before them in the file need every parcel),
// so only two deviations per building stay in memory.
class SummaryWriter {
 public:
  SummaryWriter(const BatchReport& report, const BatchModel& header, const std::string& path)
      : report_(report), epsg_(header.epsg), crs_wkt_(header.crs_wkt), path_(path),
        parcels_(path, ".parcels.part") {}

  void add(const BatchModel& page) {
    for (size_t i = 0; i < page.parcels.size(); ++i) add(page.parcels[i], page.results[i]);
  }

  void finish() {
    json stages = json::object();
    for (const auto& [k, v] : report_.timings.stages) stages[k] = v;
    json j = {{"tool", "cadastre3d " C3D_VERSION},
              {"crs_epsg", epsg_},
              {"areas_crs", areas_crs_text(crs_wkt_)},
              {"parcels_total", count_},
              {"parcels_ok", ok_},
              {"parcels_empty", empty_},
              {"parcels_failed", failed_},
              {"parcels_suspect", suspect_},
              {"pooled_roof_deviation", to_json(pool(roof_devs_))},
              {"pooled_wall_deviation", to_json(pool(wall_devs_))},
              {"any_model_fit", fit_text(report_)},
              {"any_model_roof_deviation", fit_ ? to_json(report_.any_model_roof) : json()},
              {"any_model_wall_deviation", fit_ ? to_json(report_.any_model_wall) : json()},
              {"roof_ruler", fit_ ? to_json(report_.roof_ruler) : json()},
              {"wall_ruler", fit_ ? to_json(report_.wall_ruler) : json()},
              {"wall_points_measured_share", fit_ ? json(report_.wall_points_measured) : json()},
              {"timings_s",
               {{"ingest_and_clip", report_.timings.ingest_s},
                {"reconstruct_and_store", report_.timings.reconstruct_s},
                {"stages_cpu", stages}}},
              {"parcels", json::array()}};
    // Keys print sorted, one a line: the empty array's line is where the parcels go.
    const std::string text = j.dump(2), slot = "\n  \"parcels\": []";
    const size_t at = text.find(slot);
    if (at == std::string::npos) throw std::logic_error("summary.json: no parcels slot");
    std::ofstream f(path_, std::ios::binary);
    f << text.substr(0, at + slot.size() - 1);
    if (count_ > 0) {
      f << "\n";
      parcels_.copy_to(f);
      f << "\n  ";
    }
    f << text.substr(at + slot.size() - 1) << "\n";
    if (!f.flush()) throw InputError(path_, "cannot write");
  }

 private:
  void add(const Parcel& p, const ParcelResult& r) {
    json buildings = json::array();
    for (const auto& b : r.buildings) {
      buildings.push_back(building_json(b));
      roof_devs_.push_back(b.roof_deviation);
      wall_devs_.push_back(b.wall_deviation);
    }
    ok_ += r.status == ParcelStatus::Ok;
    empty_ += r.status == ParcelStatus::Empty;
    failed_ += r.status == ParcelStatus::Failed;
    suspect_ += r.status == ParcelStatus::Suspect;
    const json entry = {{"parcel_index", count_},
                        {"parcel_id", p.id},
                        {"status", to_string(r.status)},
                        {"reason", r.reason},
                        {"buildings", buildings}};
    // As an element of the top-level array, each line sits 4 spaces in
    // (a JSON string holds no raw line break).
    std::string text = "    " + entry.dump(2);
    for (size_t k = 0; (k = text.find('\n', k)) != std::string::npos; k += 5) text.insert(k + 1, "    ");
    parcels_.out() << (count_ ? ",\n" : "") << text;
    if (!parcels_.out()) throw InputError(path_, "cannot write");
    ++count_;
  }

  const BatchReport& report_;
  const bool fit_ = report_.fit_missing.empty();  // the whole-run fit figures, else null
  const int epsg_;
  const std::string crs_wkt_, path_;
  exp::Spool parcels_;
  std::vector<Deviation> roof_devs_, wall_devs_;
  size_t count_ = 0;
  int ok_ = 0, empty_ = 0, failed_ = 0, suspect_ = 0;
};

// One standalone picture per parcel with buildings, coloured by element type,
// named by file_stem_for_id (an id can neither leave the folder nor share a file).
void write_previews(const BatchModel& model, const std::string& dir) {
  for (size_t i = 0; i < model.parcels.size(); ++i) {
    if (model.results[i].buildings.empty()) continue;
    const fs::path path = fs::path(dir) / (file_stem_for_id(model.parcels[i].id) + ".svg");
    std::ofstream svg(path, std::ios::binary);
    std::string pic = parcel_svg(model.parcels[i], model.results[i], model.frame, 720, 520);
    // Inline in the report it needs no namespace; a standalone file does.
    if (pic.rfind("<svg ", 0) == 0) pic.insert(5, "xmlns=\"http://www.w3.org/2000/svg\" ");
    svg << pic;
    if (!svg.flush()) throw InputError(path.string(), "cannot write the preview");
  }
}

}  // namespace

WrittenOutputs write_outputs(const BatchReport& report, const std::string& store_loc,
                             const std::string& out_dir, const Config& cfg,
                             const std::vector<std::string>& formats, const OutputProgress& progress) {
  return write_outputs(report, StorePages(store_loc), out_dir, cfg, formats, progress);
}

namespace {

// Every output under `stage` in one pass over the store: each output takes
// each page in turn. Returns the export files; the writers (and their spools)
// are gone before the caller publishes the folder.
std::vector<std::string> write_staged(const BatchReport& report, const StorePages& pages,
                                      const std::string& stage, const Config& cfg,
                                      const std::vector<std::string>& formats, const OutputProgress& progress) {
  const BatchModel& header = pages.header();
  SummaryWriter summary(report, header, (fs::path(stage) / "summary.json").string());
  ReportInfo info = store_report_info(pages.location(), cfg, false, true);
  if (!report.fit_missing.empty()) info.run_note += "; whole-run fit of the models " + fit_text(report);
  ReportWriter report_pages(stage, pages.parcel_count(), header, std::move(info));
  std::vector<std::unique_ptr<ExportWriter>> exports;
  for (const auto& f : formats) exports.push_back(export_writer(f, header, stage));
  const std::string previews = (fs::path(stage) / "preview").string();
  fs::create_directories(previews);
  for (size_t k = 0; k < pages.page_count(); ++k) {
    BatchModel page = pages.page(k);
    summary.add(page);
    write_previews(page, previews);
    std::vector<ParcelValuation> values = pages.valuations(k);
    for (auto& w : exports) {
      if (w->carries_values()) w->values(values);
      w->add(page);
    }
    report_pages.add(std::move(page), std::move(values));
    if (progress) progress(k + 1, pages.page_count() + 1);
  }
  summary.finish();
  report_pages.finish();
  std::vector<std::string> files;
  for (auto& w : exports)
    for (auto& p : w->finish()) files.push_back(std::move(p));
  return files;
}

}  // namespace

WrittenOutputs write_outputs(const BatchReport& report, const StorePages& pages,
                             const std::string& out_dir, const Config& cfg,
                             const std::vector<std::string>& formats, const OutputProgress& progress) {
  // Everything is written under OUT/.staging, then each file is renamed into
  // place: a killed batch leaves no half-written file in OUT.
  const std::string stage = staging_dir(out_dir);
  fs::remove_all(stage);
  fs::create_directories(stage);
  WrittenOutputs out;
  for (const auto& p : write_staged(report, pages, stage, cfg, formats, progress))
    out.exports.push_back(moved(p, stage, out_dir));
  publish_staged(stage, out_dir);
  if (progress) progress(pages.page_count() + 1, pages.page_count() + 1);
  out.summary = (fs::path(out_dir) / "summary.json").string();
  out.report = (fs::path(out_dir) / "report.html").string();
  out.preview_dir = (fs::path(out_dir) / "preview").string();
  return out;
}

namespace {

bool is_cityjson(const std::string& path) {
  return path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0;
}

}  // namespace

std::vector<PagesExport> export_store(const std::string& store, const std::string& dir,
                                     const std::vector<std::string>& formats, size_t& buildings) {
  if (!is_cityjson(store)) return export_pages(StorePages(store), dir, formats, &buildings);
  std::vector<PagesExport> done;
  BatchModel model = read_cityjson(store);
  for (const auto& r : model.results) buildings += r.buildings.size();
  for (const auto& f : formats) {
    auto t0 = std::chrono::steady_clock::now();
    PagesExport e{f};
    e.files = export_formats(model, dir, {f}, &e.skipped);
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    done.push_back(std::move(e));
  }
  return done;
}

}  // namespace c3d
