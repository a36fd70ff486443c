#include "core/io/crs.h"

#include <ogr_spatialref.h>
#include <proj.h>

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
  CPLPushErrorHandler(CPLQuietErrorHandler);  // callers say what failed, in one line
  bool ok = srs.importFromWkt(text.c_str()) == OGRERR_NONE;
  const char* opts[] = {"ALLOW_NETWORK_ACCESS=NO", "ALLOW_FILE_ACCESS=NO", nullptr};
  ok = ok || srs.SetFromUserInput(text.c_str(), opts) == OGRERR_NONE;
  CPLPopErrorHandler();
  return ok;
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

double areal_scale_at(const std::string& wkt, double lon_deg, double lat_deg) {
  OGRSpatialReference srs;
  if (!parse_horizontal(wkt, srs) || !srs.IsProjected()) return 0;
  char* text = nullptr;
  const char* opts[] = {"FORMAT=WKT2_2019", nullptr};
  srs.exportToWkt(&text, opts);
  const std::string wkt2 = text ? text : "";
  CPLFree(text);
  PJ_CONTEXT* ctx = proj_context_create();
  proj_log_level(ctx, PJ_LOG_NONE);  // a failure answers 0; PROJ need not print it
  PJ* crs = proj_create(ctx, wkt2.c_str());
  double scale = 0;
  if (crs) {
    PJ_FACTORS f = proj_factors(crs, proj_coord(proj_torad(lon_deg), proj_torad(lat_deg), 0, 0));
    if (proj_context_errno(ctx) == 0 && std::isfinite(f.areal_scale)) scale = f.areal_scale;
    proj_destroy(crs);
  }
  proj_context_destroy(ctx);
  return scale;
}

std::string utm_wkt_at(double lon_deg, double lat_deg) {
  const int zone = std::clamp(int(std::floor((lon_deg + 180) / 6)) + 1, 1, 60);
  return wkt_from_epsg((lat_deg < 0 ? 32700 : 32600) + zone);
}

std::string areas_crs_text(const std::string& wkt) {
  if (wkt.empty()) return "the inputs' coordinates (no CRS)";
  OGRSpatialReference srs;
  const std::string name = parse_horizontal(wkt, srs) && srs.GetName() ? srs.GetName() : "unnamed CRS";
  const int code = epsg_of(wkt);
  return (code ? "EPSG:" + std::to_string(code) : std::string("no EPSG code")) + " (" + name + ")";
}

std::string user_crs_wkt(const std::string& text, const std::string& where) {
  OGRSpatialReference srs;
  if (!parse(text, srs)) throw InputError(where, "'" + text + "' is not a CRS (try EPSG:32748)");
  char* out = nullptr;
  if (srs.exportToWkt(&out) != OGRERR_NONE) {
    CPLFree(out);
    const char* opts[] = {"FORMAT=WKT2_2019", nullptr};
    srs.exportToWkt(&out, opts);
  }
  const std::string wkt = out ? out : "";
  CPLFree(out);
  if (!is_metric(wkt))
    throw InputError(where, describe(wkt) + " is not a projected CRS in metres; areas need one");
  return wkt;
}

}  // namespace c3d
