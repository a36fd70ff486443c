#include "cadastre/store/gis.h"

#include <algorithm>
#include <cctype>

#include "cadastre/store/gpkg_geometry.h"
#include "cadastre/store/schema.h"
#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"

namespace c3d::store_gis {

namespace {

// The parcel layer's own columns in insert order (after the geometry).
const char* const kParcelColumns[] = {
    "spatialunit_id", "parcel_id", "layer_index", "status", "reason", "right_type", "ladm_right_type",
    "official_area", "computed_area", "repair_note", "buildings", "roof_area", "wall_area",
    "ground_area", "volume", "zone", "quality", "land_area", "land_area_source", "land_price_per_m2",
    "land_value", "building_cost", "building_value", "sigma_building_value", "njop", "sigma_njop",
    "njop_per_m2", "taxable", "tax", "sigma_tax", "currency", "valuation_note"};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

std::string quoted(const std::string& name) {
  std::string q = "\"";
  for (char c : name) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

void bind_attribute(sql::Stmt& s, const ParcelAttribute& a) {
  if (a.is_null) {
    s.bind_null();
    return;
  }
  try {
    if (a.kind == ParcelAttribute::Kind::Integer) s.bind(std::stoll(a.value));
    else if (a.kind == ParcelAttribute::Kind::Real) s.bind(std::stod(a.value));
    else s.bind(a.value);
  } catch (const std::exception&) {
    s.bind(a.value);  // not a number after all: keep the text
  }
}

Polygon2 projection(const Face& f, const Vec3& off) {
  Polygon2 p;
  for (const Vec3& v : f.ring) p.outer.push_back((v + off).head<2>());
  for (const Ring3& h : f.holes) {
    Ring2 r;
    for (const Vec3& v : h) r.push_back((v + off).head<2>());
    if (r.size() >= 3) p.holes.push_back(std::move(r));
  }
  return p;
}

}  // namespace

MultiPolygon2 plan_of(const std::vector<Face>& faces, const Vec3& offset, bool* repaired) {
  std::vector<MultiPolygon2> parts;
  bool any_repair = false;
  for (const Face& f : faces) {
    if (f.ring.size() < 3) continue;
    MultiPolygon2 one{projection(f, offset)};
    if (!poly::is_valid(one)) {
      one = poly::make_valid(one);
      if (one.empty()) continue;  // a vertical face: no plan, nothing repaired
      any_repair = true;
    }
    parts.push_back(std::move(one));
  }
  if (repaired) *repaired = any_repair;
  if (parts.empty()) return {};
  MultiPolygon2 out = poly::unite_all(parts);
  return poly::is_valid(out) ? out : poly::make_valid(out);
}

MultiPolygon2 footprint_of(const Building& b, const Vec3& offset) {
  std::vector<Face> ground;
  for (const Element& e : b.elements)
    if (e.type == ElementType::Ground) ground.insert(ground.end(), e.faces.begin(), e.faces.end());
  if (ground.empty())
    for (const Face& f : b.solid)
      if (unit_normal(f).z() < -0.99) ground.push_back(f);  // facing straight down
  return plan_of(ground, offset);
}

Writer::Writer(sql::Db& db, int srs) : db_(&db), srs_(srs) {
  ins_footprint_ = sql::Stmt(
      db,
      "INSERT INTO building_footprint (geom, building_fid, building_id, parcel_id, lod, lod_note, "
      "roof_type, data_quality, footprint_area, volume, eave_height, ridge_height, ground_z, roof_z_min, "
      "roof_z_50p, roof_z_70p, roof_z_max, storeys, roof_points, point_density, roof_rmse, wall_rmse, "
      "solid_valid, roof_planes, roof_area, sigma_roof_area, roof_plan_area, wall_area, sigma_wall_area, "
      "party_wall_area, sigma_party_wall_area, ground_area, sigma_ground_area, outer_ceiling_area, "
      "sigma_outer_ceiling_area, building_cost, parcel_njop, parcel_tax, currency) "
      "VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
  ins_roof_ = sql::Stmt(db,
                        "INSERT INTO roof_part (geom, element_fid, building_id, parcel_id, element_index, "
                        "area, plan_area, sigma_area, slope_deg, azimuth_deg, support_points, rmse, "
                        "plan_note) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?)");
  for (const std::string& c : store_schema::columns_of(db, "parcel")) parcel_columns_.insert(lower(c));
}

void Writer::add_input_columns(const std::vector<Parcel>& parcels) {
  for (const Parcel& p : parcels)
    for (const ParcelAttribute& a : p.attributes) input_column(a);
}

std::string Writer::input_column(const ParcelAttribute& a) {
  static const std::set<std::string> own = [] {
    std::set<std::string> s{"fid", "geom"};
    for (const char* c : kParcelColumns) s.insert(c);
    return s;
  }();
  const std::string name = own.count(lower(a.name)) ? "src_" + a.name : a.name;
  if (parcel_columns_.insert(lower(name)).second) {
    const char* type = a.kind == ParcelAttribute::Kind::Integer ? "INTEGER"
                       : a.kind == ParcelAttribute::Kind::Real  ? "DOUBLE"
                                                                : "TEXT";
    // Another writer of a shared database may have added it since we looked.
    db_->exec(std::string("ALTER TABLE parcel ADD COLUMN ") + (db_->postgres() ? "IF NOT EXISTS " : "") +
              quoted(name) + " " + store_schema::column_type(*db_, type));
  }
  return name;
}

void Writer::parcel(const Parcel& p, std::int64_t su, const ParcelResult& r, const ParcelValuation& v) {
  std::string cols = "geom", marks = "?";
  for (const char* c : kParcelColumns) cols += std::string(",") + c, marks += ",?";
  for (const ParcelAttribute& a : p.attributes) cols += "," + quoted(input_column(a)), marks += ",?";
  sql::Stmt s(*db_, "INSERT INTO parcel (" + cols + ") VALUES (" + marks + ")");
  BuildingTotals sum;
  double volume = 0;
  for (const Building& b : r.buildings) {
    const BuildingTotals t = totals(b);
    sum.roof += t.roof, sum.wall += t.wall, sum.ground += t.ground;
    volume += b.volume;
  }
  const char* code = store_schema::ladm_right_type(p.right_type);
  s.bind_blob(gpkg_multipolygon_blob(p.shape, srs_)).bind(su).bind(p.id).bind(p.index)
      .bind(to_string(r.status)).bind(r.reason).bind(p.right_type);
  if (code) s.bind(code);
  else s.bind_null();
  s.bind(p.official_area).bind(area(p.shape)).bind(p.repair_note).bind(int(r.buildings.size()))
      .bind(sum.roof).bind(sum.wall).bind(sum.ground).bind(volume).bind(v.zone).bind(v.quality)
      .bind(v.land_area).bind(v.land_area_source).bind(v.land_price_per_m2).bind(v.land_value)
      .bind(v.building_cost).bind(v.building_value).bind(v.sigma_building_value).bind(v.njop)
      .bind(v.sigma_njop).bind(v.land_area > 0 ? v.njop / v.land_area : kNaN).bind(v.taxable)
      .bind(v.tax).bind(v.sigma_tax).bind(v.currency).bind(v.note);
  for (const ParcelAttribute& a : p.attributes) bind_attribute(s, a);
  s.run();
}

void Writer::building(const Building& b, std::int64_t building_fid, const std::string& parcel_id,
                      const Vec3& off, const ParcelValuation& v) {
  const MultiPolygon2 plan = footprint_of(b, off);
  const BuildingTotals t = totals(b);
  const BuildingAttributes& a = b.attributes;
  double cost = 0;
  for (const CostItem& c : v.items) cost += c.building_id == b.id ? c.amount : 0.0;
  auto& s = ins_footprint_;
  s.bind_blob(gpkg_multipolygon_blob(plan, srs_)).bind(building_fid).bind(b.id).bind(parcel_id)
      .bind(to_string(b.lod)).bind(b.lod_note).bind(a.roof_type).bind(a.data_quality).bind(area(plan))
      .bind(b.volume).bind(b.eave_height).bind(b.ridge_height).bind(b.terrain_z + off.z());
  for (double z : {a.roof_z_min, a.roof_z_50p, a.roof_z_70p, a.roof_z_max}) s.bind(z + off.z());  // NaN stays NULL
  s.bind(b.storeys).bind(a.roof_points).bind(a.point_density).bind(b.roof_deviation.rmse)
      .bind(b.wall_deviation.rmse).bind(b.solid_valid ? 1 : 0).bind(t.roof_planes).bind(t.roof)
      .bind(t.sigma_roof).bind(t.roof_plan).bind(t.wall).bind(t.sigma_wall).bind(t.party_wall)
      .bind(t.sigma_party_wall).bind(t.ground).bind(t.sigma_ground).bind(t.outer_ceiling)
      .bind(t.sigma_outer_ceiling).bind(cost).bind(v.njop).bind(v.tax).bind(v.currency).run();
}

void Writer::roof_part(const Element& e, std::int64_t element_fid, int index, const std::string& building_id,
                       const std::string& parcel_id, const Vec3& off) {
  bool repaired = false;
  const MultiPolygon2 plan = plan_of(e.faces, off, &repaired);
  ins_roof_.bind_blob(gpkg_multipolygon_blob(plan, srs_)).bind(element_fid).bind(building_id)
      .bind(parcel_id).bind(index).bind(e.area).bind(e.plan_area).bind(e.sigma_area).bind(e.slope_deg)
      .bind(e.azimuth_deg).bind(e.support_points).bind(e.rmse)
      .bind(repaired ? "plan crossed itself: repaired by GEOS MakeValid" : "").run();
}

}  // namespace c3d::store_gis
