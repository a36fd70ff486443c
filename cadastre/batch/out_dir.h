#pragma once
// The output folder of a batch: one batch at a time (an advisory lock), and
// outputs that appear whole or not at all (written under a staging folder in
// OUT, then each renamed into place).
#include <functional>
#include <string>
#include <vector>

namespace c3d {

// An exclusive advisory lock (flock) on OUT/.cadastre3d.lock, held while the
// object lives and released by the kernel when the process ends, however it
// ends. A second holder is refused: InputError naming the folder and the pid
// that holds it.
class OutDirLock {
 public:
  explicit OutDirLock(const std::string& out_dir);
  ~OutDirLock();
  OutDirLock(const OutDirLock&) = delete;
  OutDirLock& operator=(const OutDirLock&) = delete;

 private:
  int fd_ = -1;
};

// OUT/.staging: the batch writes its outputs here first (same file system as
// OUT, so each rename into place is atomic). A killed batch leaves it behind;
// the next batch on OUT removes it.
std::string staging_dir(const std::string& out_dir);
// Moves every file under `staging` to the same relative place under out_dir
// (one rename each: a reader sees the old file or the new one, never a part),
// then removes `staging`. Each folder of `whole` ("report", "obj") that the
// staging holds is replaced as a whole: its files under out_dir that the
// staging did not hold go (a report of fewer parcels leaves no old page).
void publish_staged(const std::string& staging, const std::string& out_dir,
                    const std::vector<std::string>& whole = {});
// The same relative path under `to` as `path` has under `from`.
std::string moved(const std::string& path, const std::string& from, const std::string& to);
// For a command writing into a folder a batch may hold (report, export):
// under OUT's lock (refused while another command holds it), `write` fills
// a fresh OUT/.staging, which is then published (whole as publish_staged).
void write_staged_into(const std::string& out_dir, const std::function<void(const std::string& stage)>& write,
                       const std::vector<std::string>& whole);
// Removes what a batch writes into out_dir (store, summary, report, exports,
// previews, staging) and nothing else, for --overwrite.
void remove_batch_outputs(const std::string& out_dir);

}  // namespace c3d
