#include "core/io/crs.h"

#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "core/error.h"

namespace c3d {
namespace {

// Parses WKT (any dialect) or "EPSG:n"; never touches files or the network.
bool parse(const std::string& text, OGRSpatialReference& srs) {
  if (text.empty()) return false;
  if (srs.importFromWkt(text.c_str()) == OGRERR_NONE) return true;
  const char* opts[] = {"ALLOW_NETWORK_ACCESS=NO", "ALLOW_FILE_ACCESS=NO", nullptr};
  return srs.SetFromUserInput(text.c_str(), opts) == OGRERR_NONE;
}

// Horizontal part only: a DTM carries a compound CRS (UTM + vertical) that is
// still "the same" as the 2D parcels CRS for every use here.
bool parse_horizontal(const std::string& text, OGRSpatialReference& srs) {
  if (!parse(text, srs)) return false;
  if (srs.IsCompound()) srs.StripVertical();
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return true;
}

int authority_epsg(const OGRSpatialReference& srs) {
  const char* name = srs.GetAuthorityName(nullptr);
  const char* code = srs.GetAuthorityCode(nullptr);
  if (name && code && EQUAL(name, "EPSG")) return std::atoi(code);
  return 0;
}

std::string describe(const std::string& wkt) { return crs_display_name(wkt); }

}  // namespace

int epsg_of(const std::string& wkt) {
  OGRSpatialReference srs;
  if (!parse_horizontal(wkt, srs)) return 0;
  if (int code = authority_epsg(srs)) return code;
  // ESRI-style WKT ("WGS_1984_UTM_Zone_48S") carries no authority: ask PROJ.
  OGRSpatialReference probe(srs);
  if (probe.AutoIdentifyEPSG() == OGRERR_NONE)
    if (int code = authority_epsg(probe)) return code;
  int n = 0;
  int* confidence = nullptr;
  OGRSpatialReferenceH* matches = srs.FindMatches(nullptr, &n, &confidence);
  int code = 0;
  if (n > 0 && confidence[0] >= 90)
    code = authority_epsg(*OGRSpatialReference::FromHandle(matches[0]));
  OSRFreeSRSArray(matches);
  CPLFree(confidence);
  return code;
}

std::string wkt_from_epsg(int epsg) {
  OGRSpatialReference srs;
  if (srs.importFromEPSG(epsg) != OGRERR_NONE)
    throw std::runtime_error("unknown EPSG code " + std::to_string(epsg));
  char* out = nullptr;
  if (srs.exportToWkt(&out) != OGRERR_NONE) {  // WKT1 cannot express every CRS
    CPLFree(out);
    const char* opts[] = {"FORMAT=WKT2_2019", nullptr};
    srs.exportToWkt(&out, opts);
  }
  std::string wkt = out ? out : "";
  CPLFree(out);
  return wkt;
}

bool same_crs(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  if (a == b) return true;
  OGRSpatialReference sa, sb;
  if (!parse_horizontal(a, sa) || !parse_horizontal(b, sb)) return false;
  const char* opts[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES",
                        "CRITERION=EQUIVALENT_EXCEPT_AXIS_ORDER_GEOGCRS", nullptr};
  if (sa.IsSame(&sb, opts)) return true;
  // Same EPSG code: equal even when the WKT dialects (ESRI vs OGC) differ in detail.
  int ea = epsg_of(a);
  return ea != 0 && ea == epsg_of(b);
}

std::string crs_display_name(const std::string& wkt) {
  if (wkt.empty()) return "(none)";
  OGRSpatialReference srs;
  if (!parse_horizontal(wkt, srs)) return "(unreadable CRS)";
  std::string name = srs.GetName() ? srs.GetName() : "unnamed CRS";
  int code = epsg_of(wkt);
  return code ? name + " (EPSG:" + std::to_string(code) + ")" : name + " (no EPSG code)";
}

namespace {

struct TransformDeleter {
  void operator()(OGRCoordinateTransformation* t) const {
    OGRCoordinateTransformation::DestroyCT(t);
  }
};
using Transform = std::unique_ptr<OGRCoordinateTransformation, TransformDeleter>;

Transform make_transform(const std::string& from, const std::string& to, const std::string& where) {
  OGRSpatialReference src, dst;
  if (!parse(from, src) || !parse(to, dst))
    throw InputError(where, "cannot reproject from " + describe(from) + " to " + describe(to) +
                                ": unreadable CRS");
  src.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  dst.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  CPLPushErrorHandler(CPLQuietErrorHandler);  // the InputError below says it better
  Transform t(OGRCreateCoordinateTransformation(&src, &dst));
  CPLPopErrorHandler();
  if (!t)
    throw InputError(where, "cannot reproject from " + describe(from) + " to " + describe(to) +
                                ": no transformation between them");
  return t;
}

}  // namespace

void reproject_points(std::vector<Vec3>& points, const std::string& from_wkt,
                      const std::string& to_wkt, const std::string& where) {
  Transform t = make_transform(from_wkt, to_wkt, where);
  constexpr size_t kChunk = 1 << 16;  // bounded scratch memory for huge clouds
  std::vector<double> x, y, z;
  std::vector<int> ok;
  for (size_t start = 0; start < points.size(); start += kChunk) {
    size_t n = std::min(kChunk, points.size() - start);
    x.resize(n), y.resize(n), z.resize(n), ok.assign(n, 0);
    for (size_t i = 0; i < n; ++i) {
      const Vec3& p = points[start + i];
      x[i] = p.x(), y[i] = p.y(), z[i] = p.z();
    }
    t->Transform(n, x.data(), y.data(), z.data(), nullptr, ok.data());
    for (size_t i = 0; i < n; ++i) {
      if (!ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i]))
        throw InputError(where, "cannot reproject point " + std::to_string(start + i) + " from " +
                                    describe(from_wkt) + " to " + describe(to_wkt));
      points[start + i] = Vec3(x[i], y[i], z[i]);
    }
  }
}

