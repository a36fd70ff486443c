#include "tests/fuzz/fuzz_mutate.h"

#include <cfloat>
#include <cstring>
#include <limits>
#include <vector>

namespace c3d::fuzz {

namespace {

// Values that sit on the edges readers get wrong: sign bits, all ones, float
// and double overflow, NaN/inf, 2^31, 2^32.
const uint64_t kInts[] = {0, 1, 2, 0x7F, 0x80, 0xFF, 0x7FFF, 0x8000, 0xFFFF, 0x10000,
                          0x7FFFFFFF, 0x80000000, 0xFFFFFFFF, 0x100000000ull,
                          0x7FFFFFFFFFFFFFFFull, 0x8000000000000000ull, ~0ull};
const double kDoubles[] = {0.0,    -0.0,   1e-300, 1e15,   -1e15, 3.5e38, -3.5e38, 1e308,
                           DBL_MAX, -DBL_MAX, std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN(), 1e9, 2e9};
const float kFloats[] = {0.0f, FLT_MAX, -FLT_MAX, 1e-45f, 3e38f, 1e10f,
                         std::numeric_limits<float>::infinity(),
                         std::numeric_limits<float>::quiet_NaN()};
const char* const kNumbers[] = {
    "0", "-1", "1", "255", "256", "65536", "2147483647", "2147483648", "-2147483649",
    "4294967295", "4294967296", "9223372036854775807", "18446744073709551615",
    "99999999999999999999999", "3.5e38", "-3.5e38", "1e308", "1e400", "-1e400", "1e-400",
    "nan", "NaN", "inf", "-inf", "0x10", "1e15", "-0", "1.5", "", "+", "-", "1e", "1e9", "2e9"};
const char* const kInserts[] = {"\n", "\r\n", "\t", " ", ",", ";", "\"", "'", "#", "[", "]",
                                "{", "}", "=", ".", "\\", "" /* NUL, see text_op */,
                                "\xff", "\xc3\x28", "\xef\xbb\xbf", "ply\n", "end_header\n",
                                "element vertex 1\n", "property float x\n"};

template <typename T>
void put(std::string& b, size_t at, T v) {
  if (at + sizeof(T) <= b.size()) std::memcpy(&b[at], &v, sizeof(T));
}

bool number_char(char c) {
  return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E';
}

}  // namespace

uint64_t mix_seed(uint64_t seed, const std::string& target, uint64_t iteration) {
  uint64_t h = 1469598103934665603ull ^ seed;  // FNV-1a over the name, then splitmix64
  for (unsigned char c : target) h = (h ^ c) * 1099511628211ull;
  h += iteration * 0x9E3779B97F4A7C15ull;
  h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
  h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
  return h ^ (h >> 31);
}

size_t Mutator::pick(size_t n) { return n == 0 ? 0 : size_t(rng_() % n); }

// Half the time within the header (where counts, offsets and sizes live).
size_t Mutator::offset_in(const std::string& b, size_t header) {
  if (header > 0 && pick(2) == 0) return pick(std::min(header, b.size()));
  return pick(b.size());
}

void Mutator::set_interesting(std::string& b, size_t header) {
  const size_t at = offset_in(b, header);
  switch (pick(5)) {
    case 0: put<uint8_t>(b, at, uint8_t(kInts[pick(6)])); break;
    case 1: put<uint16_t>(b, at, uint16_t(kInts[pick(10)])); break;
    case 2: put<uint32_t>(b, at, uint32_t(kInts[pick(14)])); break;
    case 3: put<uint64_t>(b, at, kInts[pick(std::size(kInts))]); break;
    default:
      if (pick(2)) put<double>(b, at, kDoubles[pick(std::size(kDoubles))]);
      else put<float>(b, at, kFloats[pick(std::size(kFloats))]);
  }
}

void Mutator::chunk_op(std::string& b) {
  if (b.empty()) return;
  const size_t a = pick(b.size()), len = 1 + pick(std::min<size_t>(b.size() - a, 512));
  switch (pick(3)) {
    case 0: b.insert(pick(b.size() + 1), b.substr(a, len)); break;  // duplicate a chunk
    case 1: b.erase(a, len); break;
    default: {  // overwrite with another part of the file
      const size_t to = pick(b.size());
      b.replace(to, std::min(len, b.size() - to), b.substr(a, len));
    }
  }
}

void Mutator::binary_op(std::string& b, size_t header) {
  if (b.empty()) return;
  switch (pick(6)) {
    case 0: {  // flip 1-8 bits
      for (size_t k = 0, n = 1 + pick(8); k < n; ++k) b[offset_in(b, header)] ^= char(1 << pick(8));
      break;
    }
    case 1: b[offset_in(b, header)] = char(pick(3) == 0 ? 0 : pick(2) ? 0xFF : pick(256)); break;
    case 2: set_interesting(b, header); break;
    case 3: b.resize(pick(b.size())); break;  // truncate
    case 4: chunk_op(b); break;
    default: {  // random bytes inserted
      std::string r(1 + pick(16), '\0');
      for (char& c : r) c = char(pick(256));
      b.insert(pick(b.size() + 1), r);
    }
  }
}

// A run of number characters replaced by an edge-case number.
void Mutator::replace_number(std::string& b) {
  std::vector<size_t> starts;
  for (size_t i = 0; i < b.size(); ++i)
    if (number_char(b[i]) && (i == 0 || !number_char(b[i - 1]))) starts.push_back(i);
  if (starts.empty()) return;
  const size_t s = starts[pick(starts.size())];
  size_t e = s;
  while (e < b.size() && number_char(b[e])) ++e;
  b.replace(s, e - s, kNumbers[pick(std::size(kNumbers))]);
}

void Mutator::text_op(std::string& b) {
  std::vector<size_t> lines{0};
  for (size_t i = 0; i < b.size(); ++i)
    if (b[i] == '\n') lines.push_back(i + 1);
  auto line_at = [&](size_t k) {
    const size_t s = lines[k], e = k + 1 < lines.size() ? lines[k + 1] : b.size();
    return std::make_pair(s, e - s);
  };
  switch (pick(5)) {
    case 0:
    case 1: replace_number(b); break;
    case 2: {  // duplicate or delete a line
      auto [s, n] = line_at(pick(lines.size()));
      if (pick(2)) b.insert(s, b.substr(s, n));
      else b.erase(s, n);
      break;
    }
    case 3: {  // swap two lines
      auto [s1, n1] = line_at(pick(lines.size()));
      auto [s2, n2] = line_at(pick(lines.size()));
      if (s1 > s2) std::swap(s1, s2), std::swap(n1, n2);
      if (s1 + n1 > s2) break;
      const std::string l1 = b.substr(s1, n1), l2 = b.substr(s2, n2);
      b.replace(s2, n2, l1);
      b.replace(s1, n1, l2);
      break;
    }
    default: {
      const size_t k = pick(std::size(kInserts));
      const std::string ins = k == 16 ? std::string(1, '\0') : std::string(kInserts[k]);
      b.insert(pick(b.size() + 1), ins);
    }
  }
}

std::string Mutator::mutate(const SeedInput& seed) {
  std::string b = seed.bytes;
  for (size_t k = 0, n = 1 + pick(4); k < n; ++k) {
    if (seed.text && pick(3) != 0) text_op(b);
    else binary_op(b, seed.header);
  }
  return b;
}

}  // namespace c3d::fuzz
