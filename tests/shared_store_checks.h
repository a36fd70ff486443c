#pragma once
// One store shared by two writers of different parcel selections (issue 37:
// two `--where` halves): each numbers its parcels from 0, so their layer
// indices collide and only the parcel ids tell their parcels apart. The same
// checks run on a GeoPackage (outputs_stream_test) and on PostGIS
// (postgis_store_test).
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "cadastre/report/report.h"
#include "cadastre/store/pages.h"
#include "cadastre/store/store.h"
#include "core/config/config.h"
#include "tests/store_fixtures.h"
#include "tests/test_support.h"
#include "valuation/valuation.h"

namespace c3d::test {

// sample_batch(1) (a house, an empty lot, a failed parcel; layer indices 0-2)
// with ids prefixed and moved `dy` metres north: another writer's layer.
inline BatchModel writer_layer(const std::string& prefix, double dy) {
  BatchModel m = sample_batch(1);
  for (size_t i = 0; i < m.parcels.size(); ++i) {
    m.parcels[i].id = m.results[i].parcel_id = prefix + m.parcels[i].id;
    for (auto& poly : m.parcels[i].shape)
      for (auto& v : poly.outer) v.y() += dy;
    for (Building& b : m.results[i].buildings) {
      b.id = prefix + b.id;
      auto move = [&](Face& f) {
        for (auto& p : f.ring) p.y() += dy;
      };
      for (auto& e : b.elements)
        for (Face& f : e.faces) move(f);
      for (Face& f : b.solid) move(f);
    }
  }
  return m;
}

// Writes parcels [from, to) of m as one writer's run into the store at loc.
inline void write_parcels(const std::string& loc, const BatchModel& m, size_t from, size_t to,
                          const std::string& key = "") {
  Store s;
  s.open(loc, "", m.epsg);
  s.begin_run("{}", {}, m.frame);
  const Config c = default_config();
  for (size_t i = from; i < to; ++i)
    s.write_parcel(m.parcels[i], m.results[i], value_parcel(m.parcels[i], m.results[i], c.valuation), m.frame, key);
  s.end_run();
}

// How many times each parcel id comes in the pages, and in their valuations.
inline std::map<std::string, int> paged_ids(const StorePages& pages, std::map<std::string, int>* valued = nullptr) {
  std::map<std::string, int> seen;
  for (size_t k = 0; k < pages.page_count(); ++k) {
    for (const Parcel& p : pages.page(k).parcels) ++seen[p.id];
    if (valued)
      for (const ParcelValuation& v : pages.valuations(k)) ++(*valued)[v.parcel_id];
  }
  return seen;
}

// The pages hold exactly the parcels counted when they were made, each once,
// whatever the other writer stores meanwhile under the same layer indices;
// the report from them is written.
inline void expect_pages_fixed_once(const std::string& loc, const std::string& report_dir) {
  const BatchModel a = writer_layer("A-", 0), b = writer_layer("B-", 40);
  write_parcels(loc, a, 0, 3);  // writer A: done
  write_parcels(loc, b, 0, 1);  // writer B: its first parcel so far
  const StorePages pages(loc, 2);
  ASSERT_EQ(pages.parcel_count(), 4u);
  write_parcels(loc, b, 1, 3);  // B stores its parcels 1 and 2 (A's indices too) after the count
  const std::map<std::string, int> want = {{"A-32.73.01", 1}, {"A-32.73.02", 1}, {"A-32.73.03", 1}, {"B-32.73.01", 1}};
  std::map<std::string, int> valued;
  EXPECT_EQ(paged_ids(pages, &valued), want);
  EXPECT_EQ(valued, want);
  EXPECT_NO_THROW(write_report_from_store(pages, report_dir, default_config()));
  // Writer B reruns with other settings: its parcels are pending, their rows
  // an earlier run's. A reader now sees A's parcels only.
  {
    Store s;
    s.open(loc, "", b.epsg);
    s.begin_run("{}", {}, b.frame);
    s.mark_pending(b.parcels, {"other", "other", "other"});
  }
  const StorePages later(loc, 2);
  EXPECT_EQ(later.parcel_count(), 3u);
  EXPECT_EQ(paged_ids(later), (std::map<std::string, int>{{"A-32.73.01", 1}, {"A-32.73.02", 1}, {"A-32.73.03", 1}}));
}

}  // namespace c3d::test
