#include "olt/runtime/publish.h"

#include <algorithm>
#include <set>

#include "olt/core/error.h"
#include "olt/core/fault.h"
#include "olt/core/hash.h"
#include "olt/core/json_text.h"
#include "olt/core/parallel.h"
#include "olt/core/progress.h"
#include "olt/runtime/runner.h"
#include "olt/stages/stage.h"

namespace olt {
namespace {

// Whether `path` (relative, safe) reaches into `output` through real folders only: no component
// before the last is a symbolic link or a file. Missing folders are fine (publishing creates them).
// `known` (optional) remembers the folders found real, so many files of one folder cost one stat.
bool through_real_folders(const FileSystem& files, const fs::path& output, const std::string& path,
                          std::set<fs::path>* known = nullptr) {
  fs::path at = output;
  const fs::path relative(path);
  for (auto it = relative.begin(); it != relative.end() && std::next(it) != relative.end(); ++it) {
    at /= *it;
    if (known && known->count(at)) continue;
    const FileStat st = files.stat(at);
    if (!st.exists()) return true;
    if (!st.is_folder()) return false;
    if (known) known->insert(at);
  }
  return true;
}

// A file to publish: what the manifest says of it, the stage and the artifact file it comes from.
struct Entry {
  Published published;
  std::string stage;
  const Artifact* artifact;
  const ArtifactFile* file;
};

// The entries sorted by output path (a 10,000-observation job publishes ~80,000: a vector, not a
// map, and lists parsed an element at a time, keep this within a few tens of MB).
using Entries = std::vector<Entry>;

const Entry* find_entry(const Entries& entries, const std::string& path) {
  auto it = std::lower_bound(entries.begin(), entries.end(), path,
                             [](const Entry& e, const std::string& p) { return e.published.path < p; });
  return it != entries.end() && it->published.path == path ? &*it : nullptr;
}

// Every stage's publish list, sorted by output path; throws on a path leaving the output folder, a
// file the stage did not write, or two stages writing one path.
Entries entries_to_publish(const FileSystem& files, const std::vector<std::pair<std::string, Artifact>>& artifacts) {
  Entries entries;
  for (const auto& [stage, artifact] : artifacts)
    for_each_at(files.read(artifact.dir / "publish.json"), 1, [&](const nlohmann::json& j) {
      Published p = published_from_json(j);
      if (!stays_inside(p.path))
        throw StageFailure(stage, "output path '" + p.path + "' would leave the output folder");
      const ArtifactFile* file = artifact.file(p.file);
      if (!file) throw std::runtime_error("stage '" + stage + "' publishes " + p.file + ", which it did not write");
      entries.push_back(Entry{std::move(p), stage, &artifact, file});
    });
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Entry& a, const Entry& b) { return a.published.path < b.published.path; });
  for (std::size_t i = 1; i < entries.size(); ++i)
    if (entries[i].published.path == entries[i - 1].published.path)
      throw InputError("job", "stages '" + entries[i - 1].stage + "' and '" + entries[i].stage + "' both write " +
                                  entries[i].published.path);
  return entries;
}

// What the output's manifest lists (path -> sha256), sorted by path; empty without a readable one.
using Listed = std::vector<std::pair<std::string, std::string>>;

const std::string* find_listed(const Listed& listed, const std::string& path) {
  auto it = std::lower_bound(listed.begin(), listed.end(), path,
                             [](const auto& entry, const std::string& p) { return entry.first < p; });
  return it != listed.end() && it->first == path ? &it->second : nullptr;
}

Listed previous_manifest(const FileSystem& files, const fs::path& manifest_file) {
  Listed previous;
  if (!files.stat(manifest_file, true).is_file()) return previous;
  try {
    for_each_at(files.read(manifest_file), 2, [&](const nlohmann::json& f) {
      if (f.is_object() && f.contains("path") && f.contains("sha256") && f["path"].is_string() &&
          f["sha256"].is_string())
        previous.emplace_back(f["path"], f["sha256"]);
    });
  } catch (const nlohmann::json::exception&) {
    return {};  // not a manifest OLT can read: nothing in the output is taken for ours
  }
  std::sort(previous.begin(), previous.end());
  return previous;
}

