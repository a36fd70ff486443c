#include "ifc_citygml/detail.h"
#include "core/text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "core/geometry/geometry.h"

namespace c3d::exp {

Ring3 hole_oriented(const Face& face, size_t k) {
  Ring3 h = face.holes[k];
  if (newell_normal(h).dot(newell_normal(face.ring)) > 0) std::reverse(h.begin(), h.end());
  return h;
}

static bool same_ring(const Ring3& a, const Ring3& b, double tol) {
  if (a.size() != b.size() || a.empty()) return false;
  const size_t n = a.size();
  for (size_t s = 0; s < n; ++s) {
    bool ok = true;
    for (size_t i = 0; i < n && ok; ++i) ok = (a[i] - b[(i + s) % n]).norm() <= tol;
    if (ok) return true;
  }
  return false;
}

std::array<int, 2> matching_element_face(const Building& b, const Face& f) {
  for (size_t e = 0; e < b.elements.size(); ++e) {
    const auto& faces = b.elements[e].faces;
    for (size_t k = 0; k < faces.size(); ++k) {
      if (faces[k].holes.size() == f.holes.size() && same_ring(faces[k].ring, f.ring, 1e-3))
        return {int(e), int(k)};
    }
  }
  return {-1, -1};
}

// True when face f lies in the plane of g (same orientation) within 1 cm.
static bool coplanar(const Face& f, const Face& g) {
  Vec3 nf = unit_normal(f), ng = unit_normal(g);
  if (nf.dot(ng) < 0.999) return false;
  for (const auto& p : f.ring)
    if (std::abs((p - g.ring.front()).dot(ng)) > 0.01) return false;
  return true;
}

ElementType solid_face_type(const Building& b, const Face& f) {
  auto m = matching_element_face(b, f);
  if (m[0] >= 0) return b.elements[m[0]].type;
  for (const auto& e : b.elements) {
    if (e.type == ElementType::OuterCeiling) continue;
    for (const auto& g : e.faces)
      if (coplanar(f, g)) return e.type;
  }
  Vec3 n = unit_normal(f);
  if (n.z() < -0.9) return ElementType::Ground;
  if (std::abs(n.z()) < 0.1) return ElementType::Wall;
  return ElementType::Roof;
}

static double face_min_z(const Face& f) {
  double z = f.ring.front().z();
  for (const auto& p : f.ring) z = std::min(z, p.z());
  return z;
}

static bool inside_xy(const Ring3& ring, const Vec2& p) {
  bool in = false;
  for (size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Vec3 &a = ring[i], &b = ring[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

// Roof elements whose eaves lie more than 1 m apart are separate levels; every other
// element joins the level whose roof covers a point just inside its first face.
std::vector<int> element_levels(const Building& b, int* level_count) {
  const double kGap = 1.0;
  std::vector<std::pair<double, int>> eaves;  // eave z, element
  for (size_t e = 0; e < b.elements.size(); ++e) {
    const auto& el = b.elements[e];
    if (el.type != ElementType::Roof || el.faces.empty()) continue;
    double z = face_min_z(el.faces.front());
    for (const auto& f : el.faces) z = std::min(z, face_min_z(f));
    eaves.push_back({z, int(e)});
  }
  std::sort(eaves.begin(), eaves.end());
  std::vector<int> level(b.elements.size(), 0);
  int levels = eaves.empty() ? 1 : 1;
  for (size_t i = 0; i < eaves.size(); ++i) {
    if (i > 0 && eaves[i].first - eaves[i - 1].first > kGap) ++levels;
    level[eaves[i].second] = levels - 1;
  }
  *level_count = levels;
  if (levels == 1) return level;
  for (size_t e = 0; e < b.elements.size(); ++e) {
    const auto& el = b.elements[e];
    if (el.type == ElementType::Roof || el.faces.empty()) continue;
    const Face& f = el.faces.front();
    Vec3 c = Vec3::Zero();
    for (const auto& p : f.ring) c += p;
    c /= double(f.ring.size());
    Vec3 n = unit_normal(f);
    Vec2 probe(c.x() - 0.1 * n.x(), c.y() - 0.1 * n.y());  // step inside for walls
    for (const auto& [z, r] : eaves) {
      bool hit = false;
      for (const auto& rf : b.elements[r].faces) hit = hit || inside_xy(rf.ring, probe);
      if (hit) { level[e] = level[r]; break; }
    }
  }
  return level;
}

const Parcel* parcel_of(const BatchModel& m, const ParcelResult& r) {
  if (r.parcel_index >= 0 && size_t(r.parcel_index) < m.parcels.size() &&
      m.parcels[r.parcel_index].id == r.parcel_id)
    return &m.parcels[r.parcel_index];
  for (const auto& p : m.parcels)
    if (p.id == r.parcel_id) return &p;
  return nullptr;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s(buf);
  if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

std::string xml_escape(const std::string& s) { return escape_markup(s); }

std::string uri_escape(const std::string& s) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : s) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~') {
      out += char(c);
    } else {
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

const char* citygml_surface(ElementType t) {
  switch (t) {
    case ElementType::Roof: return "RoofSurface";
    case ElementType::Wall:
    case ElementType::PartyWall: return "WallSurface";
    case ElementType::Ground: return "GroundSurface";
    case ElementType::OuterCeiling: return "OuterCeilingSurface";
  }
  return "WallSurface";
}

}  // namespace c3d::exp
