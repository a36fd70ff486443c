#pragma once
// A store's parcels a page at a time, in layer order (layer index, then id):
// what is written after modelling (summary.json, the report, previews,
// exports) holds one page of models in memory, never the whole town's.
#include <string>
#include <vector>

#include "core/types.h"
#include "valuation/valuation_types.h"

namespace c3d {

// Parcels read from the store at once: a sample-town parcel's models take
// ~30-60 kB, so a page stays near 10 MB, while one query per page keeps the
// store's per-query cost (opening, the parcel scan) small beside the reading.
constexpr size_t kOutputPageParcels = 200;

class StorePages {
 public:
  // loc: the store (a GeoPackage path or whatever load_batch_model takes).
  // A parcel whose job is pending (a run in progress) is left out: its rows,
  // if any, are an earlier run's that the run will replace.
  // The parcels are fixed here, once, by their ids (unique in a store, where
  // layer indices are not): the count and the pages agree whatever other
  // writers add to a shared store meanwhile.
  explicit StorePages(const std::string& loc, size_t page_size = kOutputPageParcels);
  const std::string& location() const { return loc_; }
  // The frame and CRS of the latest run; no parcels.
  const BatchModel& header() const { return header_; }
  size_t page_count() const;
  // Parcels the pages hold: those with a stored result (a job not pending).
  size_t parcel_count() const { return parcel_ids_.size(); }
  // Page k: its parcels and their results, buildings in local coordinates.
  BatchModel page(size_t k) const;
  // The stored valuations of page k's parcels (in the same order).
  std::vector<ParcelValuation> valuations(size_t k) const;

 private:
  std::vector<std::string> ids(size_t k) const;
  std::string loc_;
  size_t page_size_;
  std::vector<std::string> parcel_ids_;  // of every stored parcel, in layer order (layer index, then id)
  BatchModel header_;
};

}  // namespace c3d

namespace c3d {

// One export format's files from export_pages, the buildings STEP skipped and
// the seconds its writer took.
struct PagesExport {
  std::string format;
  std::vector<std::string> files, skipped;
  double seconds = 0;
};
// The exports of `formats` (ifc_citygml/export.h) into dir in one pass over
// the pages; `buildings` (when given) counts the buildings written.
std::vector<PagesExport> export_pages(const StorePages& pages, const std::string& dir,
                                      const std::vector<std::string>& formats, size_t* buildings = nullptr);

}  // namespace c3d
