#include "cadastre/store/lods.h"

#include <stdexcept>

#include "cadastre/store/columns.h"
#include "cadastre/store/gpkg_geometry.h"
#include "cadastre/store/schema.h"
#include "core/error.h"

namespace c3d::store_lods {

namespace {

// The face types of a shell, comma-separated ("ground,wall,...,roof").
std::string joined(const std::vector<ElementType>& types) {
  std::string out;
  for (ElementType t : types) out += (out.empty() ? "" : ",") + std::string(to_string(t));
  return out;
}

std::vector<ElementType> split_types(const std::string& text) {
  std::vector<ElementType> out;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find(',', start);
    if (end == std::string::npos) end = text.size();
    const std::string name = text.substr(start, end - start);
    bool found = false;
    for (ElementType t : {ElementType::Roof, ElementType::Wall, ElementType::PartyWall, ElementType::Ground,
                          ElementType::OuterCeiling})
      if (name == to_string(t)) out.push_back(t), found = true;
    if (!found) throw std::invalid_argument("unknown face type '" + name + "'");
    start = end + 1;
  }
  return out;
}

}  // namespace

Writer::Writer(const sql::Db& db)
    : attributes_(db, store_columns::update_sql(store_columns::kBuildingAttributes)),
      lod_(db, store_columns::insert_sql(store_columns::kBuildingLod)) {}

void Writer::write(std::int64_t building_fid, const Building& b, const Vec3& origin, int srs) {
  const BuildingAttributes& a = b.attributes;
  const double z = origin.z();
  attributes_.bind(a.roof_type).bind(a.roof_z_min + z).bind(a.roof_z_50p + z).bind(a.roof_z_70p + z)
      .bind(a.roof_z_max + z).bind(a.roof_points).bind(a.point_density).bind(a.roof_rmse).bind(a.data_quality)
      .bind(static_cast<long long>(building_fid)).run();
  for (const LodShell& s : b.lower_lods)
    lod_.bind_blob(gpkg_faces_blob(s.faces, origin, srs)).bind(static_cast<long long>(building_fid)).bind(to_string(s.lod))
        .bind(joined(s.face_types)).bind(s.volume).bind(s.roof_rmse).run();
}

Reader::Reader(const sql::Db& db)
    : where_(sql::display_name(db.path())),
      has_attributes_(store_schema::has_column(db, "building", "data_quality")),
      has_lods_(store_schema::has_column(db, "building_lod", "face_types")) {
  using namespace store_columns;
  if (has_attributes_)
    attributes_ = sql::Stmt(db, "SELECT " + select_list(db, kBuildingAttributes) + " FROM building WHERE fid=?");
  if (has_lods_)
    lod_ = sql::Stmt(db, "SELECT " + select_list(db, kBuildingLod) + " FROM building_lod WHERE building_fid=? ORDER BY lod");
}

void Reader::read(std::int64_t building_fid, const Vec3& origin, Building& b) {
  if (has_attributes_) {
    attributes_.bind(static_cast<long long>(building_fid));
    if (attributes_.step()) {
      BuildingAttributes& a = b.attributes;
      const double z = origin.z();
      a.roof_type = attributes_.get_text("roof_type");
      a.roof_z_min = attributes_.get_double("roof_z_min") - z;
      a.roof_z_50p = attributes_.get_double("roof_z_50p") - z;
      a.roof_z_70p = attributes_.get_double("roof_z_70p") - z;
      a.roof_z_max = attributes_.get_double("roof_z_max") - z;
      a.roof_points = long(attributes_.get_int("roof_points"));
      a.point_density = attributes_.get_double("point_density");
      a.roof_rmse = attributes_.get_double("roof_rmse");
      a.data_quality = attributes_.get_text("data_quality");
    }
    attributes_.reset();
  }
  if (!has_lods_) return;
  lod_.bind(static_cast<long long>(building_fid));
  while (lod_.step()) {
    LodShell s;
    std::size_t n;
    const std::uint8_t* blob = lod_.blob("geom", &n);
    s.faces = gpkg_read_faces(blob, n, origin);
    try {
      s.lod = lod_from(lod_.get_text("lod"));
      s.face_types = split_types(lod_.get_text("face_types"));
    } catch (const std::invalid_argument& e) {
      throw InputError(where_, "building_lod of " + b.id + ": " + e.what());
    }
    s.volume = lod_.get_double("volume");
    s.roof_rmse = lod_.get_double("roof_rmse");
    if (s.face_types.size() != s.faces.size())
      throw InputError(where_, "building_lod of " + b.id + ": " + std::to_string(s.faces.size()) + " faces but " +
                                    std::to_string(s.face_types.size()) + " face types");
    b.lower_lods.push_back(std::move(s));
  }
  lod_.reset();
}

}  // namespace c3d::store_lods
