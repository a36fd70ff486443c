#include "cadastre/store_pages.h"

#include <algorithm>
#include <chrono>
#include <memory>

#include "cadastre/store.h"
#include "ifc_citygml/export.h"

namespace c3d {

StorePages::StorePages(const std::string& loc, size_t page_size)
    : loc_(loc), page_size_(std::max<size_t>(page_size, 1)) {
  for (const JobRecord& j : load_jobs(loc))
    if (j.status != "pending") layer_indices_.push_back(j.layer_index), ++parcel_count_;
  std::sort(layer_indices_.begin(), layer_indices_.end());
  layer_indices_.erase(std::unique(layer_indices_.begin(), layer_indices_.end()), layer_indices_.end());
  // The frame and CRS come with any read; one parcel's is the smallest that
  // needs no empty index list (which not every SQL dialect takes).
  header_ = layer_indices_.empty() ? load_batch_model(loc) : load_batch_model(loc, {layer_indices_[0]});
  header_.parcels.clear();
  header_.results.clear();
}

size_t StorePages::page_count() const { return (layer_indices_.size() + page_size_ - 1) / page_size_; }

std::vector<int> StorePages::indices(size_t k) const {
  const size_t from = std::min(k * page_size_, layer_indices_.size());
  const size_t to = std::min(from + page_size_, layer_indices_.size());
  return {layer_indices_.begin() + long(from), layer_indices_.begin() + long(to)};
}

BatchModel StorePages::page(size_t k) const { return load_batch_model(loc_, indices(k)); }

std::vector<ParcelValuation> StorePages::valuations(size_t k) const { return load_valuations(loc_, indices(k)); }

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
    for (size_t f = 0; f < formats.size(); ++f) {
      const auto t0 = clock::now();
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
