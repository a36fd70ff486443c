#include "tests/test_support.h"

#include <array>
#include <cstdio>
#include <filesystem>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace c3d::test {

static std::string shared_path(const std::string& sub) {
  fs::path p = fs::path(C3D_SOURCE_DIR).parent_path() / "shared" / sub;
  return fs::exists(p) ? p.string() : std::string();
}

std::string cimahi_dir() { return shared_path("data/cimahi"); }
std::string schemas_dir() { return shared_path("schemas"); }

std::string temp_dir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("c3d_test_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

int run_cli(const std::string& args, std::string* output) {
  std::string cmd = std::string(C3D_CLI_PATH) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buf;
  std::string out;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  int status = pclose(pipe);
  if (output) *output = out;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace c3d::test
