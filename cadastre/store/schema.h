#pragma once
// The store's tables (internal to cadastre/store/): GeoPackage core
// tables, the LADM / valuation tables, their layers in gpkg_contents and the
// layer extents.
#include <string>
#include <vector>

#include "cadastre/store/sql_db.h"

namespace c3d::store_schema {

// SQLite's current time in the form GeoPackage writes (ISO 8601, UTC).
inline constexpr const char* kNow = "strftime('%Y-%m-%dT%H:%M:%fZ','now')";
// The same expression in the connection's dialect.
std::string now(const sql::Db& db);

// Creates the tables in one transaction (an existing store must have the same
// CRS) and returns the srs_id the geometry layers use.
int create(sql::Db& db, const std::string& crs_wkt, int epsg);
// The LA_RightType value (ISO 19152) of a right named as the parcel layer
// names it ("Hak Milik" -> "ownership"); nullptr when the code list has none.
const char* ladm_right_type(const std::string& local);
// Whether `table` has a column `column` (a store written before it was added has not).
bool has_column(const sql::Db& db, const std::string& table, const std::string& column);
// The table's column names.
std::vector<std::string> columns_of(const sql::Db& db, const std::string& table);
// A column type in the connection's dialect ("DOUBLE" -> "double precision" on PostgreSQL).
std::string column_type(const sql::Db& db, const std::string& gpkg_type);
// Refreshes each feature layer's xy extent and every layer's change time.
void update_extents(sql::Db& db);

}  // namespace c3d::store_schema