MultiPolygon2 reproject(const MultiPolygon2& shape, const std::string& from_wkt,
                        const std::string& to_wkt, const std::string& where) {
  Transform t = make_transform(from_wkt, to_wkt, where);
  auto ring = [&](const Ring2& r) {
    Ring2 out = r;
    for (Vec2& v : out)
      if (!t->Transform(1, &v.x(), &v.y()))
        throw InputError(where, "cannot reproject a vertex from " + describe(from_wkt) + " to " +
                                    describe(to_wkt));
    return out;
  };
  MultiPolygon2 out;
  for (const Polygon2& p : shape) {
    Polygon2 q{ring(p.outer), {}};
    for (const Ring2& h : p.holes) q.holes.push_back(ring(h));
    out.push_back(std::move(q));
  }
  return out;
}

void reproject(PointCloud& cloud, const std::string& to_wkt) {
  if (cloud.crs_wkt.empty())
    throw InputError(cloud.source, "has no CRS, cannot reproject it to " + describe(to_wkt));
  reproject_points(cloud.points, cloud.crs_wkt, to_wkt, cloud.source);
  cloud.crs_wkt = to_wkt;
}

bool is_metric(const std::string& wkt) {
  OGRSpatialReference srs;
  return parse_horizontal(wkt, srs) && srs.IsProjected() && std::abs(srs.GetLinearUnits() - 1.0) < 1e-9;
}

