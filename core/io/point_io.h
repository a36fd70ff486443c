#pragma once
// Point-cloud readers and the LAS writer. Every reader returns world
// coordinates in double and throws InputError("<file>", "<problem>") on bad input.
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

// Dispatches on the extension: .las, .laz (LASzip-compressed, decoded by
// core/io/laz), .ply, .pcd, .xyz/.txt/.csv.
PointCloud read_point_cloud(const std::string& path);

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
