#include "cadastre/batch/out_dir.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <set>
#include <system_error>

#include "core/error.h"

namespace fs = std::filesystem;

namespace c3d {

OutDirLock::OutDirLock(const std::string& out_dir) {
  const std::string path = (fs::path(out_dir) / ".cadastre3d.lock").string();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw InputError(out_dir, std::string("cannot create the lock file: ") + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    char pid[32] = {0};
    const ssize_t n = ::pread(fd_, pid, sizeof pid - 1, 0);
    ::close(fd_);
    fd_ = -1;
    if (err != EWOULDBLOCK) throw InputError(out_dir, std::string("cannot lock: ") + std::strerror(err));
    std::string holder = n > 0 ? std::string(pid, size_t(n)) : std::string("?");
    while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) holder.pop_back();
    throw InputError(out_dir, "another cadastre3d command (pid " + holder +
                                  ") is writing to this folder; wait for it or choose another --out");
  }
  // The pid only words a refused batch's message: failing to write it is harmless.
  const std::string me = std::to_string(::getpid()) + "\n";
  [[maybe_unused]] const bool written =
      ::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, me.data(), me.size(), 0) == ssize_t(me.size());
}

OutDirLock::~OutDirLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the flock
}

std::string staging_dir(const std::string& out_dir) { return (fs::path(out_dir) / ".staging").string(); }

void publish_staged(const std::string& staging, const std::string& out_dir, const std::vector<std::string>& whole) {
  std::set<fs::path> published;
  for (const auto& e : fs::recursive_directory_iterator(staging)) {
    if (!e.is_regular_file()) continue;
    const fs::path to = fs::path(out_dir) / fs::relative(e.path(), staging);
    std::error_code ec;
    fs::create_directories(to.parent_path(), ec);
    fs::rename(e.path(), to, ec);
    if (ec) throw InputError(to.string(), "cannot move the finished file into place: " + ec.message());
    published.insert(to);
  }
  for (const std::string& folder : whole) {
    std::error_code ec;
    if (!fs::is_directory(fs::path(staging) / folder, ec)) continue;
    std::vector<fs::path> stale;
    for (const auto& e : fs::recursive_directory_iterator(fs::path(out_dir) / folder, ec))
      if (e.is_regular_file() && !published.count(e.path())) stale.push_back(e.path());
    for (const fs::path& f : stale) fs::remove(f, ec);
  }
  fs::remove_all(staging);
}

std::string moved(const std::string& path, const std::string& from, const std::string& to) {
  return (fs::path(to) / fs::relative(path, from)).string();
}

void write_staged_into(const std::string& out_dir, const std::function<void(const std::string& stage)>& write,
                       const std::vector<std::string>& whole) {
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw InputError(out_dir, "cannot create the output folder: " + ec.message());
  const OutDirLock lock(out_dir);
  const std::string stage = staging_dir(out_dir);
  fs::remove_all(stage);
  fs::create_directories(stage);
  write(stage);
  publish_staged(stage, out_dir, whole);
}

void remove_batch_outputs(const std::string& out_dir) {
  static const char* const kOutputs[] = {
      "cadastre.gpkg", "cadastre.gpkg-wal", "cadastre.gpkg-shm", "summary.json", "report.html",
      "report.csv", "buildings.gml", "buildings.citygml3.gml", "buildings.city.json", "buildings.ifc",
      "buildings.city.jsonl", "obj", "step", "preview", "report", "mesh", ".staging"};
  for (const char* name : kOutputs) {
    std::error_code ec;
    fs::remove_all(fs::path(out_dir) / name, ec);
    if (ec) throw InputError((fs::path(out_dir) / name).string(), "cannot remove (--overwrite): " + ec.message());
  }
}

}  // namespace c3d
