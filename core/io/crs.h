#pragma once
// Coordinate reference systems through GDAL OSR. A CRS is passed around as WKT;
// an empty string means "the file carries no CRS". All transformations use
// traditional GIS axis order (x = easting/longitude, y = northing/latitude).
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

// EPSG code of the (horizontal part of the) CRS, 0 when none can be identified.
int epsg_of(const std::string& wkt);
// WKT (WKT1 where expressible) for an EPSG code; throws std::runtime_error when unknown.
std::string wkt_from_epsg(int epsg);
// True when both describe the same horizontal CRS (names and WKT dialect ignored).
// Two empty strings are the same; an empty and a non-empty one are not.
bool same_crs(const std::string& a, const std::string& b);
// "WGS 84 / UTM zone 48S (EPSG:32748)", or "(none)" for an empty WKT.
std::string crs_display_name(const std::string& wkt);

// In-place reprojection; `where` names the file for the InputError raised when
// the transformation cannot be built or fails for a point.
void reproject_points(std::vector<Vec3>& points, const std::string& from_wkt,
                      const std::string& to_wkt, const std::string& where);
MultiPolygon2 reproject(const MultiPolygon2& shape, const std::string& from_wkt,
                        const std::string& to_wkt, const std::string& where);
// Reprojects cloud.points from cloud.crs_wkt to to_wkt and sets cloud.crs_wkt.
void reproject(PointCloud& cloud, const std::string& to_wkt);

struct CrsReconciliation {
  std::string crs_wkt;                // the CRS every input is in now
  std::vector<std::string> warnings;  // assumptions made, reprojections done
};

// True for a projected CRS whose unit is the metre.
bool is_metric(const std::string& wkt);

// Brings every input into the CRS of the parcel layer (the reference): a cloud
// without a CRS is assumed to be in it (a warning says so), a cloud in another
// CRS is reprojected; a DTM (optional) must already match, as rasters are not
// warped here. A layer without CRS adopts the clouds' common CRS (warning). A
// layer whose CRS is not in metres (degrees, feet) is first reprojected into
// the first cloud CRS that is (warning); with none, that is an InputError.
// Throws InputError naming the file and both CRS when inputs cannot be reconciled.
CrsReconciliation reconcile_crs(ParcelLayer& parcels, std::vector<PointCloud>& clouds, Dtm* dtm = nullptr);

}  // namespace c3d
