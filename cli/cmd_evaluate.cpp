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
  if (points.unclassified)
    std::cerr << "cadastre3d: note: " << o.cloud << " has no classes; all points taken as roof\n";
  const ModelEvaluation e = o.parcels.empty() ? evaluate_as_one_zone(model, points)
                                              : evaluate_per_parcel(model, points, layer, o.buffer);
  const EvaluationSummary summary = summarize(e);
  std::fputs(evaluation_table(e, summary).c_str(), stdout);
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