// Copies the entry's cache file to `to`, hashed on the way: other bytes than recorded are a
// DamagedArtifact (the copy removed).
void copy_verified(FileSystem& files, const Entry& e, const fs::path& to) {
  files.copy(e.artifact->path(e.published.file), to);
  if (files.sha256(to) == e.file->sha256) return;
  files.remove(to);
  throw DamagedArtifact(e.stage, e.artifact->key,
                        "its cache entry is damaged: " + e.artifact->path(e.published.file).string() +
                            " does not hold the bytes recorded for it");
}

// Puts the entry at `staged` / path: a hard link to the output's file where the last manifest lists
// it with its digest and a file of its size is there, else a copy from the cache, hashed on the way.
// (Every entry's path was found to go through real folders of the output before.)
void stage_file(FileSystem& files, const Entry& e, const fs::path& output, const fs::path& staged,
                const Listed& previous) {
  const std::string& path = e.published.path;
  const std::string* old = find_listed(previous, path);
  if (old && *old == e.file->sha256) {
    const FileStat st = files.stat(output / path);
    if (st.is_file() && st.size == e.file->size) return files.link(output / path, staged / path);
  }
  copy_verified(files, e, staged / path);
  fault_point("published_file");
}

// Files of the output that stay: those no manifest listed (someone's own), and those the last one
// listed that no longer hold the listed bytes (edited by hand). Temporaries of killed runs do not.
std::vector<std::string> files_to_keep(const FileSystem& files, const fs::path& output, const Entries& entries,
                                       const Listed& previous) {
  std::vector<std::string> keep;
  for (const auto& path : files.files_below(output)) {
    if (path == "manifest.json" || find_entry(entries, path)) continue;
    bool temporary = false;
    for (const auto& part : fs::path(path)) temporary = temporary || part.string().rfind(".tmp.", 0) == 0;
    if (temporary) continue;
    const std::string* listed = find_listed(previous, path);
    if (!listed || files.sha256(output / path) != *listed) keep.push_back(path);
  }
  return keep;
}

// The staged folder becomes the output in one step (the old one left at `staged`, then removed).
void switch_to(FileSystem& files, const fs::path& staged, const fs::path& output) {
  if (!files.stat(output).exists()) {
    if (!files.rename(staged, output)) throw FileSystemError(output.string() + ": cannot publish here");
    return;
  }
  if (!files.exchange(staged, output)) {
    // No atomic exchange on this file system (some network file systems): for a moment there is no
    // output; a run killed then publishes the whole output anew, from the cache.
    const fs::path old = temp_sibling(output);
    if (!files.rename(output, old) || !files.rename(staged, output))
      throw FileSystemError(output.string() + ": cannot replace the output folder");
    files.remove(old);
    return;
  }
  fault_point("output_switched");
  files.remove(staged);  // the old output
}

// Where the output cannot be replaced whole (a mount point, a parent folder not ours to write): each
// changed file through a temporary sibling inside the output and a rename, stale files removed, the
// manifest last. A run that dies midway leaves new files under the old manifest; the next run
// corrects them.
void publish_in_place(FileSystem& files, const Entries& entries, const fs::path& output, const Listed& previous,
                      const std::string& manifest) {
  remove_orphaned_temps(files, output);
  for (const Entry& e : entries) {
    const std::string& path = e.published.path;
    const std::string* old = find_listed(previous, path);
    const FileStat st = files.stat(output / path);
    if (old && *old == e.file->sha256 && st.is_file() && st.size == e.file->size) continue;
    const fs::path temp = temp_sibling(output / path);
    copy_verified(files, e, temp);
    if (!files.rename(temp, output / path)) {
      files.remove(temp);
      throw FileSystemError((output / path).string() + ": cannot publish: a folder is in the way");
    }
    fault_point("published_file");
  }
  for (const auto& [path, sha] : previous) {
    if (find_entry(entries, path) || !stays_inside(path) || !through_real_folders(files, output, path)) continue;
    if (files.stat(output / path).is_file() && files.sha256(output / path) == sha) files.remove(output / path);
  }
  files.sync(output);
  fault_point("manifest_next");
  files.write_atomic(output / "manifest.json", manifest);
}

