#include "cadastre/batch/resume_key.h"

#include <nlohmann/json.hpp>

#include "core/io/sha256.h"

namespace c3d {

std::string run_parameters(const Config& cfg) {
  nlohmann::json j = effective_config_json(cfg);
  j["config_file"] = cfg.source;  // for the reader of the run record; not part of the key
  return j.dump();
}

std::string run_key(const Config& cfg, const std::vector<InputFile>& inputs) {
  std::string s = config_fingerprint(cfg);
  for (const auto& f : inputs) s += "|" + f.sha256;
  return sha256_hex(s);
}

std::string parcel_key(const std::string& run_key, const Parcel& p, const std::vector<std::string>& tiles) {
  std::string s = run_key + "|" + p.id;
  for (const auto& poly : p.shape)
    for (const auto& v : poly.outer) s += "|" + std::to_string(v.x()) + "," + std::to_string(v.y());
  for (const auto& t : tiles) s += "|t" + t;
  return sha256_hex(s);
}

}  // namespace c3d
