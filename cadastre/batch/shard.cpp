#include "cadastre/batch/shard.h"

#include <algorithm>
#include <cstdlib>
#include <numeric>

#include "core/error.h"
#include "core/geometry/hilbert.h"

namespace c3d {
namespace {

// Centre of the parcel's bounding box (world); a parcel with no vertex sits at 0,0.
Vec2 box_centre(const Parcel& p) {
  bool any = false;
  Vec2 lo(0, 0), hi(0, 0);
  for (const auto& poly : p.shape)
    for (const Vec2& v : poly.outer) {
      lo = any ? Vec2(lo.cwiseMin(v)) : v;
      hi = any ? Vec2(hi.cwiseMax(v)) : v;
      any = true;
    }
  return (lo + hi) / 2;
}

// A whole positive decimal number, or -1.
// Digits only (at most kMaxDigits: an int), else -1; -2 for more digits.
constexpr size_t kMaxDigits = 9;
long whole_number(const std::string& s) {
  if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos) return -1;
  if (s.size() > kMaxDigits) return -2;
  return std::strtol(s.c_str(), nullptr, 10);
}

}  // namespace

namespace {

// K and N of "K/N", each -1 (not a whole number) or -2 (too many digits) where not.
std::pair<long, long> shard_numbers(const std::string& text) {
  const auto slash = text.find('/');
  if (slash == std::string::npos) return {-1, -1};
  return {whole_number(text.substr(0, slash)), whole_number(text.substr(slash + 1))};
}

}  // namespace

std::string shard_problem(const std::string& text) {
  const auto [k, n] = shard_numbers(text);
  if (k == -2 || n == -2) return "'" + text + "' has more shards than " + std::string(kMaxDigits, '9');
  if (k < 1 || n < 1 || k > n) return "'" + text + "' is not K/N with 1 <= K <= N (e.g. 2/4)";
  return "";
}

Shard parse_shard(const std::string& text) {
  if (const std::string problem = shard_problem(text); !problem.empty()) throw InputError("--shard", problem);
  const auto [k, n] = shard_numbers(text);
  return {int(k), int(n)};
}

std::string to_string(const Shard& s) {
  return s.active() ? std::to_string(s.k) + "/" + std::to_string(s.n) : "";
}

std::vector<size_t> shard_parcels(const std::vector<Parcel>& parcels, const Shard& s) {
  std::vector<size_t> out(parcels.size());
  std::iota(out.begin(), out.end(), size_t(0));
  if (!s.active()) return out;
  std::vector<Vec2> centres;
  centres.reserve(parcels.size());
  for (const Parcel& p : parcels) centres.push_back(box_centre(p));
  const std::vector<size_t> order = hilbert_order(centres);
  const IndexRange r = part_range(order.size(), s.k, s.n);
  out.assign(order.begin() + long(r.begin), order.begin() + long(r.end));
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace c3d