// Temporaries beside the output (.tmp.<output name>.<pid>.<n>) of runs that died while publishing.
void remove_orphaned_siblings(FileSystem& files, const fs::path& output) {
  const std::string prefix = ".tmp." + output.filename().string() + ".";
  for (const auto& name : files.list(output.parent_path()))
    if (name.rfind(prefix, 0) == 0 && orphaned_temp(name)) files.remove(output.parent_path() / name);
}

// Nothing to publish: the output's manifest is, byte for byte, the one this run would write, and
// every file it lists is there with its size (what stage_file asks of a file before it keeps it;
// the folders on the way were checked before).
bool unchanged(const FileSystem& files, const fs::path& output, const Entries& entries, const std::string& manifest) {
  const fs::path manifest_file = output / "manifest.json";
  const FileStat manifest_stat = files.stat(manifest_file);
  if (!manifest_stat.is_file() || manifest_stat.size != manifest.size()) return false;
  try {
    if (files.sha256(manifest_file) != sha256_hex(manifest)) return false;  // not read whole: 31 MB at 80,000 files
  } catch (const std::exception&) {
    return false;
  }
  for (const Entry& e : entries) {
    const FileStat st = files.stat(output / e.published.path);
    if (!st.is_file() || st.size != e.file->size) return false;
  }
  return true;
}

// The manifest's text, as nlohmann::json's dump(1) of {"files": [...]} writes it, built an entry at a
// time (the whole document as a JSON value would take ~1 KB per file).
std::string manifest_text(const Entries& entries) {
  std::string text = "{\n \"files\": ";
  append_array(
      text, entries.size(),
      [&](size_t i) {
        const Entry& e = entries[i];
        nlohmann::json j = {
            {"path", e.published.path}, {"sha256", e.file->sha256}, {"kind", e.published.kind}, {"stage", e.stage}};
        if (!e.published.sensor.empty()) j["sensor"] = e.published.sensor;
        if (!e.published.observation.empty())
          j["observation"] = {{"id", e.published.observation}, {"timestamp", e.published.timestamp}};
        return j;
      },
      1);
  text += "\n}\n";
  return text;
}

}  // namespace

void publish_outputs(const fs::path& output_path, const std::vector<std::pair<std::string, Artifact>>& artifacts,
                     FileSystem& files) {
  const Entries entries = entries_to_publish(files, artifacts);
  // An output that is a link (to a bigger disk, say) is published where it points.
  const fs::path output =
      files.stat(output_path).type == FileStat::Type::link ? files.real_path(output_path) : output_path;
  std::set<fs::path> real_folders;
  for (const Entry& e : entries)
    if (!through_real_folders(files, output, e.published.path, &real_folders))
      throw InputError((output / e.published.path).string(),
                       "a symbolic link or a file is on the way inside the output folder: OLT writes only into "
                       "folders of its own there; remove it");
  remove_orphaned_siblings(files, output);
  const std::string manifest = manifest_text(entries);
  if (unchanged(files, output, entries, manifest)) return;
  const Listed previous = previous_manifest(files, output / "manifest.json");
  if (files.stat(output).exists() && !files.can_swap(output))
    return publish_in_place(files, entries, output, previous, manifest);
  // The new output is built beside the old one and switched with it in one step: a run that dies or
  // meets a full disk before the switch leaves the old output whole, after it the new one.
  const fs::path staged = temp_sibling(output);
  try {
    files.make_folders(staged);
    Progress progress("files published", entries.size());
    // In parallel: most of a relabel's files are new, and creating them is the kernel's work.
    parallel_for(entries.size(), [&](size_t i) {
      stage_file(files, entries[i], output, staged, previous);
      progress.advance();
    });
    for (const auto& path : files_to_keep(files, output, entries, previous)) files.link(output / path, staged / path);
    files.write(staged / "manifest.json", manifest);
    files.sync(staged);  // every file on disk before the switch that shows them
    fault_point("manifest_next");
    switch_to(files, staged, output);
  } catch (...) {
    files.remove(staged);
    throw;
  }
}

}  // namespace olt
