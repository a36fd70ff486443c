#pragma once
// The store's mesh ladders (batch --mesh; docs/meshes.md): a row of
// `building_mesh` per meshed building (method, points, the element model
// against the closed hull, the flag) and one of `building_mesh_level` per
// level (figures, files, SHA-256). Internal to cadastre/store/.
#include <cstdint>
#include <string>

#include "cadastre/store/sql_db.h"
#include "core/types.h"

namespace c3d::store_meshes {

class Writer {
 public:
  Writer() = default;
  explicit Writer(const sql::Db& db);
  // Nothing for a building the batch did not mesh (b.mesh.method "").
  void write(std::int64_t building_fid, const Building& b);

 private:
  sql::Stmt mesh_, level_;
};

// A store without the tables (written before them) leaves b.mesh empty.
class Reader {
 public:
  explicit Reader(const sql::Db& db);
  void read(std::int64_t building_fid, Building& b);

 private:
  bool has_tables_ = false;
  sql::Stmt mesh_, level_;
};

}  // namespace c3d::store_meshes
