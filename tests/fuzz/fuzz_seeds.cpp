#include "tests/fuzz/fuzz_seeds.h"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/config/config.h"
#include "core/gdal_dataset.h"
#include "core/io/crs.h"
#include "core/io/point_io.h"

namespace c3d::fuzz {

namespace {

std::string file_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), {});
}

// A dozen UTM-sized points on a little roof, classes 2, 6 and 64.
PointCloud small_cloud() {
  PointCloud c;
  for (int i = 0; i < 12; ++i) {
    c.points.emplace_back(781800.25 + i % 4, 9240000.5 + i / 4, 790 + 0.5 * (i % 3));
    c.classes.push_back(uint8_t(i % 3 == 0 ? 2 : i % 3 == 1 ? 6 : 64));
  }
  return c;
}

template <typename T>
void append(std::string& out, T v, bool big_endian = false) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

// LAS 1.4 format 6 with the CRS moved into an EVLR (the EVLR path of the reader).
std::string las_with_evlr(const std::string& path) {
  PointCloud c = small_cloud();
  write_las(path, c, 6, 4);
  std::string b = file_bytes(path);
  const std::string wkt = wkt_from_epsg(32748);
  std::string evlr(60, '\0');
  std::memcpy(&evlr[2], "LASF_Projection", 15);
  uint16_t id = 2112;
  uint64_t length = wkt.size() + 1;
  std::memcpy(&evlr[18], &id, 2);
  std::memcpy(&evlr[20], &length, 8);
  const uint64_t offset = b.size();
  const uint32_t count = 1;
  b += evlr + wkt + '\0';
  std::memcpy(&b[235], &offset, 8);
  std::memcpy(&b[243], &count, 4);
  return b;
}

std::string ply_text(const std::string& format) {
  std::ostringstream h;
  h << "ply\nformat " << format << " 1.0\ncomment fuzz seed\nelement camera 1\n"
    << "property float view\nelement vertex 4\nproperty double x\nproperty double y\n"
    << "property float z\nproperty uchar classification\nelement face 1\n"
    << "property list uchar int vertex_indices\nend_header\n";
  return h.str();
}

std::string ply_binary(bool big_endian) {
  std::string b = ply_text(big_endian ? "binary_big_endian" : "binary_little_endian");
  append<float>(b, 1.0f, big_endian);
  for (int i = 0; i < 4; ++i) {
    append<double>(b, 781800.5 + i, big_endian);
    append<double>(b, 9240000.25 + i % 2, big_endian);
    append<float>(b, 790.0f + i, big_endian);
    append<uint8_t>(b, uint8_t(i % 2 ? 6 : 2));
  }
  return b;  // the face element after the vertices is never read
}

std::string gdal_raster(const char* const* options) {
  register_gdal_drivers();
  const char* name = "/vsimem/fuzz_seed.tif";
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  {
    GdalDataset ds(gtiff->Create(name, 16, 12, 1, GDT_Float32, const_cast<char**>(options)));
    double gt[6] = {781790, 1.0, 0, 9240010, 0, -1.0};
    ds->SetGeoTransform(gt);
    OGRSpatialReference srs;
    srs.importFromEPSG(32748);
    ds->SetSpatialRef(&srs);
    std::vector<float> z(16 * 12);
    for (size_t i = 0; i < z.size(); ++i) z[i] = (i % 37 == 5) ? -9999.0f : 780.0f + 0.1f * float(i % 16);
    GDALRasterBand* band = ds->GetRasterBand(1);
    band->SetNoDataValue(-9999);
    if (band->RasterIO(GF_Write, 0, 0, 16, 12, z.data(), 16, 12, GDT_Float32, 0, 0) != CE_None) return {};
  }
  vsi_l_offset size = 0;
  GByte* data = VSIGetMemFileBuffer(name, &size, FALSE);
  std::string bytes(reinterpret_cast<const char*>(data), size_t(size));
  VSIUnlink(name);
  return bytes;
}

