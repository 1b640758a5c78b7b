#pragma once
// The stages' ArtifactWriter on a folder of the content store: the files a stage writes (hashed as
// they are written, so the commit does not read them again), those it takes from other artifacts
// (referred to), and what it publishes (private to the runtime).
// Its files go through the store's FileSystem; `path()` (for libraries that write files themselves)
// is meaningful on the real one only.
#include <deque>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "olt/core/file_system.h"
#include "olt/stages/stage.h"
#include "publish_list.h"

namespace olt {

class ArtifactFolder : public ArtifactWriter {
 public:
  /// `previous`: the stage's artifact from its last run, if it has one. A file written with the bytes
  /// it holds under the same name is referred to where those bytes are, not written again: after an
  /// edit of one box the export writes 1,500 of its 10,000 boxes files, not all of them.
  ArtifactFolder(fs::path dir, FileSystem& files, std::optional<Artifact> previous = std::nullopt)
      : dir_(std::move(dir)), files_(files), previous_(std::move(previous)) {}
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
  std::deque<ArtifactFile> take_described();

 private:
  fs::path dir_;
  FileSystem& files_;
  std::optional<Artifact> previous_;
  PublishListText published_;  ///< 60,000 entries at 10,000 frames, as text
  // Growing lists of 70,000 at 10,000 frames: in blocks, never copied to grow (a vector holds up to
  // three times its size while it grows).
  std::deque<ArtifactFile> referred_;
  std::deque<ArtifactFile> written_;
  SharedKeys keys_;  ///< of the artifacts referred to
  std::set<std::string> unhashed_;
  std::set<std::string> named_;  ///< with a previous artifact, the names written: one written twice is not referred to
  std::mutex mutex_;             // for the lists above

  bool refer_unchanged(const std::string& name, size_t size, const std::string& sha256);
  void record_written(const std::string& file, const std::string& sha256, size_t size);
  void leave_unhashed(const std::string& file);
};

}  // namespace olt
