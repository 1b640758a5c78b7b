#pragma once
// The stages' ArtifactWriter on a folder of the content store: the files a stage writes (hashed as
// they are written, so the commit does not read them again), those it takes from other artifacts
// (referred to), and what it publishes (private to the runtime).
// Its files go through the store's FileSystem; `path()` (for libraries that write files themselves)
// is meaningful on the real one only.
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "olt/core/file_system.h"
#include "olt/stages/stage.h"
#include "publish_list.h"

namespace olt {

/// Where a file's bytes are kept in the store: the artifact holding them, the file's name there, its
/// size and its place on disk.
struct KeptBytes {
  std::string key;
  std::string file;
  uint64_t size = 0;
  fs::path path;
};
/// The files a stage's last artifact in this process was written with, by their bytes' SHA-256 (hex).
using WrittenBefore = std::unordered_map<std::string, KeptBytes>;

class ArtifactFolder : public ArtifactWriter {
 public:
  /// With `before` (what the stage wrote last time, in a process that keeps memory: `olt watch`), a
  /// file written with bytes the store still holds there is referred to, not written again: after an
  /// edit, the export writes the boxes files of the frames that see the box, not all of them.
  ArtifactFolder(fs::path dir, FileSystem& files, std::shared_ptr<const WrittenBefore> before = nullptr)
      : dir_(std::move(dir)), files_(files), before_(std::move(before)) {}
  void write(const std::string& file, std::string_view bytes) override;
  void write_pieces(const std::string& file, const std::function<void(const PieceSink&)>& make) override;
  fs::path path(const std::string& file) override;
  void refer(const std::string& file, const Artifact& from, const std::string& from_file) override;
  void publish(Published published) override;
  using ArtifactWriter::publish;

  const fs::path& dir() const { return dir_; }
  /// The publish list's text (publish.json), in pieces.
  void publish_list(const PieceSink& sink) const { published_.pieces(sink); }
  /// What the commit need not read again (Store::commit's `described`): the files taken from other
  /// artifacts (listed with where their bytes are, not copied or linked: 70,000 at 10,000 frames),
  /// and the files written here with the digest and size of the bytes written (hashed as they were
  /// written; not those a library wrote through `path`, written more than once, or whose write
  /// failed: the commit hashes those from the disk).
  ArtifactFiles take_described();
  /// The files write() was given, where their bytes are kept now that the folder is `committed`:
  /// the next run's `before`.
  WrittenBefore written(const Artifact& committed) const;

 private:
  fs::path dir_;
  FileSystem& files_;
  PublishListText published_;  ///< 60,000 entries at 10,000 frames, as text
  // 70,000 at 10,000 frames (a source writes 30,000): held compactly, and so committed.
  ArtifactFiles referred_;
  ArtifactFiles written_;
  std::set<std::string, std::less<>> unhashed_;
  std::shared_ptr<const WrittenBefore> before_;
  std::map<std::string, std::string> given_;        ///< each name write() was given: its bytes' digest
  std::map<std::string, const KeptBytes*> reused_;  ///< names referred to their bytes in `before_`
  std::mutex mutex_;                                // for the lists above

  void record_written(const std::string& file, const std::string& sha256, size_t size);
  void leave_unhashed(const std::string& file);
  bool reuse(const std::string& file, const std::string& sha256, size_t size);
};

}  // namespace olt
