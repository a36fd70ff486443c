#pragma once
// The store's 3DBAG-style building attributes (columns of `building`) and
// lower LoDs (table `building_lod`), internal to cadastre/store/.
#include <cstdint>
#include <string>

#include "cadastre/store/sql_db.h"
#include "core/types.h"

namespace c3d::store_lods {

// Writes a building's attributes into its row and its lower LoDs as rows of
// building_lod; statements prepared once per store.
class Writer {
 public:
  Writer() = default;
  explicit Writer(const sql::Db& db);
  // Heights and shells go to world coordinates: local + origin.
  void write(std::int64_t building_fid, const Building& b, const Vec3& origin, int srs);

 private:
  sql::Stmt attributes_, lod_;
};

// Reads them back into `b` (local coordinates: world - origin). A store
// written before they existed leaves b's attributes and lower_lods empty.
class Reader {
 public:
  explicit Reader(const sql::Db& db);
  void read(std::int64_t building_fid, const Vec3& origin, Building& b);

 private:
  std::string where_;  // the store, as messages name it
  bool has_attributes_ = false, has_lods_ = false;
  sql::Stmt attributes_, lod_;
};

}  // namespace c3d::store_lods
