#include "olt/runtime/publish.h"

#include <algorithm>
#include <functional>
#include <optional>
#include <set>

#include "manifest.h"
#include "olt/core/error.h"
#include "olt/core/fault.h"
#include "olt/core/fs.h"
#include "olt/core/hash.h"
#include "olt/core/json_text.h"
#include "olt/core/parallel.h"
#include "olt/core/process_memory.h"
#include "olt/core/progress.h"
#include "olt/core/run_memory.h"
#include "olt/runtime/runner.h"
#include "olt/stages/stage.h"
#include "output_memory.h"
#include "pending_publish.h"
#include "publish_list.h"

namespace olt {
namespace {

// Calls `each` with every entry of `stage`'s artifact's publish list, in order: read as it is parsed,
// or where the process keeps memory (`olt watch`), from the list as it was parsed before with the
// same digest. Edit after edit the labeling stage publishes the same 60,000 files (their bytes change,
// their names do not): parsing its list was 5 % of a one-box cycle at 10,000 observations.
void for_each_published(const FileSystem& files, const std::string& stage, const Artifact& artifact,
                        const std::function<void(const Published&)>& each) {
  const fs::path list = artifact.path("publish.json");
  const std::optional<ListedFile> listed = artifact.file("publish.json");
  if (!keeping_memory() || !listed || listed->sha256.empty())
    return read_publish_list(*files.read_stream(list), list.string(), each);
  const auto parsed = remembered_or_made<std::vector<Published>>(
      "publish list " + stage, listed->sha256.hex(),
      [&] {
        std::vector<Published> all;
        read_publish_list(*files.read_stream(list), list.string(), [&](Published&& p) { all.push_back(std::move(p)); });
        return all;
      },
      [](const std::vector<Published>& all) {
        size_t bytes = all.capacity() * sizeof(Published);
        for (const auto& p : all) bytes += p.file.size() + p.path.size() + p.observation.size();
        return bytes;
      });
  for (const Published& p : *parsed) each(p);
}

// What the entries' order is found from: the stages in order and the digests of their publish lists
// (which hold every path); "" where a list has none.
std::string order_made_of(const std::vector<std::pair<std::string, Artifact>>& artifacts) {
  std::string made_of;
  for (const auto& [stage, artifact] : artifacts) {
    const std::optional<ListedFile> list = artifact.file("publish.json");
    if (!list || list->sha256.empty()) return "";
    made_of += json_string(stage) + " " + list->sha256.hex() + "\n";
  }
  return made_of;
}

// The entries sorted by path, then in the stages' order. A process that keeps memory (`olt watch`)
// remembers the order by what it is found from (`made_of`: order_made_of, where not "") and puts the
// entries of its next publish in it, checked in one walk: edit after edit the stages publish the
// same paths, and sorting them again was a third of making the entries (2,615 entries on the robot,
// 80,000 at 10,000 observations; docs/benchmarks.md, "A one-box cycle phase by phase, on a faster
// VM"). Elsewhere they are sorted in place (no order beside them).
void sort_entries(Entries& entries, const std::string& made_of, const fs::path& output) {
  if (made_of.empty()) {
    std::sort(entries.list.begin(), entries.list.end(),
              [&](const Entry& a, const Entry& b) { return entries.goes_before(a, b); });
    return;
  }
  const std::string name = "publish order " + output.string();
  if (const auto known = remembered_from<std::vector<uint32_t>>(name, made_of);
      known && known->size() == entries.list.size()) {
    put_in_order(entries, *known);
    if (sorted(entries)) return;
  }
  auto order = std::make_shared<std::vector<uint32_t>>(sorting_order(entries));
  put_in_order(entries, *order);
  remember_from<std::vector<uint32_t>>(name, made_of, order, sizeof(*order) + order->size() * sizeof(uint32_t));
}

// Every stage's publish list, sorted by output path (sort_entries); throws on a path leaving the
// output folder, a file the stage did not write, or two stages writing one path.
// An artifact without its file list is listed by `list_files` at its first entry; one that publishes
// nothing lets go of its list (the source's 30,000 files at 10,000 observations).
Entries entries_to_publish(const FileSystem& files, std::vector<std::pair<std::string, Artifact>>& artifacts,
                           const ListFiles& list_files, const fs::path& output) {
  Entries entries;
  const std::string order_made_of_lists = keeping_memory() ? order_made_of(artifacts) : "";  // before they go
  for (auto& stage_artifact : artifacts) {
    const std::string& stage = stage_artifact.first;  // named, not bound: a lambda takes it (C++17)
    Artifact& artifact = stage_artifact.second;
    entries.add_stage(stage, artifact);
    const size_t before = entries.list.size();
    bool listed = !artifact.files.empty() || !list_files;
    for_each_published(files, stage, artifact, [&](const Published& p) {
      if (!stays_inside(p.path))
        throw StageFailure(stage, "output path '" + p.path + "' would leave the output folder");
      if (!listed) artifact.files = list_files(stage, artifact), listed = true;
      const std::optional<size_t> file = artifact.files.place(p.file);
      if (!file) throw std::runtime_error("stage '" + stage + "' publishes " + p.file + ", which it did not write");
      entries.add(p, *file);
    });
    if (entries.list.size() == before) artifact.files = ArtifactFiles();  // publishes nothing: not needed
  }
  sort_entries(entries, order_made_of_lists, output);
  const auto& list = entries.list;
  for (std::size_t i = 1; i < list.size(); ++i)
    if (entries.path(list[i]) == entries.path(list[i - 1]))
      throw InputError("job", "stages '" + entries.stage(list[i - 1]) + "' and '" + entries.stage(list[i]) +
                                  "' both write " + entries.path(list[i]).str());
  return entries;
}

// Copies the entry's cache file to `to`, hashed on the way (its bytes read once): other bytes than
// recorded, or none (the file gone from the cache during the run), are a DamagedArtifact (the copy
// removed). Whether `to` is a clone of it (FileSystem::copy_hashed).
bool copy_verified(FileSystem& files, const Entries& entries, const Entry& e, const fs::path& to) {
  const fs::path from = entries.artifact(e).path(entries.file(e));
  const auto damaged = [&](const std::string& what) {
    return DamagedArtifact(entries.stage(e), entries.artifact(e).key, "its cache entry is damaged: " + what);
  };
  FileSystem::Copied copied;
  try {
    copied = files.copy_hashed(from, to);
  } catch (const FileSystemError&) {
    if (!files.stat(from).is_file()) throw damaged(from.string() + " is gone");
    throw;
  }
  if (copied.sha256 == entries.file(e).sha256) return copied.cloned;
  files.remove(to);
  throw damaged(from.string() + " does not hold the bytes recorded for it");
}

// Puts the entry's file at `to`: written from the bytes this run wrote under its digest, where the
// process kept them (run_memory.h) and `from_memory` (the output's files are not clones of the
// cache's: a clone shares the cache's blocks, where a write takes its own), else copied from the
// cache, verified. The bytes kept are those the cache file was written with, hashed then
// (ArtifactFolder): the output gets them even where the cache file was damaged since, which is then
// noticed by the next publish that copies the file from the cache (a later cycle's, where the file
// is not written again), `olt cache verify` or an `olt run`. Whether `to` is a clone.
bool put_file(FileSystem& files, const Entries& entries, const Entry& e, const fs::path& to, bool from_memory) {
  const ListedFile file = entries.file(e);
  if (from_memory)
    if (const auto bytes = kept_for_run<std::string>(file.sha256.hex()); bytes && bytes->size() == file.size) {
      files.write(to, *bytes);
      return false;
    }
  return copy_verified(files, entries, e, to);
}

// Nothing to publish: the output's manifest is, byte for byte, the one this run would write (their
// digests), and every file it lists is there with its size (what `changes` asks of a file before it
// keeps it; the folders on the way were checked before; `trust_listed`: taken to be so, in an output
// as this process left it).
bool unchanged(const FileSystem& files, const fs::path& output, const Entries& entries, const std::string& digest,
               const std::string& existing_digest, bool trust_listed) {
  if (digest != existing_digest) return false;
  if (trust_listed) return true;
  return parallel_all(entries.list.size(), [&](size_t i) {
    const FileStat st = files.stat(output / entries.path(entries.list[i]).str());
    return st.is_file() && st.size == entries.file(entries.list[i]).size;
  });
}

// A publish's changes to the output: the entries to put (indices into the entries) and the files
// the last manifest listed that this one does not (path, listed digest).
struct Changes {
  std::vector<uint32_t> put;  ///< 4 bytes a place: 80,000 entries at 10,000 observations
  Listed gone;
};

// What differs between the output and the entries: an entry is put unless the last manifest lists
// it with its digest and a file of its size is there (a listed file edited by hand to other bytes of
// the same size is left as it is, like any file the manifest does not describe). `trust_listed`: a
// file the manifest lists is taken to be there as listed, without a look (an output as this process
// left it).
Changes changes(const FileSystem& files, const fs::path& output, const Entries& entries,
                const PreviousManifest& previous, bool trust_listed) {
  const std::vector<uint32_t> listed = listed_places(entries, previous);
  std::vector<char> put(entries.list.size(), 0);
  parallel_for(entries.list.size(), [&](size_t i) {
    const Entry& e = entries.list[i];
    const ListedFile file = entries.file(e);
    if (trust_listed && listed[i] != kNotListed) {
      put[i] = !(previous.sha256(previous.files[listed[i]]) == file.sha256);
      return;
    }
    const fs::path path = output / entries.path(e).str();
    const FileStat st = files.stat(path);
    if (st.is_folder())
      throw InputError(path.string(),
                       "a folder is where OLT publishes a file (from stage '" + entries.stage(e) + "'); remove it");
    put[i] = !(listed[i] != kNotListed && previous.sha256(previous.files[listed[i]]) == file.sha256 && st.is_file() &&
               st.size == file.size);
  });
  Changes out;
  out.put.reserve(static_cast<size_t>(std::count(put.begin(), put.end(), 1)));  // not grown by doubling
  std::vector<char> kept(previous.files.size(), 0);                             // listed and still published
  for (size_t i = 0; i < entries.list.size(); ++i) {
    if (put[i]) out.put.push_back(static_cast<uint32_t>(i));
    if (listed[i] != kNotListed) kept[listed[i]] = 1;
  }
  for (size_t j = 0; j < previous.files.size(); ++j) {
    const std::string_view path = previous.path(previous.files[j]);
    if (j > 0 && path == previous.path(previous.files[j - 1])) kept[j] = kept[j - 1];  // listed twice
    if (!kept[j] && stays_inside(path)) out.gone.emplace_back(path, previous.sha256(previous.files[j]));
  }
  return out;
}

// Temporaries beside the output (.tmp.<output name>.<host>.<pid>.<n>, where earlier versions staged a whole
// output) and changes staged inside it (.tmp.olt-publish.<host>.<pid>.<n>) of runs that died before
// they published, or while they removed a finished publish's folder.
void remove_orphans(FileSystem& files, const fs::path& output) {
  const std::string prefix = ".tmp." + output.filename().string() + ".";
  for (const auto& name : files.list(output.parent_path()))
    if (name.rfind(prefix, 0) == 0 && orphaned_temp(name)) files.remove(output.parent_path() / name);
  for (const auto& name : files.list(output))
    if (orphaned_temp(name)) files.remove(output / name);
}

// The output folder itself: where a link points, for an output that is a link (to a bigger disk, say).
fs::path output_folder(const FileSystem& files, const fs::path& output) {
  return files.stat(output).type == FileStat::Type::link ? files.real_path(output) : output;
}

// The changes staged inside the output (the same file system, a mount point included) under a
// temporary name, made durable, then renamed to .olt-publish: a run that dies or meets a full disk
// before that leaves the output as it was. The listing of the new manifest is written beside the
// listing there and made durable with them before it replaces it (a listing cut short would pass
// for a shorter one), and so are the file systems of `along`: one sync for all (two where the
// files are clones: `along` first, see below).
void stage_changes(FileSystem& files, const fs::path& output, const Entries& entries, const Changes& todo,
                   const ManifestText& manifest, const fs::path& listing, const SyncAlong& along) {
  const fs::path staged = temp_sibling(output / "olt-publish");  // .tmp.olt-publish.<host>.<pid>.<n>
  const fs::path next_listing = listing.empty() ? fs::path() : temp_sibling(listing);
  try {
    files.make_folders(staged / "files");
    Progress progress("files published", todo.put.size());
    bool from_memory = false;  // set once the first file says the output's files are not clones
    const auto put = [&](size_t i) {
      const Entry& e = entries.list[todo.put[i]];
      const bool cloned = put_file(files, entries, e, staged / "files" / entries.path(e).str(), from_memory);
      fault_point("published_file");
      progress.advance();
      return cloned;
    };
    // The first file alone: where it is a clone (XFS, Btrfs) and others follow, the cache is synced
    // before they are cloned. XFS writes a clone's source to the disk before it clones it, a file at a
    // time, where one sync writes them all at once (without it, the cycles were 3-25 % slower on XFS).
    const bool clones = !todo.put.empty() && put(0);
    if (clones && todo.put.size() > 1 && !along.folders.empty()) {
      files.sync(along.folders);
      if (along.synced) along.synced();  // the run's entries are durable from here
    }
    from_memory = !clones;
    // The other files, beside the manifest, the journal and the listing (none needs another).
    std::vector<std::function<void()>> writes = {
        [&] { parallel_for(todo.put.size() - std::min<size_t>(todo.put.size(), 1), [&](size_t i) { put(i + 1); }); },
        [&] {
          write_pieces(files, staged / "manifest.json", [&](const PieceSink& sink) { manifest.pieces(entries, sink); });
        },
        [&] {
          write_pieces(files, staged / "journal.json", [&](const PieceSink& sink) {
            journal_pieces(
                todo.put.size(), [&](size_t i) { return entries.path(entries.list[todo.put[i]]).str(); }, todo.gone,
                sink);
          });
        }};
    if (!listing.empty())
      writes.emplace_back([&] {
        write_pieces(files, next_listing,
                     [&](const PieceSink& sink) { listing_pieces(manifest.digest, entries, sink); });
      });
    for (const std::exception_ptr& failure : run_side_by_side(writes))
      if (failure) std::rethrow_exception(failure);
    std::vector<fs::path> synced = along.folders;
    synced.push_back(staged);
    if (!listing.empty()) synced.push_back(next_listing);
    files.sync(synced);
    if (along.synced) along.synced();
    // The listing of the new manifest, before it is published: a run that stops before that leaves a
    // listing of a manifest that is not there, which is not read.
    if (!listing.empty() && !files.rename(next_listing, listing))
      throw FileSystemError(listing.string() + ": cannot replace: it is a folder");
    fault_point("manifest_next");
    if (!files.rename(staged, output / kPending))
      throw FileSystemError((output / kPending).string() + ": cannot publish: a folder is in the way");
  } catch (...) {
    files.remove(staged);
    if (!next_listing.empty()) files.remove(next_listing);
    throw;
  }
}

// What stage_publish did: whether it staged changes, and the digest of the manifest the output
// holds once they are made.
struct Staged {
  bool changes = false;
  bool as_left = false;  ///< the output was as this process left it
  std::string digest;
  FileStat manifest;              ///< the manifest of that digest: the one in place, or the one staged
  std::vector<fs::path> folders;  ///< the output's, and every folder it publishes into or through
};

// Everything up to the moment a publish happens: the changes to `output` staged and renamed to
// OUTPUT/.olt-publish, if there are any. Its entries (80,000 at 10,000 observations) are gone
// before the changes are made.
Staged stage_publish(const fs::path& output, std::vector<std::pair<std::string, Artifact>>& artifacts,
                     FileSystem& files, const fs::path& listing, const ListFiles& list, const SyncAlong& along) {
  const Entries entries = entries_to_publish(files, artifacts, list, output);
  std::set<fs::path> real_folders;
  std::set<std::string> folders = {""};  // in the output: itself, and what the entries publish into
  std::string checked;                   // the folder of the last entry checked (entries of one folder come together)
  std::string scratch;                   // a path assembled
  for (const Entry& e : entries.list) {
    const std::string_view path = entries.path(e).in(scratch);
    const std::string_view folder = folder_of(path);
    if (folder == checked) continue;
    for (size_t at = 0; at != std::string_view::npos && at < folder.size(); at = folder.find('/', at + 1))
      if (at > 0) folders.emplace(folder.substr(0, at));
    folders.emplace(folder);
    if (!through_real_folders(files, output, std::string(path), &real_folders))
      throw InputError((output / path).string(),
                       "a symbolic link or a file is on the way inside the output folder: OLT writes only into "
                       "folders of its own there; remove it");
    checked = folder;
  }
  std::vector<fs::path> watched;
  for (const std::string& folder : folders) watched.push_back(output / folder);
  finish_publishing(output, files);
  const ManifestText manifest = manifest_text(entries);
  const std::string& digest = manifest.digest;
  const FileStat in_place = files.stat(output / "manifest.json");  // before it is read: what is hashed is no older
  const bool left = as_left(files, output, in_place);
  const std::string existing = existing_manifest_digest(files, output / "manifest.json", in_place);
  if (unchanged(files, output, entries, digest, existing, left))
    return {false, left, digest, in_place, std::move(watched)};
  const Changes todo = [&] {  // what the output held is not kept past this
    if (const std::optional<PreviousManifest> listed = read_listing(files, listing, existing))
      return changes(files, output, entries, *listed, left);
    return changes(files, output, entries, previous_manifest(files, output / "manifest.json"), left);
  }();
  stage_changes(files, output, entries, todo, manifest, listing, along);
  // Moved into place by a rename, the staged manifest keeps its inode, size and time.
  return {true, left, digest, files.stat(output / kPending / "manifest.json"), std::move(watched)};
}

}  // namespace

fs::path output_listing(const fs::path& cache, const fs::path& output) {
  return cache / "outputs" / (sha256_hex(fs::absolute(output).lexically_normal().string()).substr(0, 32) + ".listing");
}

void finish_publishing(const fs::path& output_path, FileSystem& files) {
  const fs::path output = output_folder(files, output_path);
  if (!files.stat(output).is_folder()) return;
  remove_orphans(files, output);
  if (files.stat(output / kPending).is_folder()) apply_pending(files, output);
}

void publish_outputs(const fs::path& output_path, std::vector<std::pair<std::string, Artifact>> artifacts,
                     FileSystem& files, const fs::path& listing, const ListFiles& list, const SyncAlong& along) {
  const fs::path output = output_folder(files, output_path);
  const Staged staged = stage_publish(output, artifacts, files, listing, list, along);
  std::vector<std::pair<std::string, Artifact>>().swap(artifacts);
  if (staged.changes) {
    fault_point("publish_committed");
    apply_pending(files, output, Pending::staged_now);
  }
  remember_manifest_digest(files, output / "manifest.json", staged.digest, staged.manifest);
  // Nothing published: the watch begun after the last publish goes on (what changed meanwhile, even
  // while this one looked, is seen by the next).
  if (!(staged.as_left && !staged.changes))
    remember_as_left(files, output, staged.folders, staged.manifest, staged.as_left);
}

}  // namespace olt
