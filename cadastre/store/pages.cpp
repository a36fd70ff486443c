#include "cadastre/store/pages.h"

#include <algorithm>
#include <chrono>
#include <memory>

#include "cadastre/store/store.h"
#include "ifc_citygml/export.h"

namespace c3d {

StorePages::StorePages(const std::string& loc, size_t page_size)
    : loc_(loc), page_size_(std::max<size_t>(page_size, 1)) {
  for (const JobRecord& j : load_jobs(loc))  // in layer order; a parcel id is one job
    if (j.status) parcel_ids_.push_back(j.parcel_id);
  header_ = load_batch_model(loc, std::vector<std::string>());  // the frame and CRS, no parcels
}

size_t StorePages::page_count() const { return (parcel_ids_.size() + page_size_ - 1) / page_size_; }

std::vector<std::string> StorePages::ids(size_t k) const {
  const size_t from = std::min(k * page_size_, parcel_ids_.size());
  const size_t to = std::min(from + page_size_, parcel_ids_.size());
  return {parcel_ids_.begin() + long(from), parcel_ids_.begin() + long(to)};
}

BatchModel StorePages::page(size_t k) const { return load_batch_model(loc_, ids(k)); }

std::vector<ParcelValuation> StorePages::valuations(size_t k) const { return load_valuations(loc_, ids(k)); }

}  // namespace c3d

namespace c3d {

std::vector<PagesExport> export_pages(const StorePages& pages, const std::string& dir,
                                      const std::vector<std::string>& formats, size_t* buildings) {
  using clock = std::chrono::steady_clock;
  std::vector<PagesExport> out(formats.size());
  std::vector<std::unique_ptr<ExportWriter>> writers;
  for (size_t f = 0; f < formats.size(); ++f) {
    const auto t0 = clock::now();
    out[f].format = formats[f];
    writers.push_back(export_writer(formats[f], pages.header(), dir, &out[f].skipped));
    out[f].seconds += std::chrono::duration<double>(clock::now() - t0).count();
  }
  if (buildings) *buildings = 0;
  for (size_t k = 0; k < pages.page_count(); ++k) {
    const BatchModel page = pages.page(k);
    if (buildings)
      for (const auto& r : page.results) *buildings += r.buildings.size();
    std::vector<ParcelValuation> values;  // read only for a writer that carries them
    for (size_t f = 0; f < formats.size(); ++f) {
      const auto t0 = clock::now();
      if (writers[f]->carries_values()) {
        if (values.empty()) values = pages.valuations(k);
        writers[f]->values(values);
      }
      writers[f]->add(page);
      out[f].seconds += std::chrono::duration<double>(clock::now() - t0).count();
    }
  }
  for (size_t f = 0; f < formats.size(); ++f) {
    const auto t0 = clock::now();
    out[f].files = writers[f]->finish();
    out[f].seconds += std::chrono::duration<double>(clock::now() - t0).count();
  }
  return out;
}

}  // namespace c3d
