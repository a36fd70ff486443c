// cadastre3d evaluate: deviation of classified points from a building model
// (OBJ/PLY, or CityJSON), as the plane-intersection paper measures it: roof points against the
// roof surfaces (3D and vertical distance), wall points against the walls; per
// parcel when a parcel layer is given, and pooled (cadastre/evaluate, core/evaluate).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cadastre/evaluate/parcel_evaluation.h"
#include "cadastre/inspect/parcel_inputs.h"
#include "cli/commands.h"
#include "core/error.h"
#include "core/evaluate/evaluation_output.h"
#include "core/io/point_io.h"
#include "ifc_citygml/export.h"

namespace c3d::cli {
namespace {

struct EvalOptions {
  std::vector<std::string> meshes;
  std::string cloud, classes = "roof=6,wall=64", parcels, id_field, json, residuals;
  double buffer = kWallPointReachM;
};

// "a roof within 0.3 m": the printed name of the part on the model, from the
// same constant the split uses.
std::string within_on_model(const char* surface) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "a %s within %.1f m", surface, kOnModelM);
  return buf;
}

// Where a pooled deviation comes from: each part's points and share of the
// squared distance.
void print_parts(const char* title, const std::vector<std::string>& labels, const std::vector<Deviation>& parts) {
  double total = 0;
  for (const Deviation& d : parts) total += double(d.n) * d.rmse * d.rmse;
  std::printf("%s (share of the squared distance):\n", title);
  for (size_t k = 0; k < parts.size(); ++k) {
    const Deviation& d = parts[k];
    const double share = total > 0 ? 100.0 * double(d.n) * d.rmse * d.rmse / total : 0.0;
    std::printf("  %-24s %8ld  rmse %6.3f  %5.1f %%\n", labels[k].c_str(), d.n, d.rmse, share);
  }
}

void print_row(const ZoneSummary& z) {
  auto cols = [](const Deviation& d) {
    char buf[128];
    if (d.n == 0) std::snprintf(buf, sizeof buf, "%8s %7s %7s %7s %7s", "0", "-", "-", "-", "-");
    else std::snprintf(buf, sizeof buf, "%8ld %7.3f %7.3f %7.3f %7.3f", d.n, d.mean, d.std, d.rmse, d.max);
    return std::string(buf);
  };
  char vbuf[32];
  if (z.roof_vertical.n) std::snprintf(vbuf, sizeof vbuf, "%8.3f", z.roof_vertical.rmse);
  else std::snprintf(vbuf, sizeof vbuf, "%8s", "-");
  std::printf("%-22s %s %s  %s\n", z.id.c_str(), cols(z.roof).c_str(), vbuf, cols(z.wall).c_str());
}

void print_report(const ModelEvaluation& e, const EvaluationSummary& s) {
  std::printf("%-22s %8s %7s %7s %7s %7s %8s  %8s %7s %7s %7s %7s\n", "parcel", "roof n", "mean", "std",
              "rmse", "max", "vert rms", "wall n", "mean", "std", "rmse", "max");
  if (e.per_parcel)
    for (const ZoneSummary& z : s.zones) print_row(z);
  print_row(s.pooled);
  print_parts("roof points by what the model has above or below them",
              {within_on_model("roof"), "a roof further off", "no roof"}, s.pooled.roof_cover.parts());
  print_parts("wall points by where they stand",
              {within_on_model("wall"), "under the parcel's roof", "under another's roof", "under no roof"},
              s.pooled.wall_cover.parts());
  std::printf("roof points %zu, wall points %zu; in parcels without a model: %ld roof, %ld wall; "
              "outside every parcel: %ld; model faces outside every parcel: %ld\n",
              e.roof_points, e.wall_points, s.pooled.unmodelled_roof, s.pooled.unmodelled_wall, e.points_outside,
              e.faces_outside);
  std::printf("distances in m: mean/std/rmse/max of |d|; vert rms = vertical distance RMSE\n");
}

// OBJ/PLY meshes, or CityJSON models (by the extension).
std::vector<MeshGroup> read_model(const std::vector<std::string>& paths) {
  std::vector<MeshGroup> model;
  for (const auto& path : paths) {
    auto groups = lower_ext(path) == "json" ? element_groups(read_cityjson(path)) : read_mesh_groups(path);
    model.insert(model.end(), groups.begin(), groups.end());
  }
  return model;
}

void run_evaluate(const EvalOptions& o) {
  const ClassMapping classes = parse_class_codes(o.classes, "--classes");
  const std::vector<MeshGroup> model = read_model(o.meshes);
  std::vector<PointCloud> clouds{read_point_cloud(o.cloud)};
  ParcelLayer layer;
  if (!o.parcels.empty()) {
    std::vector<std::string> warnings;
    layer = read_parcels_for_clouds(o.parcels, o.id_field, clouds, warnings);
    for (const auto& w : warnings) std::cerr << "cadastre3d: warning: " << w << "\n";
  }
  const RoofWallPoints points = roof_and_wall_points(clouds[0], classes);
  if (points.unclassified) std::cerr << "cadastre3d: note: " << o.cloud << " has no classes; all points taken as roof\n";
  const ModelEvaluation e = o.parcels.empty() ? evaluate_as_one_zone(model, points)
                                              : evaluate_per_parcel(model, points, layer, o.buffer);
  const EvaluationSummary summary = summarize(e);
  print_report(e, summary);
  if (!o.residuals.empty()) write_residuals_csv(o.residuals, e.zones);
  if (o.json.empty()) return;
  nlohmann::json j = evaluation_json(e, summary);
  j.update({{"mesh", o.meshes}, {"cloud", o.cloud}, {"classes", o.classes}, {"buffer_m", o.buffer}});
  std::ofstream out(o.json);
  out << j.dump(2) << "\n";
  if (!out) throw InputError(o.json, "cannot write");
}

}  // namespace

void register_evaluate(CLI::App& app) {
  auto o = std::make_shared<EvalOptions>();
  auto* cmd = app.add_subcommand(
      "evaluate", "Deviation of roof and wall points from a building model (per parcel and pooled)");
  cmd->add_option("--mesh", o->meshes, "models (.obj or .ply meshes, one or more: groups/materials "
                                       "named roof/wall are used, else faces are classed by their normal; "
                                       "or CityJSON .json: its semantic surfaces)")
      ->required()
      ->expected(1, -1);
  cmd->add_option("--cloud", o->cloud, "classified point cloud (LAS/PLY/PCD/XYZ)")->required();
  cmd->add_option("--classes", o->classes, "class codes, e.g. roof=6,wall=64 (unclassified files: all roof)")
      ->capture_default_str();
  cmd->add_option("--parcels", o->parcels, "parcel layer: per-parcel rows, measured as the batch does: "
                                           "roof points inside a parcel against its model's roofs, wall "
                                           "points within --buffer of it against its walls");
  cmd->add_option("--id-field", o->id_field,
                  "parcel id field (default: as the batch, NIB where the layer has it, else the feature id)");
  cmd->add_option("--buffer", o->buffer, "wall points this far outside a parcel still count for it, m")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--json", o->json, "also write the results as JSON");
  cmd->add_option("--residuals", o->residuals, "also write every measured point as CSV: parcel, kind (roof/wall), "
                                               "x, y, z, distance_m, vertical_m (roof points; empty: no roof above or below), "
                                               "part (of the split printed)");
  cmd->callback([o] {
    try {
      run_evaluate(*o);
    } catch (const std::exception& e) {
      std::cerr << "cadastre3d: error: " << e.what() << "\n";
      exit_code() = kExitError;
    }
  });
}

}  // namespace c3d::cli
