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

// Areal scale factor of a projected CRS at a point given in lon/lat degrees
// (WGS 84): 1 means the CRS measures true areas there; 0 when it cannot be told
// (not projected, unreadable). From PROJ's proj_factors.
double areal_scale_at(const std::string& wkt, double lon_deg, double lat_deg);
// WKT of the WGS 84 / UTM zone holding lon/lat (EPSG:326zz north, 327zz south).
std::string utm_wkt_at(double lon_deg, double lat_deg);
// "EPSG:32748 (WGS 84 / UTM zone 48S)", the name the report gives the areas' CRS.
std::string areas_crs_text(const std::string& wkt);
// A CRS the user names ("EPSG:32748", WKT, a PROJ string) as WKT; throws
// InputError(where, ...) when unreadable or not a projected CRS in metres.
std::string user_crs_wkt(const std::string& text, const std::string& where);

struct CrsReconciliation {
  std::string crs_wkt;                // the CRS every input is in now
  std::vector<std::string> warnings;  // assumptions made, reprojections done
};

// True for a projected CRS whose unit is the metre.
bool is_metric(const std::string& wkt);

// Brings every input into one working CRS, in which areas and volumes are
// measured (docs/inputs.md, "CRS policy"). The working CRS is `wanted` when
// given (WKT, a projected CRS in metres); else the parcel layer's CRS when it is
// projected, in metres and true to area at the data (areal scale within
// kMaxArealDistortion of 1); else the first cloud's or the DTM's CRS that is;
// else the WGS 84 UTM zone at the data's centre. A cloud without a CRS is
// assumed to be in the layer's (warning); a layer without one adopts the
// clouds' common CRS (warning). Clouds and the layer are reprojected; a DTM
// must already be in the working CRS, as rasters are not warped here. A
// geographic layer whose coordinates cannot be degrees has no CRS known.
// Throws InputError naming the file and both CRS when inputs cannot be reconciled.
CrsReconciliation reconcile_crs(ParcelLayer& parcels, std::vector<PointCloud>& clouds, Dtm* dtm = nullptr,
                                const std::string& wanted = "");

}  // namespace c3d
