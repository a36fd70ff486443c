// The CRS policy for areas (docs/inputs.md): every input into one projected
// CRS in metres that is true to area at the data.
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "core/error.h"
#include "core/io/crs.h"

namespace c3d {
namespace {

// UTM stays within 0.2 % of true areas inside its zone and a national TM
// within less; Web Mercator is at least 0.67 % off anywhere (1.47 % at
// Cimahi): 0.5 % tells a CRS fit for areas from one that is not.
constexpr double kMaxArealDistortion = 0.005;

std::string describe(const std::string& wkt) { return crs_display_name(wkt); }

bool is_geographic(const std::string& wkt) {
  OGRSpatialReference srs;
  return !wkt.empty() && srs.importFromWkt(wkt.c_str()) == OGRERR_NONE && srs.IsGeographic();
}

// The centre of the layer's bounding box, in its own coordinates.
std::optional<Vec2> layer_centre(const ParcelLayer& parcels) {
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& p : parcels.parcels)
    for (const auto& poly : p.shape)
      for (const auto& v : poly.outer) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  if (lo.x() > hi.x()) return std::nullopt;
  return Vec2((lo + hi) / 2);
}

// The layer's centre in WGS 84 lon/lat degrees, the layer being in `crs`.
std::optional<Vec2> centre_lonlat(const ParcelLayer& parcels, const std::string& crs) {
  const std::optional<Vec2> c = layer_centre(parcels);
  if (!c || crs.empty()) return std::nullopt;
  try {
    const MultiPolygon2 point{Polygon2{{*c}, {}}};
    return reproject(point, crs, wkt_from_epsg(4326), parcels.source)[0].outer[0];
  } catch (const std::exception&) {
    return std::nullopt;  // a local grid: where it lies on Earth is unknown
  }
}

// How far the CRS's areas are from true at the data (0.0147: 1.47 % too large); 0 when unknown.
double areal_distortion(const std::string& wkt, const std::optional<Vec2>& lonlat) {
  if (!lonlat) return 0;
  const double scale = areal_scale_at(wkt, lonlat->x(), lonlat->y());
  return scale > 0 ? std::abs(scale - 1) : 0;
}

bool fit_for_areas(const std::string& wkt, const std::optional<Vec2>& lonlat) {
  return is_metric(wkt) && areal_distortion(wkt, lonlat) <= kMaxArealDistortion;
}

std::string percent(double share) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f %%", share * 100);
  return buf;
}

// "EPSG:32748": the UTM zone over the layer's centre, for messages.
std::string utm_hint(const std::optional<Vec2>& lonlat) {
  if (!lonlat) return "<a projected CRS in metres>";
  return "EPSG:" + std::to_string(epsg_of(utm_wkt_at(lonlat->x(), lonlat->y())));
}

// Whether every vertex of the layer could be longitude, latitude.
bool within_degrees(const ParcelLayer& parcels) {
  for (const auto& p : parcels.parcels)
    for (const auto& poly : p.shape)
      for (const auto& v : poly.outer)
        if (std::abs(v.x()) > 180 || std::abs(v.y()) > 90) return false;
  return true;
}

// A layer claiming degrees with coordinates no degrees can be (a GeoJSON in
// UTM without a "crs" member, which GDAL reads as WGS 84) has no CRS known.
void drop_impossible_degrees(ParcelLayer& parcels, std::vector<std::string>& warnings) {
  if (!is_geographic(parcels.crs_wkt) || within_degrees(parcels)) return;
  warnings.push_back(parcels.source + ": coordinates are not degrees, so its CRS " + describe(parcels.crs_wkt) +
                     " is taken as unknown");
  parcels.crs_wkt.clear();
}

// A layer without CRS adopts the clouds' CRS, but only when they agree.
std::string adopt_cloud_crs(const ParcelLayer& parcels, const std::vector<PointCloud>& clouds,
                            std::vector<std::string>& warnings) {
  std::string crs;
  for (const PointCloud& c : clouds) {
    if (c.crs_wkt.empty()) continue;
    if (crs.empty()) {
      crs = c.crs_wkt;
      warnings.push_back(parcels.source + ": no CRS; assumed to be " + describe(c.crs_wkt) + " like " + c.source);
    } else if (!same_crs(crs, c.crs_wkt)) {
      throw InputError(c.source, "CRS " + describe(c.crs_wkt) + " differs from " + describe(crs) +
                                     " and the parcel layer " + parcels.source + " has no CRS to reproject to");
    }
  }
  return crs;
}

