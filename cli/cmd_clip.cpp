// cadastre3d clip: how many points each parcel gets (inside, in the overhang
// buffer, roof/wall classes) - the check before a batch.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cadastre/clip.h"
#include "cadastre/parcels.h"
#include "cli/commands.h"
#include "core/io/crs.h"
#include "core/error.h"
#include "core/io/point_io.h"

namespace c3d::cli {
namespace {

struct ClipOptions {
  std::vector<std::string> clouds;
  std::string parcels, id_field, csv;
  double buffer = ClipParams{}.overhang_buffer_m;
};

struct Row {
  long in_parcel = 0, in_buffer = 0, roof = 0, wall = 0;
};

bool has(const std::vector<int>& codes, int c) {
  for (int k : codes)
    if (k == c) return true;
  return false;
}

void run_clip(const ClipOptions& o) {
  std::vector<std::string> warnings;
  ParcelLayer layer = read_parcels(o.parcels, parcel_fields(o.id_field), &warnings);
  std::vector<PointCloud> clouds;
  for (const std::string& f : o.clouds) clouds.push_back(read_point_cloud(f));
  CrsReconciliation crs = reconcile_crs(layer, clouds);
  warnings.insert(warnings.end(), crs.warnings.begin(), crs.warnings.end());
  for (const std::string& w : warnings) std::cerr << "cadastre3d: warning: " << w << "\n";

  ClipParams params;
  params.overhang_buffer_m = o.buffer;
  ParcelClipper clipper(layer, params);
  const ClassMapping classes;
  std::vector<Row> rows(layer.parcels.size());
  long total = 0, unclipped = 0;
  bool any_classes = false;
  for (const PointCloud& c : clouds) {
    ParcelClipper::IndexLists lists = clipper.clip(c.points);
    std::vector<char> used(c.points.size(), 0);
    for (size_t p = 0; p < lists.size(); ++p)
      for (size_t i : lists[p]) {
        used[i] = 1;
        const Vec3& pt = c.points[i];
        Row& r = rows[p];
        (clipper.inside(p, pt.x(), pt.y()) ? r.in_parcel : r.in_buffer)++;
        if (!c.classes.empty()) {
          r.roof += has(classes.roof, c.classes[i]);
          r.wall += has(classes.wall, c.classes[i]);
        }
      }
    total += long(c.points.size());
    any_classes |= !c.classes.empty();
    for (char u : used) unclipped += !u;
  }

  std::printf("%-6s %-14s %10s %10s %10s %10s\n", "parcel", "id", "in_parcel", "in_buffer",
              "roof", "wall");
  for (size_t p = 0; p < rows.size(); ++p)
    std::printf("%-6zu %-14s %10ld %10ld %10ld %10ld\n", p, layer.parcels[p].id.c_str(),
                rows[p].in_parcel, rows[p].in_buffer, rows[p].roof, rows[p].wall);
  std::printf("%ld points, %ld in no parcel (buffer %.2f m; in_buffer = outside the parcel but "
              "within the buffer; roof/wall count both)\n",
              total, unclipped, clipper.buffer_m());
  if (!any_classes) std::printf("no cloud carries classes: roof/wall counts are 0\n");
  if (!o.csv.empty()) {
    std::ofstream csv(o.csv);
    csv << "parcel_index,parcel_id,in_parcel,in_buffer,roof,wall\n";
    for (size_t p = 0; p < rows.size(); ++p)
      csv << p << ",\"" << layer.parcels[p].id << "\"," << rows[p].in_parcel << ","
          << rows[p].in_buffer << "," << rows[p].roof << "," << rows[p].wall << "\n";
    if (!csv) throw InputError(o.csv, "cannot write the CSV file");
  }
}

}  // namespace

void register_clip(CLI::App& app) {
  auto o = std::make_shared<ClipOptions>();
  auto* cmd = app.add_subcommand(
      "clip", "Clip point clouds to the parcels (with the overhang buffer) and count the points "
              "per parcel");
  cmd->add_option("--cloud", o->clouds, "point clouds (LAS/PLY/PCD/XYZ), one or more")
      ->required()
      ->expected(1, -1);
  cmd->add_option("--parcels", o->parcels, "parcel layer (any OGR vector source)")->required();
  cmd->add_option("--buffer", o->buffer, "overhang buffer around each parcel, m")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--id-field", o->id_field,
                  "parcel id field (default: as the batch, NIB where the layer has it, else the feature id)");
  cmd->add_option("--csv", o->csv, "also write the table as CSV");
  cmd->callback([o] {
    try {
      run_clip(*o);
    } catch (const std::exception& e) {
      std::cerr << "cadastre3d: error: " << e.what() << "\n";
      exit_code() = kExitError;
    }
  });
}

}  // namespace c3d::cli
