#pragma once
// The parcel layer from any OGR vector source (Shapefile, GeoPackage, GeoJSON…).
#include <string>
#include <vector>

#include "core/config/config.h"
#include "core/types.h"

namespace c3d {

// Which features of an OGR source are the parcels (docs/inputs.md).
struct ParcelSelection {
  std::string layer;         // required when the source holds more than one layer
  std::string where;         // OGR SQL attribute filter, e.g. "KELURAHAN = 'Cigugur'"
  std::vector<double> bbox;  // xmin, ymin, xmax, ymax in the layer's own CRS; empty: all
};

// Reads the parcels of `path`: a file, a folder or any OGR connection string
// (PG:..., /vsizip/...). A source with several layers needs selection.layer;
// the error lists them. Ids must be unique, valid UTF-8 and free of NUL
// characters; an error names the features. Parcel ids come from fields.id, or the feature
// id (FID) when that is empty or a feature's value is null/empty. Invalid
// polygons are repaired with GEOS MakeValid (Parcel::repair_note says what was
// wrong) or rejected with an InputError naming the parcel. Non-polygon features
// are skipped; such notes go to *warnings when given. Parcel::index is the
// position in the returned list (layer order). Rings: outer CCW, holes CW,
// not closed. Throws InputError when the source holds no polygon.
ParcelLayer read_parcels(const std::string& path, const ParcelSelection& selection,
                         const ParcelFields& fields = {}, std::vector<std::string>* warnings = nullptr);
inline ParcelLayer read_parcels(const std::string& path, const ParcelFields& fields = {},
                                std::vector<std::string>* warnings = nullptr) {
  return read_parcels(path, ParcelSelection{}, fields, warnings);
}

// Checks one parcel shape; returns "" when valid, else GEOS's reason with location.
std::string validity_problem(const MultiPolygon2& shape);

}  // namespace c3d
