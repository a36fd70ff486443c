// A bigger store for the output benchmarks (not a test): the parcels of a
// store N times side by side, each copy shifted east by the town's width plus
// 100 m, ids suffixed "-k", read and written a page at a time.
//   cmake --build build --target c3d_store_copies
//   build/cadastre/c3d_store_copies IN.gpkg OUT.gpkg N
#include <cstdio>
#include <cstdlib>
#include <string>

#include "cadastre/store/pages.h"
#include "cadastre/store/store.h"
#include "core/config/config.h"
#include "valuation/valuation.h"

using namespace c3d;

namespace {

void shift(Building& b, const Vec3& d) {
  auto move = [&](std::vector<Face>& faces) {
    for (Face& f : faces) {
      for (Vec3& p : f.ring) p += d;
      for (Ring3& h : f.holes)
        for (Vec3& p : h) p += d;
    }
  };
  move(b.solid);
  for (Element& e : b.elements) move(e.faces);
  for (LodShell& l : b.lower_lods) move(l.faces);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s IN.gpkg OUT.gpkg N\n", argv[0]);
    return 2;
  }
  const StorePages pages(argv[1]);
  const int copies = std::atoi(argv[3]);
  const BatchModel& h = pages.header();
  double lo = 1e300, hi = -1e300;  // the town's x extent
  for (size_t k = 0; k < pages.page_count(); ++k)
    for (const Parcel& p : pages.page(k).parcels)
      for (const auto& poly : p.shape)
        for (const Vec2& v : poly.outer) lo = std::min(lo, v.x()), hi = std::max(hi, v.x());
  const int n = int(pages.parcel_count());
  Store out;
  out.open(argv[2], h.crs_wkt, h.epsg);
  out.begin_run("{}", {}, h.frame);
  const Config cfg = default_config();
  for (int c = 0; c < copies; ++c) {
    const Vec3 d(c * (hi - lo + 100), 0, 0);
    for (size_t k = 0; k < pages.page_count(); ++k) {
      BatchModel page = pages.page(k);
      for (size_t i = 0; i < page.parcels.size(); ++i) {
        Parcel& p = page.parcels[i];
        ParcelResult& r = page.results[i];
        p.id += "-" + std::to_string(c);
        p.index += c * n;
        for (auto& poly : p.shape) {
          for (Vec2& v : poly.outer) v.x() += d.x();
          for (auto& ring : poly.holes)
            for (Vec2& v : ring) v.x() += d.x();
        }
        r.parcel_id = p.id, r.parcel_index = p.index;
        for (Building& b : r.buildings) b.id = p.id + b.id.substr(b.id.rfind("_b")), shift(b, d);
        out.write_parcel(p, r, value_parcel(p, r, cfg.valuation), h.frame);
      }
    }
  }
  out.end_run();
  std::printf("%d parcels\n", n * copies);
  return 0;
}
