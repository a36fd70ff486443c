#pragma once
// Default QGIS styles stored in the GeoPackage (the `layer_styles` table QGIS
// reads when it opens a layer): parcels and building footprints coloured by
// value in graduated classes, so a user sees the valuation without a join.
#include "cadastre/store/sql_db.h"

namespace c3d::store_styles {

// The layer_styles table as QGIS creates it, registered in gpkg_contents.
void create(sql::Db& db);
// Writes (replaces) the default styles, classes at the quantiles of the
// values now in the store.
void update(sql::Db& db);

}  // namespace c3d::store_styles
