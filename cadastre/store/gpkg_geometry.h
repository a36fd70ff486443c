#pragma once
// GeoPackage geometry blobs (GPKG 1.3 §2.1.3): "GP" header, version 0, little
// endian, envelope, then ISO WKB (Z types are 1000 + base type, as GDAL and
// validate_gpkg.py expect). Only (Multi)Polygon is needed by the store.
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

using Blob = std::vector<std::uint8_t>;

// MultiPolygonZ of the faces, each vertex shifted by offset (local -> world).
// Closes the rings (WKB repeats the first vertex). Empty input -> empty blob.
Blob gpkg_faces_blob(const std::vector<Face>& faces, const Vec3& offset, int srs_id);
// 2D MultiPolygon (parcels), world coordinates.
Blob gpkg_multipolygon_blob(const MultiPolygon2& mp, int srs_id);

// Readers accept Polygon / MultiPolygon, 2D or Z, either byte order; rings come
// back open (last != first). offset is subtracted (world -> local).
// Throw std::runtime_error on a malformed blob.
std::vector<Face> gpkg_read_faces(const std::uint8_t* data, std::size_t n, const Vec3& offset);
MultiPolygon2 gpkg_read_multipolygon(const std::uint8_t* data, std::size_t n);
// min_x, min_y, max_x, max_y from the header envelope; false when it has none.
bool gpkg_envelope_xy(const std::uint8_t* data, std::size_t n, double env[4]);

}  // namespace c3d
