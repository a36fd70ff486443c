#include "core/types.h"

#include <algorithm>
#include <stdexcept>

namespace c3d {

const char* to_string(ElementType t) {
  switch (t) {
    case ElementType::Roof: return "roof";
    case ElementType::Wall: return "wall";
    case ElementType::PartyWall: return "party_wall";
    case ElementType::Ground: return "ground";
    case ElementType::OuterCeiling: return "outer_ceiling";
  }
  return "?";
}

const char* to_string(WallEvidence e) {
  switch (e) {
    case WallEvidence::None: return "none";
    case WallEvidence::Measured: return "measured";
    case WallEvidence::Propagated: return "propagated";
    case WallEvidence::Default: return "default";
    case WallEvidence::ParcelBoundary: return "parcel_boundary";
    case WallEvidence::RoofStep: return "roof_step";
  }
  return "?";
}

const LodShell* lower_lod(const Building& b, Lod lod) {
  for (const LodShell& s : b.lower_lods)
    if (s.lod == lod) return &s;
  return nullptr;
}

const char* to_string(Lod l) {
  switch (l) {
    case Lod::Lod12: return "1.2";
    case Lod::Lod13: return "1.3";
    case Lod::Lod22: return "2.2";
  }
  return "?";
}

Lod lod_from(const std::string& text) {
  for (Lod l : {Lod::Lod12, Lod::Lod13, Lod::Lod22})
    if (text == to_string(l)) return l;
  throw std::invalid_argument("unknown level of detail '" + text + "' (known: 1.2, 1.3, 2.2)");
}

ParcelStatus parcel_status_from(const std::string& text) {
  for (ParcelStatus s : {ParcelStatus::Ok, ParcelStatus::Empty, ParcelStatus::Failed, ParcelStatus::Suspect})
    if (text == to_string(s)) return s;
  throw std::invalid_argument("unknown parcel status '" + text + "' (known: ok, empty, failed, suspect)");
}

const char* to_string(ParcelStatus s) {
  switch (s) {
    case ParcelStatus::Ok: return "ok";
    case ParcelStatus::Empty: return "empty";
    case ParcelStatus::Failed: return "failed";
    case ParcelStatus::Suspect: return "suspect";
  }
  return "?";
}

bool Dtm::covers(double x, double y) const {
  double fx = (x - x0) / dx, fy = (y - y0) / dy;
  return fx >= -0.5 && fy >= -0.5 && fx <= nx - 0.5 && fy <= ny - 0.5;
}

float Dtm::cell(int i, int j) const {
  if (win_nx == 0) return z[size_t(j) * nx + i];
  const int u = i - win_x, v = j - win_y;
  if (u < 0 || v < 0 || u >= win_nx || v >= win_ny) return float(kNaN);
  return z[size_t(v) * win_nx + u];
}

double Dtm::height_at(double x, double y) const {
  if (nx == 0 || ny == 0 || !covers(x, y)) return kNaN;
  double fx = std::clamp((x - x0) / dx, 0.0, double(nx - 1));
  double fy = std::clamp((y - y0) / dy, 0.0, double(ny - 1));
  int ix = std::min(int(fx), nx - 2 < 0 ? 0 : nx - 2);
  int iy = std::min(int(fy), ny - 2 < 0 ? 0 : ny - 2);
  int ix1 = std::min(ix + 1, nx - 1), iy1 = std::min(iy + 1, ny - 1);
  double tx = fx - ix, ty = fy - iy;
  auto at = [&](int i, int j) { return double(cell(i, j)); };
  double a = at(ix, iy) * (1 - tx) + at(ix1, iy) * tx;
  double b = at(ix, iy1) * (1 - tx) + at(ix1, iy1) * tx;
  return a * (1 - ty) + b * ty;
}

}  // namespace c3d