namespace {

// "EPSG:327zz": the UTM zone over the layer's centre, for the error message.
std::string utm_hint(const ParcelLayer& parcels) {
  double lon = 0, lat = 0;
  size_t n = 0;
  for (const auto& p : parcels.parcels)
    for (const auto& poly : p.shape)
      for (const auto& v : poly.outer) lon += v.x(), lat += v.y(), ++n;
  if (n == 0) return "<a projected CRS in metres>";
  lon /= double(n), lat /= double(n);
  if (std::abs(lon) > 180 || std::abs(lat) > 84) return "<a projected CRS in metres>";
  const int zone = std::clamp(int(std::floor((lon + 180) / 6)) + 1, 1, 60);
  return "EPSG:" + std::to_string((lat < 0 ? 32700 : 32600) + zone);
}

// Whether every vertex of the layer could be longitude, latitude.
bool within_degrees(const ParcelLayer& parcels) {
  for (const auto& p : parcels.parcels)
    for (const auto& poly : p.shape)
      for (const auto& v : poly.outer)
        if (std::abs(v.x()) > 180 || std::abs(v.y()) > 90) return false;
  return true;
}

// Measuring needs metres: a layer in degrees (GeoJSON is WGS 84 by its
// standard) or in feet goes into the first clouds' CRS that is in metres. A
// layer claiming degrees with coordinates no degrees can be (a GeoJSON in UTM
// without a "crs" member, which GDAL reads as WGS 84) has no CRS known.
void put_parcels_in_metres(ParcelLayer& parcels, const std::vector<PointCloud>& clouds,
                           std::vector<std::string>& warnings) {
  if (parcels.crs_wkt.empty() || is_metric(parcels.crs_wkt)) return;
  OGRSpatialReference srs;
  if (parse_horizontal(parcels.crs_wkt, srs) && srs.IsGeographic() && !within_degrees(parcels)) {
    warnings.push_back(parcels.source + ": coordinates are not degrees, so its CRS " + describe(parcels.crs_wkt) +
                       " is taken as unknown");
    parcels.crs_wkt.clear();
    return;
  }
  for (const PointCloud& c : clouds) {
    if (!is_metric(c.crs_wkt)) continue;
    for (auto& p : parcels.parcels) p.shape = reproject(p.shape, parcels.crs_wkt, c.crs_wkt, parcels.source);
    warnings.push_back(parcels.source + ": reprojected from " + describe(parcels.crs_wkt) + " to " +
                       describe(c.crs_wkt) + " like " + c.source + " (areas are measured in metres)");
    parcels.crs_wkt = c.crs_wkt;
    return;
  }
  throw InputError(parcels.source, "CRS " + describe(parcels.crs_wkt) +
                                       " is not in metres and no point cloud carries a CRS that is; "
                                       "reproject the layer first, e.g. ogr2ogr -t_srs " + utm_hint(parcels) +
                                       " parcels_utm.gpkg " + parcels.source);
}

}  // namespace

CrsReconciliation reconcile_crs(ParcelLayer& parcels, std::vector<PointCloud>& clouds, Dtm* dtm) {
  CrsReconciliation r;
  put_parcels_in_metres(parcels, clouds, r.warnings);
  r.crs_wkt = parcels.crs_wkt;
  if (r.crs_wkt.empty()) {
    // No reference: adopt the clouds' CRS, but only when they agree.
    for (const PointCloud& c : clouds) {
      if (c.crs_wkt.empty()) continue;
      if (r.crs_wkt.empty()) {
        r.crs_wkt = c.crs_wkt;
        r.warnings.push_back(parcels.source + ": no CRS; assumed to be " + describe(c.crs_wkt) +
                             " like " + c.source);
      } else if (!same_crs(r.crs_wkt, c.crs_wkt)) {
        throw InputError(c.source, "CRS " + describe(c.crs_wkt) + " differs from " +
                                       describe(r.crs_wkt) + " and the parcel layer " +
                                       parcels.source + " has no CRS to reproject to");
      }
    }
  }
  for (PointCloud& c : clouds) {
    if (c.crs_wkt.empty()) {
      if (!r.crs_wkt.empty())
        r.warnings.push_back(c.source + ": no CRS; assumed to be " + describe(r.crs_wkt) +
                             " like the parcels");
      c.crs_wkt = r.crs_wkt;
    } else if (!same_crs(c.crs_wkt, r.crs_wkt)) {
      std::string from = describe(c.crs_wkt);
      reproject(c, r.crs_wkt);
      r.warnings.push_back(c.source + ": reprojected from " + from + " to " + describe(r.crs_wkt));
    }
  }
  if (dtm) {
    if (dtm->crs_wkt.empty()) {
      if (!r.crs_wkt.empty())
        r.warnings.push_back(dtm->source + ": no CRS; assumed to be " + describe(r.crs_wkt));
    } else if (!r.crs_wkt.empty() && !same_crs(dtm->crs_wkt, r.crs_wkt)) {
      int code = epsg_of(r.crs_wkt);
      throw InputError(dtm->source,
                       "CRS " + describe(dtm->crs_wkt) + " differs from the parcels' " +
                           describe(r.crs_wkt) + "; warp it first, e.g. gdalwarp -t_srs " +
                           (code ? "EPSG:" + std::to_string(code) : std::string("<parcels CRS>")) +
                           " " + dtm->source + " dtm_reprojected.tif");
    }
  }
  return r;
}

}  // namespace c3d
