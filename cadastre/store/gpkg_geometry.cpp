#include "cadastre/store/gpkg_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "core/geometry/geometry.h"

namespace c3d {

namespace {

constexpr std::uint32_t kPolygon = 3, kMultiPolygon = 6, kZ = 1000;

class Writer {
 public:
  Blob out;
  void u8(std::uint8_t v) { out.push_back(v); }
  void u32(std::uint32_t v) { raw(&v, 4); }  // host is little endian (x86-64 / arm64)
  void f64(double v) { raw(&v, 8); }
  void i32(std::int32_t v) { raw(&v, 4); }

 private:
  void raw(const void* p, std::size_t n) {
    auto b = static_cast<const std::uint8_t*>(p);
    out.insert(out.end(), b, b + n);
  }
};

struct Envelope {
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
  double hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  void add(double x, double y, double z = 0) {
    double v[3] = {x, y, z};
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], v[i]), hi[i] = std::max(hi[i], v[i]);
  }
};

// Header: magic, version 0, flags (bit 0 little endian, bits 1-3 envelope 1=xy 2=xyz).
void header(Writer& w, int srs_id, const Envelope& e, bool z) {
  w.u8('G'); w.u8('P'); w.u8(0);
  w.u8(std::uint8_t(((z ? 2 : 1) << 1) | 1));
  w.i32(srs_id);
  w.f64(e.lo[0]); w.f64(e.hi[0]); w.f64(e.lo[1]); w.f64(e.hi[1]);
  if (z) { w.f64(e.lo[2]); w.f64(e.hi[2]); }
}

void ring3(Writer& w, const Ring3& r, const Vec3& off) {
  w.u32(std::uint32_t(r.size() + 1));
  for (size_t i = 0; i <= r.size(); ++i) {
    Vec3 p = r[i % r.size()] + off;
    w.f64(p.x()); w.f64(p.y()); w.f64(p.z());
  }
}

void ring2(Writer& w, const Ring2& r) {
  w.u32(std::uint32_t(r.size() + 1));
  for (size_t i = 0; i <= r.size(); ++i) { w.f64(r[i % r.size()].x()); w.f64(r[i % r.size()].y()); }
}

bool usable(const Ring3& r) { return r.size() >= 3; }
bool usable(const Ring2& r) { return r.size() >= 3; }

class Reader {
 public:
  Reader(const std::uint8_t* d, std::size_t n) : d_(d), n_(n) {}
  std::size_t pos = 0;
  bool little = true;
  std::uint8_t u8() { need(1); return d_[pos++]; }
  std::uint32_t u32() {
    need(4);
    std::uint8_t b[4];
    std::memcpy(b, d_ + pos, 4);
    if (!little) std::reverse(b, b + 4);
    pos += 4;
    std::uint32_t v;
    std::memcpy(&v, b, 4);
    return v;
  }
  double f64() {
    need(8);
    std::uint8_t b[8];
    std::memcpy(b, d_ + pos, 8);
    if (!little) std::reverse(b, b + 8);
    pos += 8;
    double v;
    std::memcpy(&v, b, 8);
    return v;
  }
  void need(std::size_t k) const {
    if (pos + k > n_) throw std::runtime_error("truncated GeoPackage geometry");
  }

 private:
  const std::uint8_t* d_;
  std::size_t n_;
};

// Skips the GP header; returns the envelope code.
int skip_header(Reader& r) {
  if (r.u8() != 'G' || r.u8() != 'P') throw std::runtime_error("not a GeoPackage geometry");
  r.u8();  // version
  std::uint8_t flags = r.u8();
  r.little = flags & 1;
  r.u32();  // srs id
  int env = (flags >> 1) & 7;
  static const int doubles[] = {0, 4, 6, 6, 8};
  if (env > 4) throw std::runtime_error("bad GeoPackage envelope code");
  for (int i = 0; i < doubles[env]; ++i) r.f64();
  return env;
}

struct WkbType {
  std::uint32_t base;
  int dims;
};

WkbType wkb_type(Reader& r) {
  r.little = r.u8() == 1;
  std::uint32_t t = r.u32();
  if (t & 0x80000000u) return {t & 0xffu, 3};  // EWKB Z flag, for robustness
  std::uint32_t base = t % 1000, kind = t / 1000;
  int dims = kind == 0 ? 2 : kind == 3 ? 4 : 3;
  return {base, dims};
}

