// The effective configuration as data: what the run record stores and what the
// resume key hashes. It walks the parameter table, so no setting can be left out.
#include <nlohmann/json.hpp>

#include "core/config/config.h"
#include "core/config/parameters.h"
#include "core/io/sha256.h"

namespace c3d {

nlohmann::json effective_config_json(const Config& c) {
  nlohmann::json j = nlohmann::json::object();  // std::map underneath: keys come sorted
  for (const Parameter& p : parameter_table()) {
    std::string pointer = "/" + p.key;
    for (char& ch : pointer)
      if (ch == '.') ch = '/';
    j[nlohmann::json::json_pointer(pointer)] = p.field.get(c);
  }
  return j;
}

std::string config_fingerprint(const Config& c) {
  nlohmann::json j = effective_config_json(c);
  j.erase("batch");  // how the batch runs through the data changes no result
  return sha256_hex(j.dump());
}

}  // namespace c3d
