#pragma once
// The stages' ArtifactWriter on a folder of the content store: the files a stage writes (hashed as
// they are written, so the commit does not read them again), those it takes from other artifacts
// (referred to), and what it publishes (private to the runtime).
// Its files go through the store's FileSystem; `path()` (for libraries that write files themselves)
// is meaningful on the real one only.
#include <atomic>
#include <mutex>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "olt/core/file_system.h"
#include "olt/stages/stage.h"
#include "publish_list.h"

namespace olt {

class ArtifactFolder : public ArtifactWriter {
 public:
  ArtifactFolder(fs::path dir, FileSystem& files) : dir_(std::move(dir)), files_(files) {}
  void write(const std::string& file, std::string_view bytes) override;
  void write_pieces(const std::string& file, const std::function<void(const PieceSink&)>& make) override;
  fs::path path(const std::string& file) override;
  void refer(const std::string& file, const Artifact& from, const std::string& from_file) override;
  void publish(Published published) override;
  using ArtifactWriter::publish;

  /// What the stage's last run in this process wrote (`carried_forward`'s list, its artifacts still
  /// in the store): a file written now under the same name with the same bytes is referred to where
  /// those bytes are, not written again. `olt watch` after a one-box edit: the export's boxes files
  /// but those of the frames that show the box, the report's pictures but the box's. An empty list
  /// carries nothing but starts the record carried_forward makes.
  void carry_from(ArtifactFiles before);
  /// The files this run wrote or carried, each where its bytes are in `committed` (this folder as the
  /// store committed it): what the next run of the stage carries. After carry_from only.
  ArtifactFiles carried_forward(const Artifact& committed) const;

  const fs::path& dir() const { return dir_; }
  /// The publish list's text (publish.json), in pieces.
  void publish_list(const PieceSink& sink) const { published_.pieces(sink); }
  /// What the commit need not read again (Store::commit's `described`): the files taken from other
  /// artifacts (listed with where their bytes are, not copied or linked: 70,000 at 10,000 frames),
  /// and the files written here with the digest and size of the bytes written (hashed as they were
  /// written; not those a library wrote through `path`, written more than once, or whose write
  /// failed: the commit hashes those from the disk).
  ArtifactFiles take_described();

 private:
  fs::path dir_;
  FileSystem& files_;
  PublishListText published_;  ///< 60,000 entries at 10,000 frames, as text
  // 70,000 at 10,000 frames (a source writes 30,000): held compactly, and so committed.
  ArtifactFiles referred_;
  ArtifactFiles written_;
  std::set<std::string, std::less<>> unhashed_;
  // Carrying (after carry_from): what the last run wrote, the names written or carried here (true:
  // carried; a name met again is written, as a file written twice is), and those carried, then written.
  std::atomic<bool> carrying_{false};  // read before the lock: a write in `olt run` takes it once
  ArtifactFiles before_;
  std::unordered_map<std::string, bool> named_;
  std::set<std::string, std::less<>> uncarried_;
  mutable std::mutex mutex_;  // for the lists above

  void record_written(const std::string& file, const std::string& sha256, size_t size);
  void leave_unhashed(const std::string& file);
  /// Whether `file` (a listed name) with these bytes was referred to where the last run's are; else
  /// it is named as written here.
  bool carried(const std::string& file, const Digest& sha256, size_t size);
  /// `file` (a listed name) is written here: a name carried before is no longer carried. Under the
  /// lock.
  void name_written(const std::string& file);
};

}  // namespace olt