Ring3 read_ring(Reader& r, int dims, const Vec3& off) {
  std::uint32_t n = r.u32();
  Ring3 ring;
  ring.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    double v[4] = {0, 0, 0, 0};
    for (int k = 0; k < dims; ++k) v[k] = r.f64();
    ring.push_back(Vec3(v[0], v[1], dims == 4 || dims == 3 ? v[2] : 0.0) - off);
  }
  if (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
  return ring;
}

Face read_polygon(Reader& r, int dims, const Vec3& off) {
  std::uint32_t rings = r.u32();
  Face f;
  for (std::uint32_t i = 0; i < rings; ++i) {
    Ring3 ring = read_ring(r, dims, off);
    if (i == 0) f.ring = std::move(ring);
    else f.holes.push_back(std::move(ring));
  }
  return f;
}

}  // namespace

Blob gpkg_faces_blob(const std::vector<Face>& faces, const Vec3& off, int srs_id) {
  Envelope e;
  std::uint32_t count = 0;
  for (const Face& f : faces) {
    if (!usable(f.ring)) continue;
    ++count;
    for (const Vec3& p : f.ring) e.add(p.x() + off.x(), p.y() + off.y(), p.z() + off.z());
  }
  if (count == 0) return {};
  Writer w;
  header(w, srs_id, e, true);
  w.u8(1);
  w.u32(kZ + kMultiPolygon);
  w.u32(count);
  for (const Face& f : faces) {
    if (!usable(f.ring)) continue;
    w.u8(1);
    w.u32(kZ + kPolygon);
    std::uint32_t holes = 0;
    for (const Ring3& h : f.holes) holes += usable(h);
    w.u32(1 + holes);
    ring3(w, f.ring, off);
    for (const Ring3& h : f.holes)
      if (usable(h)) ring3(w, h, off);
  }
  return std::move(w.out);
}

Blob gpkg_multipolygon_blob(const MultiPolygon2& mp, int srs_id) {
  Envelope e;
  std::uint32_t count = 0;
  for (const Polygon2& p : mp) {
    if (!usable(p.outer)) continue;
    ++count;
    for (const Vec2& v : p.outer) e.add(v.x(), v.y());
  }
  if (count == 0) return {};
  Writer w;
  header(w, srs_id, e, false);
  w.u8(1);
  w.u32(kMultiPolygon);
  w.u32(count);
  for (const Polygon2& p : mp) {
    if (!usable(p.outer)) continue;
    w.u8(1);
    w.u32(kPolygon);
    std::uint32_t holes = 0;
    for (const Ring2& h : p.holes) holes += usable(h);
    w.u32(1 + holes);
    ring2(w, p.outer);
    for (const Ring2& h : p.holes)
      if (usable(h)) ring2(w, h);
  }
  return std::move(w.out);
}

std::vector<Face> gpkg_read_faces(const std::uint8_t* data, std::size_t n, const Vec3& off) {
  std::vector<Face> faces;
  if (!data || n == 0) return faces;
  Reader r(data, n);
  skip_header(r);
  WkbType t = wkb_type(r);
  if (t.base == kPolygon) {
    faces.push_back(read_polygon(r, t.dims, off));
  } else if (t.base == kMultiPolygon) {
    std::uint32_t count = r.u32();
    for (std::uint32_t i = 0; i < count; ++i) {
      WkbType pt = wkb_type(r);
      if (pt.base != kPolygon) throw std::runtime_error("MultiPolygon member is not a Polygon");
      faces.push_back(read_polygon(r, pt.dims, off));
    }
  } else {
    throw std::runtime_error("geometry is not a (Multi)Polygon");
  }
  return faces;
}

MultiPolygon2 gpkg_read_multipolygon(const std::uint8_t* data, std::size_t n) {
  MultiPolygon2 mp;
  for (const Face& f : gpkg_read_faces(data, n, Vec3::Zero())) {
    Polygon2 p;
    p.outer = to_2d(f.ring);
    for (const Ring3& h : f.holes) p.holes.push_back(to_2d(h));
    mp.push_back(std::move(p));
  }
  return mp;
}

bool gpkg_envelope_xy(const std::uint8_t* data, std::size_t n, double env[4]) {
  if (!data || n < 8 + 32 || data[0] != 'G' || data[1] != 'P') return false;
  if (((data[3] >> 1) & 7) == 0 || !(data[3] & 1)) return false;
  double v[4];
  std::memcpy(v, data + 8, 32);  // minx, maxx, miny, maxy
  env[0] = v[0]; env[1] = v[2]; env[2] = v[1]; env[3] = v[3];
  return true;
}

}  // namespace c3d
