#pragma once
// The store's GIS layers (internal to cadastre/store/): 2D geometries a
// GIS opens as they are, each row carrying its figures so nothing needs a join.
//   parcel             the parcel, its valuation and the input layer's own fields
//   building_footprint one valid footprint per building: areas, sigma, heights,
//                      LoD, roof type and the other building attributes, value
//   roof_part          one valid plan per roof element: 3D area, slope, azimuth
// Each row hangs on its 3D source row (ON DELETE CASCADE), so rewriting a
// parcel replaces them with it. docs/design.md, "GeoPackage for GIS". Their
// tables are created with the others (schema.cpp).
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "cadastre/store/sql_db.h"
#include "core/types.h"
#include "valuation/valuation_types.h"

namespace c3d::store_gis {

// The plan of faces in world coordinates (offset added), valid by GEOS: each
// face's projection repaired with MakeValid where it crosses itself, then all
// united. *repaired (when given) tells whether any face needed the repair.
MultiPolygon2 plan_of(const std::vector<Face>& faces, const Vec3& offset, bool* repaired = nullptr);
// The building's footprint: the plan of its ground element(s), else of its
// solid's downward faces.
MultiPolygon2 footprint_of(const Building& b, const Vec3& offset);

class Writer {
 public:
  Writer() = default;
  Writer(sql::Db& db, int srs);

  // Adds the columns of the parcels' own fields that the layer lacks.
  void add_input_columns(const std::vector<Parcel>& parcels);
  void parcel(const Parcel& p, std::int64_t spatialunit, const ParcelResult& r, const ParcelValuation& v);
  void building(const Building& b, std::int64_t building_fid, const std::string& parcel_id, const Vec3& offset,
                const ParcelValuation& v);
  void roof_part(const Element& e, std::int64_t element_fid, int index, const std::string& building_id,
                 const std::string& parcel_id, const Vec3& offset);

 private:
  // The column of the `parcel` layer that holds an input field ("src_" in
  // front where the name is one of the layer's own), added when missing.
  std::string input_column(const ParcelAttribute& a);

  sql::Db* db_ = nullptr;
  int srs_ = 0;
  sql::Stmt ins_footprint_, ins_roof_;
  std::set<std::string> parcel_columns_;  // lower case
};

}  // namespace c3d::store_gis
