#include "core/geometry/label_grid.h"

#include <gdal_alg.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <map>
#include <stdexcept>

#include "core/gdal_dataset.h"

namespace c3d {
namespace {

GdalDataset create(const char* driver, int nx, int ny, GDALDataType type) {
  register_gdal_drivers();
  GDALDriver* d = GetGDALDriverManager()->GetDriverByName(driver);
  if (!d) throw std::runtime_error(std::string("GDAL has no ") + driver + " driver");
  return GdalDataset(d->Create("", nx, ny, nx > 0 ? 1 : 0, type, nullptr));
}

Ring2 ring_of(const OGRLinearRing& r) {
  Ring2 out;
  for (int i = 0; i + 1 < r.getNumPoints(); ++i) out.emplace_back(r.getX(i), r.getY(i));  // last repeats the first
  return out;
}

// Runs of equal labels, 4-connected: the run of every cell (-1 for unlabelled
// cells) and the cells of every run.
struct Runs {
  std::vector<int> of_cell;
  std::vector<std::vector<size_t>> cells;
};

// Calls f(neighbour) for each of cell c's 4 neighbours inside the grid.
template <class F>
void for_each_neighbour(const LabelGrid& g, size_t c, F f) {
  const int i = int(c % size_t(g.nx)), j = int(c / size_t(g.nx));
  const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
  for (int n = 0; n < 4; ++n) {
    const int ni = i + di[n], nj = j + dj[n];
    if (ni >= 0 && nj >= 0 && ni < g.nx && nj < g.ny) f(size_t(nj) * size_t(g.nx) + size_t(ni));
  }
}

Runs find_runs(const LabelGrid& g) {
  Runs runs{std::vector<int>(g.labels.size(), -1), {}};
  for (size_t start = 0; start < g.labels.size(); ++start) {
    if (g.labels[start] < 0 || runs.of_cell[start] >= 0) continue;
    const int id = int(runs.cells.size());
    std::vector<size_t> cells{start};
    runs.of_cell[start] = id;
    for (size_t k = 0; k < cells.size(); ++k)
      for_each_neighbour(g, cells[k], [&](size_t nc) {
        if (runs.of_cell[nc] < 0 && g.labels[nc] == g.labels[start]) runs.of_cell[nc] = id, cells.push_back(nc);
      });
    runs.cells.push_back(std::move(cells));
  }
  return runs;
}

}  // namespace

void sieve(LabelGrid& grid, const std::vector<char>& counted, int min_cells) {
  Runs runs = find_runs(grid);
  const size_t n = runs.cells.size();
  std::vector<int> size(n, 0), owner(n);  // owner: the big run a small run joined, or itself
  for (size_t r = 0; r < n; ++r) {
    owner[r] = int(r);
    for (size_t c : runs.cells[r]) size[r] += counted[c] ? 1 : 0;
  }
  auto small = [&](size_t r) { return size[r] > 0 && size[r] < min_cells; };
  for (bool moved = true; moved;) {
    // Each small run measured against the big runs as they stand at the
    // round's start, so the order of the small runs decides nothing.
    std::vector<std::pair<size_t, int>> joins;
    for (size_t r = 0; r < n; ++r) {
      if (owner[r] != int(r) || !small(r)) continue;
      std::map<int, int> shared;  // big neighbouring run -> cell edges shared
      for (size_t c : runs.cells[r])
        for_each_neighbour(grid, c, [&](size_t nc) {
          if (runs.of_cell[nc] < 0 || !(counted[c] || counted[nc])) return;
          const size_t other = size_t(owner[size_t(runs.of_cell[nc])]);
          if (other != r && size[other] >= min_cells) ++shared[int(other)];
        });
      int best = -1, best_edges = 0;  // most edges; ties to the lower label
      for (const auto& [o, edges] : shared)
        if (edges > best_edges ||
            (edges == best_edges && grid.labels[runs.cells[size_t(o)][0]] < grid.labels[runs.cells[size_t(best)][0]]))
          best = o, best_edges = edges;
      if (best >= 0) joins.emplace_back(r, best);
    }
    for (const auto& [r, into] : joins) {
      const int label = grid.labels[runs.cells[size_t(into)][0]];
      for (size_t c : runs.cells[r]) grid.labels[c] = label;
      owner[r] = into;  // only big runs take others, so none had joined r
      size[size_t(into)] += size[r];
      auto& cells = runs.cells[size_t(into)];
      cells.insert(cells.end(), runs.cells[r].begin(), runs.cells[r].end());
      runs.cells[r].clear();
    }
    moved = !joins.empty();
  }
}

std::vector<MultiPolygon2> polygonize(const LabelGrid& grid, size_t label_count) {
  std::vector<MultiPolygon2> out(label_count);
  if (grid.nx <= 0 || grid.ny <= 0) return out;
  GdalDataset raster = create("MEM", grid.nx, grid.ny, GDT_Int32);
  double transform[6] = {grid.origin.x(), grid.cell, 0, grid.origin.y(), 0, grid.cell};  // rows go up in y
  raster->SetGeoTransform(transform);
  GDALRasterBand* band = raster->GetRasterBand(1);
  if (band->RasterIO(GF_Write, 0, 0, grid.nx, grid.ny, const_cast<int*>(grid.labels.data()), grid.nx, grid.ny,
                     GDT_Int32, 0, 0) != CE_None)
    throw std::runtime_error("label grid: GDAL could not write the memory raster");
  GdalDataset vector = create("Memory", 0, 0, GDT_Unknown);
  OGRLayer* layer = vector->CreateLayer("regions", nullptr, wkbPolygon, nullptr);
  OGRFieldDefn field("label", OFTInteger);
  layer->CreateField(&field);
  if (GDALPolygonize(band, nullptr, layer, 0, nullptr, nullptr, nullptr) != CE_None)
    throw std::runtime_error("label grid: GDAL polygonize failed");
  layer->ResetReading();
  for (auto& feature : *layer) {
    const int label = feature->GetFieldAsInteger(0);
    const OGRGeometry* g = feature->GetGeometryRef();
    if (label < 0 || size_t(label) >= label_count || !g || wkbFlatten(g->getGeometryType()) != wkbPolygon) continue;
    const OGRPolygon* p = g->toPolygon();
    Polygon2 poly{ring_of(*p->getExteriorRing()), {}};
    for (int h = 0; h < p->getNumInteriorRings(); ++h) poly.holes.push_back(ring_of(*p->getInteriorRing(h)));
    out[size_t(label)].push_back(std::move(poly));
  }
  return out;
}

}  // namespace c3d
