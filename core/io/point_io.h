#pragma once
// Point-cloud readers and the LAS writer. Every reader returns world
// coordinates in double and throws InputError("<file>", "<problem>") on bad input.
#include <string>

#include "core/types.h"

namespace c3d {

// Dispatches on the extension: .las, .laz (clear error: convert with ...),
// .ply, .pcd, .xyz/.txt/.csv.
PointCloud read_point_cloud(const std::string& path);

// Writes LAS 1.<minor_version> with the given point format (0-10); classes are
// written when present; crs_wkt as an OGC WKT VLR (formats 6-10) or GeoKeys.
void write_las(const std::string& path, const PointCloud& cloud, int point_format = 6,
               int minor_version = 4);

}  // namespace c3d
