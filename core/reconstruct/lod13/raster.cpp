#include "core/reconstruct/lod13/raster.h"

#include <algorithm>

namespace c3d::lod13 {

std::vector<int> neighbours8(int nx, int ny, int i) {
  std::vector<int> out;
  const int x = i % nx, y = i / nx;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if ((dx || dy) && x + dx >= 0 && x + dx < nx && y + dy >= 0 && y + dy < ny) out.push_back(i + dy * nx + dx);
  return out;
}

std::vector<std::vector<int>> connected_patches(int nx, int ny, const std::vector<int>& cells) {
  std::vector<char> in(size_t(nx) * size_t(ny), 0);
  for (int c : cells) in[size_t(c)] = 1;
  std::vector<std::vector<int>> out;
  for (int start : cells) {
    if (in[size_t(start)] != 1) continue;
    std::vector<int> patch{start}, stack{start};
    in[size_t(start)] = 2;
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      const int x = c % nx, y = c / nx;
      const int next[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
      for (const auto& n : next) {
        if (n[0] < 0 || n[1] < 0 || n[0] >= nx || n[1] >= ny) continue;
        const int j = n[1] * nx + n[0];
        if (in[size_t(j)] != 1) continue;
        in[size_t(j)] = 2;
        patch.push_back(j);
        stack.push_back(j);
      }
    }
    std::sort(patch.begin(), patch.end());
    out.push_back(std::move(patch));
  }
  return out;
}

}  // namespace c3d::lod13
