#include "cadastre/parcels.h"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>
#include <geos/geom/GeometryFactory.h>
#include <geos/operation/valid/IsValidOp.h>
#include <geos/operation/valid/MakeValid.h>
#include <geos/util/GEOSException.h>

#include <cmath>
#include <memory>
#include <sstream>

#include "core/geometry/geos_util.h"
#include "core/error.h"
#include "core/gdal_dataset.h"
#include "core/geometry/geometry.h"

namespace c3d {
namespace {

bool is_polygonal(OGRwkbGeometryType t) {
  t = wkbFlatten(t);
  return t == wkbPolygon || t == wkbMultiPolygon || t == wkbCurvePolygon || t == wkbMultiSurface;
}

Ring2 ring_from_ogr(const OGRLinearRing& r) {
  Ring2 out;
  for (int i = 0; i < r.getNumPoints(); ++i) out.emplace_back(r.getX(i), r.getY(i));
  if (out.size() > 1 && out.front() == out.back()) out.pop_back();  // rings are implicit-closed
  return out;
}

// Raw rings as stored (orientation untouched; GEOS validates and orients them).
MultiPolygon2 shape_from_ogr(const OGRGeometry& geom) {
  std::unique_ptr<OGRGeometry> linear(geom.hasCurveGeometry() ? geom.getLinearGeometry()
                                                              : geom.clone());
  MultiPolygon2 out;
  auto add = [&](const OGRPolygon& p) {
    if (p.IsEmpty()) return;
    Polygon2 poly{ring_from_ogr(*p.getExteriorRing()), {}};
    for (int i = 0; i < p.getNumInteriorRings(); ++i)
      poly.holes.push_back(ring_from_ogr(*p.getInteriorRing(i)));
    out.push_back(std::move(poly));
  };
  auto flat = wkbFlatten(linear->getGeometryType());
  if (flat == wkbPolygon) add(*linear->toPolygon());
  if (flat == wkbMultiPolygon)
    for (const OGRPolygon* p : *linear->toMultiPolygon()) add(*p);
  return out;
}

std::string where_text(const geos::geom::Coordinate& c) {
  std::ostringstream s;
  s.precision(3);
  s << std::fixed << c.x << " " << c.y;
  return s.str();
}

const geos::geom::GeometryFactory& factory() {
  static auto f = geos::geom::GeometryFactory::create();
  return *f;
}

struct Checked {
  MultiPolygon2 shape;   // valid, oriented
  std::string problem;   // why the input was invalid ("" if valid)
};

// Validates with GEOS and repairs with MakeValid; throws when nothing polygonal remains.
Checked check_shape(const MultiPolygon2& raw, const std::string& who) {
  Checked c;
  std::unique_ptr<geos::geom::Geometry> g;
  try {
    g = to_geos(raw, factory());
  } catch (const geos::util::GEOSException& e) {
    throw InputError(who, std::string("invalid polygon that cannot be repaired: ") + e.what());
  }
  geos::operation::valid::IsValidOp op(g.get());
  if (const auto* err = op.getValidationError()) {
    c.problem = err->getMessage() + " at (" + where_text(err->getCoordinate()) + ")";
    auto fixed = geos::operation::valid::MakeValid().build(g.get());
    c.shape = fixed ? from_geos(*fixed) : MultiPolygon2{};
    if (c.shape.empty() || area(c.shape) <= 0)
      throw InputError(who, "invalid polygon (" + c.problem + ") and MakeValid leaves no area");
  } else {
    c.shape = from_geos(*g);
  }
  return c;
}

std::string layer_crs(OGRLayer& layer) {
  const OGRSpatialReference* srs = layer.GetSpatialRef();
  if (!srs) return {};
  char* out = nullptr;
  if (srs->exportToWkt(&out) != OGRERR_NONE) {
    CPLFree(out);
    const char* opts[] = {"FORMAT=WKT2_2019", nullptr};
    srs->exportToWkt(&out, opts);
  }
  std::string wkt = out ? out : "";
  CPLFree(out);
  return wkt;
}

// First layer whose declared or actual geometry is polygonal; else layer 0.
OGRLayer* polygon_layer(GDALDataset& ds) {
  for (OGRLayer* layer : ds.GetLayers())
    if (is_polygonal(layer->GetGeomType())) return layer;
  return ds.GetLayerCount() > 0 ? ds.GetLayer(0) : nullptr;
}

std::string field_text(OGRFeature& f, int index) {
  if (index < 0 || !f.IsFieldSetAndNotNull(index)) return {};
  std::string s = f.GetFieldAsString(index);
  size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

}  // namespace

std::string validity_problem(const MultiPolygon2& shape) {
  try {
    auto g = to_geos(shape, factory());
    geos::operation::valid::IsValidOp op(g.get());
    if (const auto* err = op.getValidationError())
      return err->getMessage() + " at (" + where_text(err->getCoordinate()) + ")";
    return {};
  } catch (const geos::util::GEOSException& e) {
    return e.what();
  }
}

ParcelLayer read_parcels(const std::string& path, const ParcelFields& fields,
                         std::vector<std::string>* warnings) {
  register_gdal_drivers();
  auto warn = [&](const std::string& w) {
    if (warnings) warnings->push_back(path + ": " + w);
  };
  CPLPushErrorHandler(CPLQuietErrorHandler);
  GdalDataset ds(
      GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  CPLPopErrorHandler();
  if (!ds) throw InputError(path, "not a vector layer OGR can read");
  OGRLayer* layer = polygon_layer(*ds);
  if (!layer) throw InputError(path, "holds no layer");

  ParcelLayer out;
  out.source = path;
  out.crs_wkt = layer_crs(*layer);
  OGRFeatureDefn* defn = layer->GetLayerDefn();
  for (int i = 0; i < defn->GetFieldCount(); ++i)
    out.fields.push_back(defn->GetFieldDefn(i)->GetNameRef());
  auto field_index = [&](const std::string& name, bool required) {
    if (name.empty()) return -1;
    int i = defn->GetFieldIndex(name.c_str());
    if (i < 0 && required) {
      std::string list;
      for (const std::string& f : out.fields) list += (list.empty() ? "" : ", ") + f;
      throw InputError(path, "id field '" + name + "' not found (fields: " + list + ")");
    }
    return i;
  };
  int id_field = field_index(fields.id, fields.id_required);
  if (id_field < 0 && !fields.id.empty())
    warn("no field '" + fields.id + "': feature ids are the parcel ids");
  const int right_field = field_index(fields.right_type, false);
  const int area_field = field_index(fields.official_area, false);

  layer->ResetReading();
  long record = -1;
  for (auto& feature : *layer) {
    ++record;
    const std::string fid = std::to_string(feature->GetFID());
    std::string id = field_text(*feature, id_field);
    if (id.empty()) {
      if (id_field >= 0)
        warn("feature " + fid + " has an empty " + fields.id + "; its FID " + fid + " is the id");
      id = fid;
    }
    const std::string who = path + ": parcel " + id + " (record " + std::to_string(record) + ")";
    const OGRGeometry* geom = feature->GetGeometryRef();
    if (!geom || geom->IsEmpty() || !is_polygonal(geom->getGeometryType())) {
      warn("feature " + fid + " (" + (geom ? geom->getGeometryName() : "no geometry") +
           ") is not a polygon, skipped");
      continue;
    }
    Parcel p;
    p.index = int(out.parcels.size());
    p.id = id;
    p.right_type = field_text(*feature, right_field);
    if (area_field >= 0 && feature->IsFieldSetAndNotNull(area_field))
      p.official_area = feature->GetFieldAsDouble(area_field);
    Checked c = check_shape(shape_from_ogr(*geom), who);
    p.shape = std::move(c.shape);
    if (!c.problem.empty()) {
      std::ostringstream note;
      note.precision(2);
      note << std::fixed << "invalid polygon (" << c.problem << ") repaired by MakeValid, area "
           << area(p.shape) << " m2";
      p.repair_note = note.str();
      warn("parcel " + id + ": " + p.repair_note);
    }
    out.parcels.push_back(std::move(p));
  }
  if (out.parcels.empty()) throw InputError(path, "layer holds no polygon features (no parcels)");
  return out;
}

}  // namespace c3d
