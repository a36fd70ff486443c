#pragma once
// Point-cloud readers and the LAS writer. Every reader returns world
// coordinates in double and throws InputError("<file>", "<problem>") on bad input.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

// Dispatches on the extension: .las, .laz (LASzip-compressed, decoded by
// core/io/laz), .ply, .pcd, .xyz/.txt/.csv.
PointCloud read_point_cloud(const std::string& path);

// Reads a cloud a block of points at a time, in file order. LAS and LAZ are
// mapped and decoded a block (a LASzip chunk) at a time and the pages read are
// handed back, so a file is never held whole; PLY, PCD and XYZ are read whole,
// then handed on in blocks. `block` gets the next points (source and crs_wkt
// set; classes empty when the file has none). Throws as read_point_cloud.
void for_each_point_block(const std::string& path, const std::function<void(const PointCloud&)>& block);

// A cloud's extent in plan, in its own CRS.
struct CloudExtent {
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  std::string crs_wkt;
  uint64_t points = 0;
  bool from_header = false;  // read from a LAS/LAZ header alone, not from the points
  std::string note;          // why a LAS/LAZ header's bounds were not taken (a warning), if so
};
// LAS and LAZ: from the header (the bytes before the points), where a sample
// of the points (4,096 records through an uncompressed file, a LAZ file's
// first chunk) lies within its bounds; other formats, a header whose bounds
// are unusable, and one a sampled point lies outside (`note` says which),
// from one pass over the points.
CloudExtent read_cloud_extent(const std::string& path);
// The extent of the points themselves: one pass over the file, a block at a time.
CloudExtent decoded_cloud_extent(const std::string& path);

// The raw point records of a LAS or LAZ file (LAZ decoded), in file order:
// header point count times record length bytes.
std::vector<uint8_t> read_las_records(const std::string& path);

// Writes LAS 1.<minor_version> with the given point format (0-10); classes are
// written when present; crs_wkt as an OGC WKT VLR (formats 6-10) or GeoKeys.
void write_las(const std::string& path, const PointCloud& cloud, int point_format = 6,
               int minor_version = 4);
// The same file LASzip-compressed (core/io/laz/laz_writer.h): point formats
// 0-3 and 6-8.
void write_laz(const std::string& path, const PointCloud& cloud, int point_format = 6,
               int minor_version = 4);

}  // namespace c3d
