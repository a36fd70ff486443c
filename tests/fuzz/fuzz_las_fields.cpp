#include "tests/fuzz/fuzz_las_fields.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>

#include "core/error.h"
#include "core/io/crs.h"
#include "core/io/laz/laz_writer.h"
#include "core/io/point_io.h"

namespace c3d::fuzz {

namespace {

std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

PointCloud grid_cloud(int n) {
  PointCloud c;
  for (int i = 0; i < n; ++i) {
    c.points.emplace_back(781800.25 + 0.37 * (i % 23), 9240000.5 + 0.41 * (i / 23), 790 + 0.05 * (i % 7));
    c.classes.push_back(uint8_t(i % 3 == 0 ? 2 : i % 3 == 1 ? 6 : 1));
  }
  c.crs_wkt = wkt_from_epsg(32748);
  return c;
}

// A field of the file: where it lies and how wide it is.
struct Field {
  size_t at = 0;
  int bytes = 0;  // 1, 2, 4, 8; -8: a double
};

template <typename T>
T get(const std::string& b, size_t at) {
  T v{};
  if (at + sizeof(T) <= b.size()) std::memcpy(&v, &b[at], sizeof(T));
  return v;
}

template <typename T>
void put(std::string& b, size_t at, T v) {
  if (at + sizeof(T) <= b.size()) std::memcpy(&b[at], &v, sizeof(T));
}

// The LASzip VLR's chunk size field, if the file has the VLR.
size_t chunk_size_at(const std::string& b) {
  const uint16_t header = get<uint16_t>(b, 94);
  const uint32_t vlrs = get<uint32_t>(b, 100);
  size_t at = header;
  for (uint32_t k = 0; k < vlrs && at + 54 <= b.size(); ++k) {
    const uint16_t length = get<uint16_t>(b, at + 20);
    if (b.compare(at + 2, 14, "laszip encoded") == 0 && get<uint16_t>(b, at + 18) == 22204) return at + 54 + 12;
    at += 54 + length;
  }
  return 0;
}

// The integer fields a writer sets: header size, point offset, VLR count,
// record length, point counts; the chunk size and chunk table offset of LAZ.
std::vector<Field> count_fields(const std::string& b) {
  std::vector<Field> f = {{94, 2}, {96, 4}, {100, 4}, {105, 2}, {107, 4}, {111, 4}};
  if (get<uint8_t>(b, 25) >= 4) f.insert(f.end(), {{247, 8}, {255, 8}, {235, 8}, {243, 4}});
  if (const size_t c = chunk_size_at(b)) {
    f.push_back({c, 4});
    f.push_back({get<uint32_t>(b, 96), 8});
  }
  return f;
}

uint64_t near_value(uint64_t v, std::mt19937_64& rng) {
  switch (rng() % 8) {
    case 0: return v + 1;
    case 1: return v - 1;
    case 2: return v + 1000;
    case 3: return v >= 1000 ? v - 1000 : v / 3;
    case 4: return v * 2;
    case 5: return v / 2;
    case 6: return 0;
    default: return v + 1 + rng() % 64;
  }
}

void mutate_count(std::string& b, const Field& f, std::mt19937_64& rng) {
  switch (f.bytes) {
    case 2: put<uint16_t>(b, f.at, uint16_t(near_value(get<uint16_t>(b, f.at), rng))); break;
    case 4: put<uint32_t>(b, f.at, uint32_t(near_value(get<uint32_t>(b, f.at), rng))); break;
    default: put<uint64_t>(b, f.at, near_value(get<uint64_t>(b, f.at), rng));
  }
}

// The header's bounds (max x, min x, max y, min y, max z, min z at 179):
// one side moved in a little or a lot, the box moved 10 km, or all zero.
void mutate_bounds(std::string& b, std::mt19937_64& rng) {
  double v[6];
  for (int k = 0; k < 6; ++k) v[k] = get<double>(b, 179 + 8 * size_t(k));
  const int side = int(rng() % 6), pair = side / 2 * 2;
  const double width = v[pair] - v[pair + 1], fraction[] = {0.001, 0.1, 0.5};
  switch (rng() % 4) {
    case 0:
    case 1: v[side] += (side % 2 ? 1 : -1) * width * fraction[rng() % 3]; break;
    case 2: v[0] += 10000, v[1] += 10000; break;
    default:
      for (double& x : v) x = 0;
  }
  for (int k = 0; k < 6; ++k) put<double>(b, 179 + 8 * size_t(k), v[k]);
}

bool same_points(const PointCloud& a, const PointCloud& b, std::string& why) {
  if (a.points.size() != b.points.size()) {
    why = std::to_string(b.points.size()) + " points read, the seed has " + std::to_string(a.points.size());
    return false;
  }
  for (size_t i = 0; i < a.points.size(); ++i)
    if (a.points[i] != b.points[i] || (a.classes.empty() ? 0 : a.classes[i]) != (b.classes.empty() ? 0 : b.classes[i])) {
      std::ostringstream s;
      s.precision(12);
      s << "point " << i << " reads " << b.points[i].transpose() << ", the seed's is " << a.points[i].transpose();
      why = s.str();
      return false;
    }
  return true;
}

// The mutant read one way: InputError (refused), or the points as read.
bool read_or_refused(const std::function<PointCloud()>& read, PointCloud& out) {
  try {
    out = read();
    return true;
  } catch (const InputError&) {
    return false;
  }
}

}  // namespace

std::vector<SeedInput> las_field_seeds(const std::string& work) {
  std::vector<SeedInput> out;
  const std::string path = work + "/field-seed.las";
  for (auto [format, minor] : {std::pair{1, 2}, {6, 4}}) {
    write_las(path, grid_cloud(300), format, minor);
    const std::string las = read_bytes(path);
    const std::string name = "1." + std::to_string(minor) + "-f" + std::to_string(format);
    out.push_back({"las-" + name, ".las", las, 0, false});
    const std::vector<uint8_t> laz = laz::compress_las(std::vector<uint8_t>(las.begin(), las.end()), 100);
    out.push_back({"laz-3-chunks-" + name, ".laz", std::string(laz.begin(), laz.end()), 0, false});
  }
  for (const char* name : {"simple.laz", "1.2-with-color.copc.laz"}) {
    const std::string shared = std::string(C3D_SOURCE_DIR) + "/../shared/data/laz/" + name;
    if (std::filesystem::exists(shared)) out.push_back({std::string("laz-") + name, ".laz", read_bytes(shared), 0, false});
  }
  return out;
}

std::string mutate_las_fields(const std::string& bytes, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::string b = bytes;
  // One count field, the bounds, or both. Two count fields changed together
  // can make a well-formed file of other points (half the count, twice the
  // record length: the rest reads as extra bytes), which no reader can tell.
  const std::vector<Field> fields = count_fields(b);
  const uint64_t what = rng() % 3;
  if (what != 1) mutate_count(b, fields[rng() % fields.size()], rng);
  if (what != 0) mutate_bounds(b, rng);
  return b;
}

void expect_refused_or_same(const std::string& path, const SeedInput& seed) {
  static std::map<std::string, PointCloud> originals;  // each seed decoded once
  auto known = originals.find(seed.name);
  if (known == originals.end()) {
    const std::string original = path + ".seed" + seed.ext;
    std::ofstream(original, std::ios::binary) << seed.bytes;
    known = originals.emplace(seed.name, read_point_cloud(original)).first;
    std::filesystem::remove(original);
  }
  PointCloud whole, streamed;
  const bool read_whole = read_or_refused([&] { return read_point_cloud(path); }, whole);
  const bool read_streamed = read_or_refused(
      [&] {
        PointCloud all;
        for_each_point_block(path, [&](const PointCloud& c) {
          all.points.insert(all.points.end(), c.points.begin(), c.points.end());
          all.classes.insert(all.classes.end(), c.classes.begin(), c.classes.end());
        });
        return all;
      },
      streamed);
  if (!read_whole && !read_streamed) throw InputError(path, "refused both ways");
  std::string why;
  if (read_whole && !same_points(known->second, whole, why)) throw std::runtime_error("silent change, read whole: " + why);
  if (read_streamed && !same_points(known->second, streamed, why))
    throw std::runtime_error("silent change, streamed: " + why);
}

}  // namespace c3d::fuzz