// The CRS areas are measured in; `reference` is the layer's (or the one it was assumed to be in).
std::string working_crs(const ParcelLayer& parcels, const std::string& reference,
                        const std::vector<PointCloud>& clouds, const Dtm* dtm, const std::string& wanted,
                        const std::optional<Vec2>& lonlat, std::vector<std::string>& warnings) {
  if (!wanted.empty()) {
    if (!is_metric(wanted)) throw InputError("--crs", describe(wanted) + " is not a projected CRS in metres");
    const double off = areal_distortion(wanted, lonlat);
    if (off > kMaxArealDistortion)
      warnings.push_back("--crs " + describe(wanted) + ": areas are " + percent(off) + " off true at the data");
    return wanted;
  }
  if (reference.empty() || fit_for_areas(reference, lonlat)) return reference;
  for (const PointCloud& c : clouds)
    if (!c.crs_wkt.empty() && fit_for_areas(c.crs_wkt, lonlat)) return c.crs_wkt;
  if (dtm && !dtm->crs_wkt.empty() && fit_for_areas(dtm->crs_wkt, lonlat)) return dtm->crs_wkt;
  const auto no_crs = std::find_if(clouds.begin(), clouds.end(), [](const PointCloud& c) { return c.crs_wkt.empty(); });
  if (!is_metric(reference) && no_crs != clouds.end())
    throw InputError(parcels.source, "CRS " + describe(reference) + " is not in metres and " + no_crs->source +
                                         " has no CRS to tell what its points are in; name the working CRS with "
                                         "--crs " + utm_hint(lonlat) + " or reproject the layer first, e.g. "
                                         "ogr2ogr -t_srs " + utm_hint(lonlat) + " parcels_utm.gpkg " + parcels.source);
  if (!lonlat)
    throw InputError(parcels.source, "CRS " + describe(reference) + " is not fit for areas and where the data lies "
                                         "cannot be told; name the working CRS with --crs EPSG:<code>");
  return utm_wkt_at(lonlat->x(), lonlat->y());
}

// Why the layer leaves its CRS, for the warning.
std::string why_reprojected(const std::string& from, const std::optional<Vec2>& lonlat) {
  if (!is_metric(from)) return "areas are measured in metres";
  const double off = areal_distortion(from, lonlat);
  if (off > kMaxArealDistortion) return "its areas are " + percent(off) + " off true at the data";
  return "the CRS named with --crs";
}

void reconcile_clouds(std::vector<PointCloud>& clouds, const std::string& reference, const std::string& working,
                      std::vector<std::string>& warnings) {
  // Points without a CRS are taken to be in the layer's, unless that is in degrees.
  const std::string assumed = is_metric(reference) ? reference : working;
  for (PointCloud& c : clouds) {
    if (c.crs_wkt.empty()) {
      if (!assumed.empty())
        warnings.push_back(c.source + ": no CRS; assumed to be " + describe(assumed) + " like the parcels");
      c.crs_wkt = assumed;
    }
    if (!same_crs(c.crs_wkt, working)) {
      const std::string from = describe(c.crs_wkt);
      reproject(c, working);
      warnings.push_back(c.source + ": reprojected from " + from + " to " + describe(working));
    }
  }
}

void check_dtm(const Dtm& dtm, const std::string& reference, const std::string& working,
               std::vector<std::string>& warnings) {
  std::string crs = dtm.crs_wkt;
  if (crs.empty() && !reference.empty()) {
    crs = is_metric(reference) ? reference : working;
    warnings.push_back(dtm.source + ": no CRS; assumed to be " + describe(crs));
  }
  if (crs.empty() || working.empty() || same_crs(crs, working)) return;
  const int code = epsg_of(working);
  throw InputError(dtm.source, "CRS " + describe(crs) + " differs from the working CRS " + describe(working) +
                                   " (docs/inputs.md); warp it first, e.g. gdalwarp -t_srs " +
                                   (code ? "EPSG:" + std::to_string(code) : std::string("<working CRS>")) + " " +
                                   dtm.source + " dtm_reprojected.tif");
}

}  // namespace

CrsReconciliation reconcile_crs(ParcelLayer& parcels, std::vector<PointCloud>& clouds, Dtm* dtm,
                                const std::string& wanted) {
  CrsReconciliation r;
  drop_impossible_degrees(parcels, r.warnings);
  const std::string reference =
      parcels.crs_wkt.empty() ? adopt_cloud_crs(parcels, clouds, r.warnings) : parcels.crs_wkt;
  const std::optional<Vec2> lonlat = centre_lonlat(parcels, reference);
  r.crs_wkt = working_crs(parcels, reference, clouds, dtm, wanted, lonlat, r.warnings);
  if (!reference.empty() && !same_crs(reference, r.crs_wkt)) {
    for (auto& p : parcels.parcels) p.shape = reproject(p.shape, reference, r.crs_wkt, parcels.source);
    r.warnings.push_back(parcels.source + ": reprojected from " + describe(reference) + " to " +
                         describe(r.crs_wkt) + " (" + why_reprojected(reference, lonlat) + ")");
  }
  parcels.crs_wkt = r.crs_wkt;
  reconcile_clouds(clouds, reference, r.crs_wkt, r.warnings);
  if (dtm) check_dtm(*dtm, reference, r.crs_wkt, r.warnings);
  return r;
}

}  // namespace c3d
