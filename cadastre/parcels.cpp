#include "cadastre/parcels.h"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>
#include <geos/geom/GeometryFactory.h>
#include <geos/operation/valid/IsValidOp.h>
#include <geos/operation/valid/MakeValid.h>
#include <geos/util/GEOSException.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "core/geometry/geos_util.h"
#include "core/error.h"
#include "core/gdal_dataset.h"
#include "core/gdal_messages.h"
#include "core/geometry/geometry.h"
#include "core/io/read_limits.h"

namespace c3d {
namespace {

namespace fs = std::filesystem;

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

// Every vertex finite and within kMaxAbsCoordinate, before GEOS sees it.
void check_vertices(const MultiPolygon2& raw, const std::string& who) {
  size_t k = 0;
  auto check = [&](const Ring2& ring) {
    for (const Vec2& v : ring) {
      const std::string problem = coordinate_problem(v.x(), v.y(), 0, "vertex " + std::to_string(k++));
      if (!problem.empty()) throw InputError(who, problem);
    }
  };
  for (const Polygon2& poly : raw) {
    check(poly.outer);
    for (const Ring2& hole : poly.holes) check(hole);
  }
}

// Validates with GEOS and repairs with MakeValid; throws when nothing polygonal remains.
Checked check_shape(const MultiPolygon2& raw, const std::string& who) {
  check_vertices(raw, who);
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

// A path that names no local file but may be an OGR connection string
// ("PG:dbname=...", "WFS:...") or a GDAL virtual path ("/vsizip/a.zip/p.shp").
bool looks_like_connection(const std::string& path) {
  if (path.rfind("/vsi", 0) == 0) return true;
  const size_t colon = path.find(':');
  return colon != std::string::npos && colon > 1;  // not a drive letter ("C:\...")
}

GdalDataset open_source(const std::string& path, const GdalMessages& gdal) {
  GdalDataset ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  if (ds) return ds;
  std::error_code ec;
  if (!looks_like_connection(path) && !fs::exists(path, ec)) throw InputError(path, "does not exist");
  throw InputError(path, gdal.with_last("not a vector source OGR can read"));
}

std::string layer_list(GDALDataset& ds) {
  std::string s;
  for (OGRLayer* l : ds.GetLayers())
    s += (s.empty() ? "" : ", ") + std::string(l->GetName()) + " (" + OGRGeometryTypeToName(l->GetGeomType()) + ")";
  return s;
}

// The layer named, or the one layer with geometry; several without a name is an error.
OGRLayer* select_layer(GDALDataset& ds, const std::string& path, const std::string& name) {
  if (!name.empty()) {
    OGRLayer* layer = ds.GetLayerByName(name.c_str());
    if (!layer) throw InputError(path, "has no layer '" + name + "' (layers: " + layer_list(ds) + ")");
    return layer;
  }
  std::vector<OGRLayer*> spatial;
  for (OGRLayer* layer : ds.GetLayers())
    if (layer->GetGeomType() != wkbNone) spatial.push_back(layer);
  if (spatial.size() > 1)
    throw InputError(path, "holds " + std::to_string(spatial.size()) +
                               " layers; name the parcel layer with --layer (layers: " + layer_list(ds) + ")");
  if (spatial.size() == 1) return spatial[0];
  return ds.GetLayerCount() > 0 ? ds.GetLayer(0) : nullptr;
}

void apply_filters(OGRLayer& layer, const ParcelSelection& sel, const std::string& path, const GdalMessages& gdal) {
  if (!sel.where.empty()) {
    const size_t failed_before = gdal.failures();
    bool ok = layer.SetAttributeFilter(sel.where.c_str()) == OGRERR_NONE;
    if (ok) {  // some drivers (GeoPackage) find a bad filter only when reading
      layer.ResetReading();
      OGRFeature::DestroyFeature(layer.GetNextFeature());
      ok = gdal.failures() == failed_before;
    }
    if (!ok)
      throw InputError(path, gdal.with_last("--where \"" + sel.where + "\" is not an OGR SQL filter on layer " +
                                            layer.GetName()));
  }
  if (sel.bbox.empty()) return;
  if (sel.bbox.size() != 4 || !(sel.bbox[0] < sel.bbox[2]) || !(sel.bbox[1] < sel.bbox[3]))
    throw InputError(path, "--bbox needs xmin,ymin,xmax,ymax with xmin < xmax and ymin < ymax, in the layer's CRS");
  layer.SetSpatialFilterRect(sel.bbox[0], sel.bbox[1], sel.bbox[2], sel.bbox[3]);
}

// Offset of the first byte that breaks UTF-8 (RFC 3629: no overlong forms, no
// surrogates, nothing past U+10FFFF), or npos.
size_t invalid_utf8_at(const std::string& s) {
  auto byte = [&](size_t i) { return static_cast<unsigned char>(s[i]); };
  for (size_t i = 0; i < s.size();) {
    const unsigned char c = byte(i);
    if (c < 0x80) {
      ++i;
      continue;
    }
    const size_t n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
    if (n == 0 || i + n > s.size()) return i;
    // The second byte's range depends on the first (the overlong, surrogate and too-high forms).
    const unsigned char lo = c == 0xE0 ? 0xA0 : c == 0xF0 ? 0x90 : 0x80;
    const unsigned char hi = c == 0xED ? 0x9F : c == 0xF4 ? 0x8F : 0xBF;
    if (byte(i + 1) < lo || byte(i + 1) > hi) return i;
    for (size_t k = 2; k < n; ++k)
      if ((byte(i + k) >> 6) != 0x2) return i;
    i += n;
  }
  return std::string::npos;
}

// The text with bytes outside printable ASCII as \xNN, for an error line.
std::string escaped(const std::string& s) {
  std::string out;
  for (unsigned char c : s) {
    char buf[8];
    std::snprintf(buf, sizeof buf, c < 0x20 || c >= 0x7F ? "\\x%02X" : "%c", c);
    out += buf;
  }
  return out;
}

// Text a record holds must be UTF-8 (summary.json, the report, the store are).
void check_text(const std::string& text, const std::string& what, const std::string& fid, const std::string& path) {
  const size_t bad = invalid_utf8_at(text);
  if (bad == std::string::npos) return;
  throw InputError(path, "feature FID " + fid + ": " + what + " '" + escaped(text) + "' is not UTF-8 (byte " +
                             std::to_string(bad) + "); re-encode the source as UTF-8 (a Shapefile: a .cpg file "
                             "naming its code page, e.g. CP1252)");
}

// OGR cuts text at a NUL character without a word; in a text source (GeoJSON,
// CSV, GML, KML) such a character is refused before it can shorten an id.
void check_no_nul(const std::string& path) {
  static const std::set<std::string> text_formats = {".geojson", ".json", ".csv", ".gml", ".kml"};
  std::error_code ec;
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (!text_formats.count(ext) || !fs::is_regular_file(path, ec)) return;
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  size_t at = text.find('\0');
  if (at == std::string::npos) at = text.find("\\u0000");
  if (at != std::string::npos)
    throw InputError(path, "holds a NUL character at byte " + std::to_string(at) +
                               "; OGR would cut the text there (an id 'A<NUL>B' would become 'A'): remove it");
}

std::string field_text(OGRFeature& f, int index) {
  if (index < 0 || !f.IsFieldSetAndNotNull(index)) return {};
  std::string s = f.GetFieldAsString(index);
  size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

// Every field of the feature, typed as the layer declares it.
std::vector<ParcelAttribute> feature_attributes(OGRFeature& f) {
  std::vector<ParcelAttribute> out;
  for (int i = 0; i < f.GetFieldCount(); ++i) {
    const OGRFieldDefn* d = f.GetFieldDefnRef(i);
    ParcelAttribute a;
    a.name = d->GetNameRef();
    const OGRFieldType t = d->GetType();
    a.kind = t == OFTInteger || t == OFTInteger64 ? ParcelAttribute::Kind::Integer
             : t == OFTReal                       ? ParcelAttribute::Kind::Real
                                                  : ParcelAttribute::Kind::Text;
    a.is_null = !f.IsFieldSetAndNotNull(i);
    if (!a.is_null) a.value = f.GetFieldAsString(i);
    out.push_back(std::move(a));
  }
  return out;
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

namespace {

using Warn = std::function<void(const std::string&)>;

struct FieldIndexes {
  int id = -1, right = -1, area = -1;
};

FieldIndexes field_indexes(OGRFeatureDefn& defn, const ParcelFields& fields, ParcelLayer& out, const Warn& warn) {
  for (int i = 0; i < defn.GetFieldCount(); ++i) out.fields.push_back(defn.GetFieldDefn(i)->GetNameRef());
  auto index = [&](const std::string& name, bool required) {
    if (name.empty()) return -1;
    int i = defn.GetFieldIndex(name.c_str());
    if (i < 0 && required) {
      std::string list;
      for (const std::string& f : out.fields) list += (list.empty() ? "" : ", ") + f;
      throw InputError(out.source, "id field '" + name + "' not found (fields: " + list + ")");
    }
    return i;
  };
  FieldIndexes ix{index(fields.id, fields.id_required), index(fields.right_type, false),
                  index(fields.official_area, false)};
  if (ix.id < 0 && !fields.id.empty()) warn("no field '" + fields.id + "': feature ids are the parcel ids");
  return ix;
}

// The features of the (filtered) layer as parcels; ids checked unique and UTF-8.
// A feature GDAL failed to read (a truncated .shp reads as "no geometry") is an error, not a skip.
void read_features(OGRLayer& layer, const FieldIndexes& ix, const ParcelFields& fields, ParcelLayer& out,
                   const Warn& warn, const GdalMessages& gdal) {
  const std::string& path = out.source;
  std::map<std::string, std::string> fid_of_id;
  const size_t failed_before = gdal.failures();
  layer.ResetReading();
  long record = -1;
  for (auto& feature : layer) {
    ++record;
    const std::string fid = std::to_string(feature->GetFID());
    if (gdal.failures() > failed_before)
      throw InputError(path, "feature FID " + fid + " (record " + std::to_string(record) + ") cannot be read: " +
                                 gdal.last());
    std::string id = field_text(*feature, ix.id);
    if (id.empty()) {
      if (ix.id >= 0) warn("feature " + fid + " has an empty " + fields.id + "; its FID " + fid + " is the id");
      id = fid;
    }
    check_text(id, "parcel id", fid, path);
    const OGRGeometry* geom = feature->GetGeometryRef();
    if (!geom || geom->IsEmpty() || !is_polygonal(geom->getGeometryType())) {
      warn("feature " + fid + " (" + (geom ? geom->getGeometryName() : "no geometry") + ") is not a polygon, skipped");
      continue;
    }
    const auto [first, fresh] = fid_of_id.emplace(id, fid);
    if (!fresh)
      throw InputError(path, "parcel id '" + id + "' is held by features FID " + first->second + " and FID " + fid +
                                 "; ids must be unique (or name another id field with --id-field NAME)");
    Parcel p;
    p.index = int(out.parcels.size());
    p.id = id;
    p.right_type = field_text(*feature, ix.right);
    check_text(p.right_type, fields.right_type, fid, path);
    if (ix.area >= 0 && feature->IsFieldSetAndNotNull(ix.area)) p.official_area = feature->GetFieldAsDouble(ix.area);
    p.attributes = feature_attributes(*feature);
    Checked c = check_shape(shape_from_ogr(*geom), path + ": parcel " + id + " (record " + std::to_string(record) + ")");
    p.shape = std::move(c.shape);
    if (!c.problem.empty()) {
      std::ostringstream note;
      note.precision(2);
      note << std::fixed << "invalid polygon (" << c.problem << ") repaired by MakeValid, area " << area(p.shape)
           << " m2";
      p.repair_note = note.str();
      warn("parcel " + id + ": " + p.repair_note);
    }
    out.parcels.push_back(std::move(p));
  }
  if (gdal.failures() > failed_before)  // the reading stopped at a broken record
    throw InputError(path, "cannot be read after record " + std::to_string(record) + ": " + gdal.last());
}

ParcelLayer read_source(const std::string& path, const ParcelSelection& selection, const ParcelFields& fields,
                        const Warn& warn, const GdalMessages& gdal) {
  check_no_nul(path);
  GdalDataset ds = open_source(path, gdal);
  OGRLayer* layer = select_layer(*ds, path, selection.layer);
  if (!layer) throw InputError(path, "holds no layer");
  apply_filters(*layer, selection, path, gdal);
  ParcelLayer out;
  out.source = path;
  out.crs_wkt = layer_crs(*layer);
  const FieldIndexes ix = field_indexes(*layer->GetLayerDefn(), fields, out, warn);
  read_features(*layer, ix, fields, out, warn, gdal);
  if (gdal.count() > 0)  // warnings only (a failure throws): one line, the rest in the debug log
    warn("GDAL reported " + std::to_string(gdal.count()) + " message(s), the last: " + gdal.last());
  if (out.parcels.empty())
    throw InputError(path, std::string("layer ") + layer->GetName() + " holds no polygon features (no parcels)" +
                               (selection.where.empty() && selection.bbox.empty() ? "" : " that --where/--bbox select"));
  return out;
}

}  // namespace

ParcelLayer read_parcels(const std::string& path, const ParcelSelection& selection, const ParcelFields& fields,
                         std::vector<std::string>* warnings) {
  register_gdal_drivers();
  const Warn warn = [&](const std::string& w) {
    if (warnings) warnings->push_back(path + ": " + w);
  };
  GdalMessages gdal;  // GDAL prints nothing; its last word joins the error
  try {
    return read_source(path, selection, fields, warn, gdal);
  } catch (const InputError& e) {
    throw gdal.fold(e);
  }
}

}  // namespace c3d
