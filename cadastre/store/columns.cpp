#include "cadastre/store/columns.h"

#include <algorithm>
#include <stdexcept>

#include "cadastre/store/schema.h"

namespace c3d::store_columns {

std::string insert_sql(const Table& t, const std::map<std::string, std::string>& fixed) {
  std::string names, values;
  for (const Column& c : t.columns) {
    const auto it = fixed.find(c.name);
    names += (names.empty() ? "" : ", ") + std::string(c.name);
    values += (values.empty() ? "" : ",") + (it == fixed.end() ? std::string("?") : it->second);
  }
  return "INSERT INTO " + std::string(t.name) + " (" + names + ") VALUES (" + values + ")";
}

std::string upsert_sql(const Table& t, const std::string& key, const std::map<std::string, std::string>& fixed) {
  std::string set;
  for (const Column& c : t.columns)
    if (c.name != key) set += (set.empty() ? "" : ", ") + std::string(c.name) + "=excluded." + c.name;
  return insert_sql(t, fixed) + " ON CONFLICT(" + key + ") DO UPDATE SET " + set;
}

std::string update_sql(const Table& t) {
  std::string set;
  for (const Column& c : t.columns) set += (set.empty() ? "" : ", ") + std::string(c.name) + "=?";
  return "UPDATE " + std::string(t.name) + " SET " + set + " WHERE fid=?";
}

std::string select_list(const sql::Db& db, const Table& t, const std::string& alias,
                        const std::vector<std::string>& only) {
  const std::vector<std::string> present = store_schema::columns_of(db, t.name);
  const std::string prefix = alias.empty() ? "" : alias + ".";
  std::vector<std::string> items;
  if (only.empty()) items.push_back(prefix + "fid AS fid");
  for (const Column& c : t.columns) {
    if (!only.empty() && std::find(only.begin(), only.end(), c.name) == only.end()) continue;
    const bool has = std::find(present.begin(), present.end(), c.name) != present.end();
    items.push_back((has || !c.before ? prefix + c.name : std::string(c.before)) + " AS " + c.name);
  }
  if (!only.empty() && items.size() != only.size())
    throw std::logic_error(std::string("select_list: a name asked of ") + t.name + " is not in its column list");
  std::string out;
  for (const std::string& i : items) out += (out.empty() ? "" : ", ") + i;
  return out;
}

}  // namespace c3d::store_columns
