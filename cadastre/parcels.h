#pragma once
// The parcel layer from any OGR vector source (Shapefile, GeoPackage, GeoJSON…).
#include <string>
#include <vector>

#include "core/config/config.h"
#include "core/types.h"

namespace c3d {

// Reads the first polygon layer. Parcel ids come from fields.id, or the feature
// id (FID) when that is empty or a feature's value is null/empty. Invalid
// polygons are repaired with GEOS MakeValid (Parcel::repair_note says what was
// wrong) or rejected with an InputError naming the parcel. Non-polygon features
// are skipped; such notes go to *warnings when given. Parcel::index is the
// position in the returned list (layer order). Rings: outer CCW, holes CW,
// not closed. Throws InputError when the source holds no polygon.
ParcelLayer read_parcels(const std::string& path, const ParcelFields& fields = {},
                         std::vector<std::string>* warnings = nullptr);

// Checks one parcel shape; returns "" when valid, else GEOS's reason with location.
std::string validity_problem(const MultiPolygon2& shape);

}  // namespace c3d
