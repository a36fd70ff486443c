#pragma once
// The GeoPackage R-tree spatial index extension (gpkg_rtree_index, GPKG 1.3
// §F.3): one SQLite rtree per geometry column, kept current by the spec's
// triggers. Those triggers call ST_MinX, ST_MaxX, ST_MinY, ST_MaxY and
// ST_IsEmpty, which GDAL and QGIS provide on their connections; the store
// registers its own on every connection that writes geometry.
#include <string>

#include "cadastre/store/sql_db.h"

namespace c3d::gpkg_rtree {

// Registers the ST_* functions the triggers call on this connection.
void register_functions(sql::Db& db);
// Creates rtree_<table>_geom, its triggers and its gpkg_extensions row unless
// present, and indexes the rows already in the table (a store written before).
void create(sql::Db& db, const std::string& table);

}  // namespace c3d::gpkg_rtree