const char* const kGeoJson = R"({"type": "FeatureCollection", "name": "parcels",
"crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32748"}},
"features": [
{"type": "Feature", "properties": {"NIB": "10.25.00.001", "area": 120.5},
 "geometry": {"type": "Polygon", "coordinates": [[[781800, 9240000], [781812, 9240000],
 [781812, 9240010], [781800, 9240010], [781800, 9240000]]]}},
{"type": "Feature", "properties": {"NIB": "10.25.00.002", "area": 99},
 "geometry": {"type": "Polygon", "coordinates": [[[781812, 9240000], [781824, 9240000],
 [781824, 9240010], [781812, 9240010], [781812, 9240000]], [[781815, 9240003], [781816, 9240003],
 [781816, 9240004], [781815, 9240003]]]}},
{"type": "Feature", "properties": {"NIB": null},
 "geometry": {"type": "MultiPolygon", "coordinates": [[[[781800, 9240020], [781810, 9240020],
 [781800, 9240030], [781810, 9240030], [781800, 9240020]]]]}}
]}
)";

std::string gpkg_parcels(const std::string& path) {
  register_gdal_drivers();
  std::remove(path.c_str());
  {
    GDALDriver* gpkg = GetGDALDriverManager()->GetDriverByName("GPKG");
    GdalDataset ds(gpkg->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    OGRSpatialReference srs;
    srs.importFromEPSG(32748);
    OGRLayer* layer = ds->CreateLayer("parcels", &srs, wkbPolygon, nullptr);
    OGRFieldDefn nib("NIB", OFTString);
    layer->CreateField(&nib);
    for (int i = 0; i < 2; ++i) {
      OGRFeature f(layer->GetLayerDefn());
      f.SetField("NIB", ("10.25.00.00" + std::to_string(i)).c_str());
      OGRGeometry* g = nullptr;
      std::string wkt = "POLYGON ((" + std::to_string(781800 + 12 * i) + " 9240000, " +
                        std::to_string(781812 + 12 * i) + " 9240000, " + std::to_string(781812 + 12 * i) +
                        " 9240010, " + std::to_string(781800 + 12 * i) + " 9240010, " +
                        std::to_string(781800 + 12 * i) + " 9240000))";
      OGRGeometryFactory::createFromWkt(wkt.c_str(), nullptr, &g);
      f.SetGeometryDirectly(g);
      if (layer->CreateFeature(&f) != OGRERR_NONE) return {};
    }
  }
  return file_bytes(path);
}

}  // namespace

std::vector<SeedInput> las_seeds(const std::string& work) {
  std::vector<SeedInput> out;
  PointCloud c = small_cloud();
  c.crs_wkt = wkt_from_epsg(32748);
  for (auto [format, minor] : {std::pair{1, 2}, {6, 4}, {0, 0}}) {
    const std::string path = work + "/seed.las";
    write_las(path, c, format, minor);
    out.push_back({"las-1." + std::to_string(minor) + "-f" + std::to_string(format), ".las",
                   file_bytes(path), 375, false});
  }
  out.push_back({"las-1.4-evlr", ".las", las_with_evlr(work + "/seed.las"), 375, false});
  return out;
}

std::vector<SeedInput> laz_seeds() {
  std::vector<SeedInput> out;
  // Point-wise v2 from two encoders, layered v3 chunks of a COPC file (RGB14)
  // and of a format 8 file with extra bytes (RGBNIR14, BYTE14), the latter
  // cut to its first 3000 points (LAS 1.4 point count, bytes 247-254).
  for (const char* name : {"simple.laz", "liblas-generated.laz", "1.2-with-color.copc.laz",
                           "las_with_several_extra_byte_bloc.laz"}) {
    const std::string path = std::string(C3D_SOURCE_DIR) + "/../shared/data/laz/" + name;
    if (!std::filesystem::exists(path)) continue;
    std::string bytes = file_bytes(path);
    if (std::string(name).rfind("las_with", 0) == 0 && bytes.size() > 255) {
      const uint64_t cut = 3000;
      std::memcpy(&bytes[247], &cut, 8);
    }
    uint32_t point_offset = 0;  // header and VLRs (the LASzip VLR among them) get field mutations
    if (bytes.size() >= 100) std::memcpy(&point_offset, bytes.data() + 96, 4);
    out.push_back({std::string("laz-") + name, ".laz", bytes, std::min<size_t>(point_offset, bytes.size()), false});
  }
  return out;
}

std::vector<SeedInput> ply_seeds() {
  std::string ascii = ply_text("ascii") + "1.5\n";
  for (int i = 0; i < 4; ++i)
    ascii += std::to_string(781800.5 + i) + " 9240000.25 " + std::to_string(790 + i) + " " +
             (i % 2 ? "6" : "2") + "\n";
  ascii += "3 0 1 2\n";
  const size_t header = ply_text("ascii").size();
  return {{"ply-ascii", ".ply", ascii, header, true},
          {"ply-le", ".ply", ply_binary(false), header, true},
          {"ply-be", ".ply", ply_binary(true), header, true}};
}

