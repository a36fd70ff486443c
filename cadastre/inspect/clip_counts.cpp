#include "cadastre/inspect/clip_counts.h"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "cadastre/clip.h"
#include "core/error.h"
#include "core/text.h"

namespace c3d {
namespace {

// Adds one cloud's points to the counts; returns those in no parcel's buffer.
long count_cloud(const PointCloud& c, const ParcelClipper& clipper, const ClassMapping& classes,
                 std::vector<ParcelPointCount>& rows) {
  const ParcelClipper::IndexLists lists = clipper.clip(c.points);
  std::vector<char> used(c.points.size(), 0);
  for (size_t p = 0; p < lists.size(); ++p)
    for (size_t i : lists[p]) {
      used[i] = 1;
      const Vec3& pt = c.points[i];
      ParcelPointCount& r = rows[p];
      (clipper.inside(p, pt.x(), pt.y()) ? r.in_parcel : r.in_buffer)++;
      if (!c.classes.empty()) {
        r.roof += classes.is_roof(c.classes[i]);
        r.wall += classes.is_wall(c.classes[i]);
      }
    }
  return long(std::count(used.begin(), used.end(), 0));
}

}  // namespace

ClipCounts count_points_per_parcel(const ParcelLayer& layer, const std::vector<PointCloud>& clouds,
                                   double buffer_m, const ClassMapping& classes) {
  ClipParams params;
  params.overhang_buffer_m = buffer_m;
  const ParcelClipper clipper(layer, params);
  ClipCounts out;
  out.parcels.resize(layer.parcels.size());
  out.buffer_m = clipper.buffer_m();
  for (const PointCloud& c : clouds) {
    out.unclipped += count_cloud(c, clipper, classes, out.parcels);
    out.points += long(c.points.size());
    out.any_classes |= !c.classes.empty();
  }
  return out;
}

std::string clip_table(const ParcelLayer& layer, const ClipCounts& counts) {
  char buf[512];
  std::snprintf(buf, sizeof buf, "%-6s %-14s %10s %10s %10s %10s\n", "parcel", "id", "in_parcel", "in_buffer",
                "roof", "wall");
  std::string out = buf;
  for (size_t p = 0; p < counts.parcels.size(); ++p) {
    const ParcelPointCount& r = counts.parcels[p];
    std::string id = layer.parcels[p].id;  // as %-14s, of any length
    id.resize(std::max<size_t>(id.size(), 14), ' ');
    std::snprintf(buf, sizeof buf, "%-6zu ", p);
    out += buf + id;
    std::snprintf(buf, sizeof buf, " %10ld %10ld %10ld %10ld\n", r.in_parcel, r.in_buffer, r.roof, r.wall);
    out += buf;
  }
  std::snprintf(buf, sizeof buf,
                "%ld points, %ld in no parcel (buffer %.2f m; in_buffer = outside the parcel but "
                "within the buffer; roof/wall count both)\n",
                counts.points, counts.unclipped, counts.buffer_m);
  out += buf;
  if (!counts.any_classes) out += "no cloud carries classes: roof/wall counts are 0\n";
  return out;
}

void write_clip_csv(const std::string& path, const ParcelLayer& layer, const ClipCounts& counts) {
  std::ofstream csv(path);
  csv << "parcel_index,parcel_id,in_parcel,in_buffer,roof,wall\n";
  for (size_t p = 0; p < counts.parcels.size(); ++p) {
    const ParcelPointCount& r = counts.parcels[p];
    csv << p << "," << csv_text_cell(layer.parcels[p].id) << "," << r.in_parcel << "," << r.in_buffer << "," << r.roof << ","
        << r.wall << "\n";
  }
  if (!csv) throw InputError(path, "cannot write the CSV file");
}

}  // namespace c3d
