#pragma once
// The store's tables (internal to cadastre/store*.cpp): GeoPackage core
// tables, the LADM / valuation tables, their layers in gpkg_contents and the
// layer extents.
#include <string>

#include "cadastre/sqlite_util.h"

namespace c3d::store_schema {

// SQLite's current time in the form GeoPackage writes (ISO 8601, UTC).
inline constexpr const char* kNow = "strftime('%Y-%m-%dT%H:%M:%fZ','now')";

// Creates the tables in one transaction (an existing store must have the same
// CRS) and returns the srs_id the geometry layers use.
int create(sql::Db& db, const std::string& crs_wkt, int epsg);
// The LA_RightType value (ISO 19152) of a right named as the parcel layer
// names it ("Hak Milik" -> "ownership"); nullptr when the code list has none.
const char* ladm_right_type(const std::string& local);
// Whether `table` has a column `column` (a store written before it was added has not).
bool has_column(const sql::Db& db, const std::string& table, const std::string& column);
// Refreshes each feature layer's xy extent and every layer's change time.
void update_extents(sql::Db& db);

}  // namespace c3d::store_schema
