#include "cadastre/store/lods.h"

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
    if (!found) throw InputError("store", "unknown face type '" + name + "' in building_lod");
    start = end + 1;
  }
  return out;
}

}  // namespace

Writer::Writer(const sql::Db& db)
    : attributes_(db,
                  "UPDATE building SET roof_type=?, roof_z_min=?, roof_z_50p=?, roof_z_70p=?, roof_z_max=?, "
                  "roof_points=?, point_density=?, roof_rmse=?, data_quality=? WHERE fid=?"),
      lod_(db,
           "INSERT INTO building_lod (geom, building_fid, lod, face_types, volume, roof_rmse) "
           "VALUES (?,?,?,?,?,?)") {}

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
    : has_attributes_(store_schema::has_column(db, "building", "data_quality")),
      has_lods_(store_schema::has_column(db, "building_lod", "face_types")) {
  if (has_attributes_)
    attributes_ = sql::Stmt(db,
                            "SELECT roof_type, roof_z_min, roof_z_50p, roof_z_70p, roof_z_max, roof_points, "
                            "point_density, roof_rmse, data_quality FROM building WHERE fid=?");
  if (has_lods_)
    lod_ = sql::Stmt(db,
                     "SELECT geom, lod, face_types, volume, roof_rmse FROM building_lod WHERE building_fid=? "
                     "ORDER BY lod");
}

void Reader::read(std::int64_t building_fid, const Vec3& origin, Building& b) {
  if (has_attributes_) {
    attributes_.bind(static_cast<long long>(building_fid));
    if (attributes_.step()) {
      BuildingAttributes& a = b.attributes;
      const double z = origin.z();
      a.roof_type = attributes_.get_text(0);
      a.roof_z_min = attributes_.get_double(1) - z;
      a.roof_z_50p = attributes_.get_double(2) - z;
      a.roof_z_70p = attributes_.get_double(3) - z;
      a.roof_z_max = attributes_.get_double(4) - z;
      a.roof_points = long(attributes_.get_int(5));
      a.point_density = attributes_.get_double(6);
      a.roof_rmse = attributes_.get_double(7);
      a.data_quality = attributes_.get_text(8);
    }
    attributes_.reset();
  }
  if (!has_lods_) return;
  lod_.bind(static_cast<long long>(building_fid));
  while (lod_.step()) {
    LodShell s;
    std::size_t n;
    const std::uint8_t* blob = lod_.blob(0, &n);
    s.faces = gpkg_read_faces(blob, n, origin);
    try {
      s.lod = lod_from(lod_.get_text(1));
    } catch (const std::invalid_argument& e) {
      throw InputError("store", "building_lod of " + b.id + ": " + e.what());
    }
    s.face_types = split_types(lod_.get_text(2));
    s.volume = lod_.get_double(3);
    s.roof_rmse = lod_.get_double(4);
    if (s.face_types.size() != s.faces.size())
      throw InputError("store", "building_lod of " + b.id + ": " + std::to_string(s.faces.size()) + " faces but " +
                                    std::to_string(s.face_types.size()) + " face types");
    b.lower_lods.push_back(std::move(s));
  }
  lod_.reset();
}

}  // namespace c3d::store_lods
