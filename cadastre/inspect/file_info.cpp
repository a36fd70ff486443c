#include "cadastre/inspect/file_info.h"

#include <cstdio>
#include <sstream>

#include "cadastre/parcels.h"
#include "core/geometry/geometry.h"
#include "core/io/crs.h"
#include "core/io/dtm_io.h"
#include "core/io/point_io.h"

namespace c3d {
namespace {

std::string grouped(unsigned long long n) {  // 244685 -> "244,685"
  std::string s = std::to_string(n);
  for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(size_t(i), ",");
  return s;
}

std::string fixed(double v, int digits = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

void put_cloud(std::ostream& out, const CloudInfo& c) {
  out << "  kind:    point cloud\n  points:  " << grouped(c.points) << "\n";
  if (c.points)
    out << "  bbox:    x " << fixed(c.lo.x()) << " .. " << fixed(c.hi.x()) << "\n"
        << "           y " << fixed(c.lo.y()) << " .. " << fixed(c.hi.y()) << "\n"
        << "           z " << fixed(c.lo.z()) << " .. " << fixed(c.hi.z()) << "\n";
  out << (c.classified ? "  classes:\n" : "  classes: none in the file\n");
  for (int k = 0; k < 256; ++k)
    if (c.class_counts[k])
      out << "    class " << k << ": " << grouped(c.class_counts[k]) << " ("
          << fixed(100.0 * c.class_counts[k] / c.classified, 1) << " %)\n";
  out << "  CRS:     " << c.crs << "\n";
}

void put_parcels(std::ostream& out, const ParcelLayerInfo& p) {
  std::string fields;
  for (const std::string& f : p.fields) fields += (fields.empty() ? "" : ", ") + f;
  out << "  kind:     parcel layer\n  parcels:  " << p.parcels << " (total area " << fixed(p.total_area, 1)
      << " m2)\n  fields:   " << fields << "\n  CRS:      " << p.crs << "\n  validity: "
      << p.parcels - p.repairs.size() << " valid, " << p.repairs.size() << " repaired by MakeValid\n";
  for (const ParcelRepair& r : p.repairs) out << "    parcel " << r.id << ": " << r.note << "\n";
  for (const std::string& w : p.warnings) out << "  warning: " << w << "\n";
}

void put_raster(std::ostream& out, const RasterInfo& r) {
  out << "  kind:       raster (DTM, band 1)\n  size:       " << r.nx << " x " << r.ny
      << " cells\n  resolution: " << fixed(r.cell_x) << " x " << fixed(r.cell_y) << " m\n  extent:     x "
      << fixed(r.x_min) << " .. " << fixed(r.x_max) << ", y " << fixed(r.y_min) << " .. " << fixed(r.y_max)
      << "\n  NoData:     " << fixed(100.0 * r.nodata_share, 1) << " % of cells (filled for use)\n"
      << "  CRS:        " << r.crs << "\n";
}

}  // namespace


ParcelLayerInfo describe_parcel_layer(const std::string& path) {
  ParcelLayerInfo info;
  const ParcelLayer layer = read_parcels(path, ParcelFields{}, &info.warnings);
  info.parcels = layer.parcels.size();
  for (const Parcel& p : layer.parcels) {
    if (!p.repair_note.empty()) info.repairs.push_back({p.id, p.repair_note});
    info.total_area += area(p.shape);
  }
  info.fields = layer.fields;
  info.crs = crs_display_name(layer.crs_wkt);
  return info;
}

FileInfo describe_file(const std::string& path) {
  FileInfo info;
  if (is_point_cloud_file(path)) {
    info.kind = FileInfo::Kind::Cloud;
    info.cloud = describe_cloud(read_point_cloud(path));
  } else if (gdal_content(path) == GdalContent::Vector) {
    info.kind = FileInfo::Kind::Parcels;
    info.parcels = describe_parcel_layer(path);
  } else {
    info.kind = FileInfo::Kind::Raster;
    info.raster = describe_raster(DtmSource(path).header());  // the file as it is: nothing filled
  }
  return info;
}

std::string info_text(const std::string& path, const FileInfo& info) {
  std::ostringstream out;
  out << path << "\n";
  if (info.kind == FileInfo::Kind::Cloud) put_cloud(out, info.cloud);
  else if (info.kind == FileInfo::Kind::Parcels) put_parcels(out, info.parcels);
  else put_raster(out, info.raster);
  return out.str();
}

}  // namespace c3d
