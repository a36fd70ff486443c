#include "cadastre/store/styles.h"

#include <cstdio>
#include <string>
#include <vector>

#include "core/geometry/geometry.h"

namespace c3d::store_styles {

namespace {

constexpr int kClasses = 5;  // quantile classes: a legend a reader takes in at a glance

// ColorBrewer YlOrRd, light (low value) to dark (high value).
const char* const kColours[kClasses] = {"255,255,178,255", "254,204,92,255", "253,141,60,255",
                                        "240,59,32,255", "189,0,38,255"};

struct Style {
  const char* table;
  const char* field;
  const char* name;
  const char* description;
};

const Style kStyles[] = {
    {"parcel", "njop", "NJOP", "Parcels by NJOP (land + building value), quantile classes"},
    {"building_footprint", "building_cost", "Building cost",
     "Building footprints by replacement cost of their priced elements, quantile classes"},
};

std::string fill_symbol(int k) {
  const std::string c = kColours[k];
  auto prop = [](const char* key, const std::string& v) {
    return std::string("<prop k=\"") + key + "\" v=\"" + v + "\"/><Option name=\"" + key +
           "\" type=\"QString\" value=\"" + v + "\"/>";
  };
  // Both spellings of the properties: <prop> for QGIS before 3.26, <Option> after.
  return "<symbol type=\"fill\" name=\"" + std::to_string(k) + "\" alpha=\"1\" clip_to_extent=\"1\" force_rhr=\"0\">"
         "<layer class=\"SimpleFill\" enabled=\"1\" locked=\"0\" pass=\"0\"><Option type=\"Map\">" +
         prop("color", c) + prop("outline_color", "35,35,35,255") + prop("outline_width", "0.26") +
         prop("outline_style", "solid") + prop("style", "solid") + "</Option></layer></symbol>";
}

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

// A graduated-colour renderer over `field` with class bounds `breaks` (k + 1 values).
std::string qml(const std::string& field, const std::vector<double>& breaks) {
  std::string ranges, symbols;
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    const std::string lo = number(breaks[k]), hi = number(breaks[k + 1]);
    ranges += "<range lower=\"" + lo + "\" upper=\"" + hi + "\" symbol=\"" + std::to_string(k) +
              "\" label=\"" + lo + " - " + hi + "\" render=\"true\"/>";
    symbols += fill_symbol(int(k));
  }
  return "<!DOCTYPE qgis PUBLIC 'http://mrcc.com/qgis.dtd' 'SYSTEM'>"
         "<qgis version=\"3.28.0\" styleCategories=\"Symbology\">"
         "<renderer-v2 type=\"graduatedSymbol\" attr=\"" + field + "\" graduatedMethod=\"GraduatedColor\" "
         "symbollevels=\"0\" enableorderby=\"0\" forceraster=\"0\"><ranges>" + ranges + "</ranges><symbols>" +
         symbols + "</symbols><mode name=\"quantile\"/></renderer-v2></qgis>";
}

// Class bounds at the quantiles of the field's values; fewer classes where
// values repeat, one class [v, v] where all are equal, none without values.
std::vector<double> breaks_of(sql::Db& db, const Style& s) {
  std::vector<double> values;
  sql::Stmt q(db, std::string("SELECT ") + s.field + " FROM " + s.table + " WHERE " + s.field +
                      " IS NOT NULL ORDER BY 1");
  while (q.step()) values.push_back(q.get_double(0));
  std::vector<double> out;
  if (values.empty()) return out;
  for (int k = 0; k <= kClasses; ++k) {
    const double v = quantile_of_sorted(values, double(k) / kClasses);
    if (out.empty() || v > out.back()) out.push_back(v);
  }
  if (out.size() == 1) out.push_back(out[0]);
  return out;
}

}  // namespace

void create(sql::Db& db) {
  if (db.postgres()) {
    // As QGIS creates it in PostgreSQL (QgsPostgresProviderMetadata::saveStyle).
    db.exec("CREATE TABLE IF NOT EXISTS layer_styles (id serial PRIMARY KEY, f_table_catalog varchar, "
            "f_table_schema varchar, f_table_name varchar, f_geometry_column varchar, styleName text, "
            "styleQML xml, styleSLD xml, useAsDefault boolean, description text, "
            "owner varchar(63) DEFAULT CURRENT_USER, ui xml, update_time timestamp DEFAULT CURRENT_TIMESTAMP, "
            "type varchar)");
    return;
  }
  db.exec("CREATE TABLE IF NOT EXISTS layer_styles (id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, "
          "f_table_catalog TEXT(256), f_table_schema TEXT(256), f_table_name TEXT(256), "
          "f_geometry_column TEXT(256), styleName TEXT(30), styleQML TEXT, styleSLD TEXT, "
          "useAsDefault BOOLEAN, description TEXT, owner TEXT(30), ui TEXT(30), "
          "update_time DATETIME DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ','now')));"
          "INSERT OR IGNORE INTO gpkg_contents (table_name, data_type, identifier, description) "
          "VALUES ('layer_styles', 'attributes', 'layer_styles', 'QGIS default styles of the GIS layers');");
}

void update(sql::Db& db) {
  // QGIS finds a PostgreSQL layer's style by its database and schema; a GeoPackage's by name alone.
  const std::string where = db.postgres() ? "current_database(), current_schema()" : "'', ''";
  if (db.postgres()) db.exec("SELECT pg_advisory_xact_lock(2, 0)");  // one writer of the styles at a time
  sql::Stmt del(db, "DELETE FROM layer_styles WHERE f_table_name=? AND styleName=?");
  sql::Stmt ins(db,
                "INSERT INTO layer_styles (f_table_catalog, f_table_schema, f_table_name, f_geometry_column, "
                "styleName, styleQML, styleSLD, useAsDefault, description, owner) "
                "VALUES (" + where + ", ?, 'geom', ?, ?, '', TRUE, ?, 'cadastre3d')");
  for (const Style& s : kStyles) {
    del.bind(s.table).bind(s.name).run();
    const std::vector<double> breaks = breaks_of(db, s);
    if (breaks.size() < 2) continue;
    ins.bind(s.table).bind(s.name).bind(qml(s.field, breaks)).bind(s.description).run();
  }
}

}  // namespace c3d::store_styles
