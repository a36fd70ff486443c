#pragma once
// Seeded mutations of a valid input: what a damaged disk, a broken exporter or
// a hostile sender makes of a file. The same (seed, input, iteration) gives the
// same mutant, so any finding replays from three numbers.
#include <cstdint>
#include <random>
#include <string>

namespace c3d::fuzz {

struct SeedInput {
  std::string name;    // e.g. "las-1.4-format6"
  std::string ext;     // file extension the reader dispatches on, e.g. ".las"
  std::string bytes;   // the valid file
  size_t header = 0;   // bytes of header where field changes are aimed (0: none)
  bool text = false;   // line/token mutations apply (CSV, PLY/PCD headers, TOML, JSON)
};

// 64-bit mix of the campaign seed, the target's name and the iteration.
uint64_t mix_seed(uint64_t seed, const std::string& target, uint64_t iteration);

class Mutator {
 public:
  explicit Mutator(uint64_t seed) : rng_(seed) {}
  // One to four stacked mutations of seed.bytes.
  std::string mutate(const SeedInput& seed);

 private:
  size_t pick(size_t n);  // uniform in [0, n); 0 when n == 0
  size_t offset_in(const std::string& b, size_t header);
  void binary_op(std::string& b, size_t header);
  void text_op(std::string& b);
  void set_interesting(std::string& b, size_t header);
  void replace_number(std::string& b);
  void chunk_op(std::string& b);

  std::mt19937_64 rng_;
};

}  // namespace c3d::fuzz