std::vector<SeedInput> pcd_seeds(const std::string& work) {
  pcl::PointCloud<pcl::PointXYZL> cloud;
  for (int i = 0; i < 8; ++i) {
    pcl::PointXYZL p;
    p.x = 1.5f + float(i), p.y = 2.25f * float(i % 3), p.z = 10.0f + 0.5f * float(i);
    p.label = uint32_t(i % 2 ? 6 : 2);
    cloud.push_back(p);
  }
  std::vector<SeedInput> out;
  const std::string path = work + "/seed.pcd";
  pcl::io::savePCDFileASCII(path, cloud);
  out.push_back({"pcd-ascii", ".pcd", file_bytes(path), 256, true});
  pcl::io::savePCDFileBinary(path, cloud);
  out.push_back({"pcd-binary", ".pcd", file_bytes(path), 256, true});
  pcl::io::savePCDFileBinaryCompressed(path, cloud);
  out.push_back({"pcd-compressed", ".pcd", file_bytes(path), 256, true});
  return out;
}

std::vector<SeedInput> xyz_seeds() {
  std::string xyz, csv = "X,Y,Z,Classification\n";
  for (int i = 0; i < 8; ++i) {
    const std::string x = std::to_string(781800.5 + i), y = std::to_string(9240000.25 + i % 3);
    const std::string z = std::to_string(790.0 + 0.25 * i), c = i % 2 ? "6" : "2";
    xyz += x + " " + y + " " + z + "\n";
    csv += x + "," + y + "," + z + "," + c + "\n";
  }
  return {{"xyz", ".xyz", "# x y z\n" + xyz, 0, true}, {"csv", ".csv", csv, 0, true}};
}

std::vector<SeedInput> dtm_seeds() {
  const char* plain[] = {nullptr};
  const char* tiled[] = {"TILED=YES", "BLOCKXSIZE=16", "BLOCKYSIZE=16", "COMPRESS=DEFLATE", nullptr};
  return {{"geotiff-strips", ".tif", gdal_raster(plain), 512, false},
          {"geotiff-deflate-tiles", ".tif", gdal_raster(tiled), 512, false}};
}

std::vector<SeedInput> parcel_seeds(const std::string& work) {
  return {{"geojson", ".geojson", kGeoJson, 0, true},
          {"gpkg", ".gpkg", gpkg_parcels(work + "/seed.gpkg"), 100, false}};
}

std::vector<SeedInput> config_seeds() {
  const std::string small =
      "[reconstruction]\noutlier_neighbours = 8\nmin_component_points = 12\n"
      "[valuation.parcels.\"10.25.00.001\"]\nzone = \"ZNT-A\"\nage_years = 12.5\n";
  return {{"config-default", ".toml", default_config_toml(), 0, true},
          {"config-small", ".toml", default_config_toml() + small, 0, true}};
}

std::vector<SeedInput> mesh_seeds() {
  const std::string obj =
      "# coordinates local: world = local + (781800.000000, 9240000.000000, 790.000000)\n"
      "v 0 0 0\nv 4 0 0\nv 4 3 0\nv 0 3 0\nv 0 0 2.5\nv 4 0 2.5\nv 4 3 2.5\nv 0 3 2.5\n"
      "g parcel_1\nusemtl roof\nf 5 6 7 8\nusemtl wall\nf 1 2 6 5\nf 2/1 3/2 7/3 6/4\n"
      "f 3//1 4//1 8//1 7//1\nf -5 -8 -1 -4\ng other\nf 1 4 3 2\n";
  std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n1 1 0\n0 1 1\n3 0 1 2\n3 0 2 3\n";
  std::string bin =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n";
  for (int i = 0; i < 9; ++i) append<double>(bin, double(i % 3 == 0 ? i : 0));
  append<uint8_t>(bin, 3);
  for (uint32_t i = 0; i < 3; ++i) append<uint32_t>(bin, i);
  return {{"obj", ".obj", obj, 0, true},
          {"mesh-ply-ascii", ".ply", ply, 140, true},
          {"mesh-ply-binary", ".ply", bin, 160, true}};
}

}  // namespace c3d::fuzz
