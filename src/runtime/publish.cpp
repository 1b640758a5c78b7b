#include "olt/runtime/publish.h"

#include <map>
#include <set>

#include "olt/core/error.h"
#include "olt/core/fault.h"
#include "olt/core/progress.h"
#include "olt/runtime/runner.h"
#include "olt/stages/stage.h"

namespace olt {
namespace {

bool safe_relative(const std::string& path) {
  const fs::path p(path);
  if (p.empty() || p.is_absolute()) return false;
  for (const auto& part : p)
    if (part == ".." || part == ".") return false;
  return true;
}

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

// Every stage's publish list, by output path; throws on a path leaving the output folder, a file the
// stage did not write, or two stages writing one path.
std::map<std::string, Entry> entries_to_publish(const FileSystem& files,
                                                const std::vector<std::pair<std::string, Artifact>>& artifacts) {
  std::map<std::string, Entry> entries;
  for (const auto& [stage, artifact] : artifacts) {
    const auto list = nlohmann::json::parse(files.read(artifact.dir / "publish.json"));
    for (const auto& j : list) {
      const Published p = published_from_json(j);
      if (!safe_relative(p.path))
        throw StageFailure(stage, "output path '" + p.path + "' would leave the output folder");
      const ArtifactFile* file = artifact.file(p.file);
      if (!file) throw std::runtime_error("stage '" + stage + "' publishes " + p.file + ", which it did not write");
      auto [it, inserted] = entries.emplace(p.path, Entry{p, stage, &artifact, file});
      if (!inserted)
        throw InputError("job", "stages '" + it->second.stage + "' and '" + stage + "' both write " + p.path);
    }
  }
  return entries;
}

// What the output's manifest lists (path -> sha256); empty without a readable one.
std::map<std::string, std::string> previous_manifest(const FileSystem& files, const fs::path& manifest_file) {
  std::map<std::string, std::string> previous;
  if (!files.stat(manifest_file, true).is_file()) return previous;
  const auto old = nlohmann::json::parse(files.read(manifest_file), nullptr, false);
  if (old.is_object() && old.contains("files") && old["files"].is_array())
    for (const auto& f : old["files"])
      if (f.is_object() && f.contains("path") && f.contains("sha256") && f["path"].is_string() &&
          f["sha256"].is_string())
        previous[f["path"]] = f["sha256"];
  return previous;
}

// Copies the entry's cache file to `to`, hashed on the way: other bytes than recorded are a
// DamagedArtifact (the copy removed).
void copy_verified(FileSystem& files, const Entry& e, const fs::path& to) {
  files.copy(e.artifact->dir / e.published.file, to);
  if (files.sha256(to) == e.file->sha256) return;
  files.remove(to);
  throw DamagedArtifact(e.stage, e.artifact->key,
                        "its cache entry is damaged: " + (e.artifact->dir / e.published.file).string() +
                            " does not hold the bytes recorded for it");
}

// Puts the entry at `staged` / path: a hard link to the output's file where the last manifest lists
// it with its digest and a file of its size is there, else a copy from the cache, hashed on the way.
void stage_file(FileSystem& files, const Entry& e, const fs::path& output, const fs::path& staged,
                const std::map<std::string, std::string>& previous, const std::string& path) {
  auto old = previous.find(path);
  if (old != previous.end() && old->second == e.file->sha256 && through_real_folders(files, output, path)) {
    const FileStat st = files.stat(output / path);
    if (st.is_file() && st.size == e.file->size) return files.link(output / path, staged / path);
  }
  copy_verified(files, e, staged / path);
  fault_point("published_file");
}

// Files of the output that stay: those no manifest listed (someone's own), and those the last one
// listed that no longer hold the listed bytes (edited by hand). Temporaries of killed runs do not.
std::vector<std::string> files_to_keep(const FileSystem& files, const fs::path& output,
                                       const std::map<std::string, Entry>& entries,
                                       const std::map<std::string, std::string>& previous) {
  std::vector<std::string> keep;
  for (const auto& path : files.files_below(output)) {
    if (path == "manifest.json" || entries.count(path)) continue;
    bool temporary = false;
    for (const auto& part : fs::path(path)) temporary = temporary || part.string().rfind(".tmp.", 0) == 0;
    if (temporary) continue;
    auto listed = previous.find(path);
    if (listed == previous.end() || files.sha256(output / path) != listed->second) keep.push_back(path);
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
void publish_in_place(FileSystem& files, const std::map<std::string, Entry>& entries, const fs::path& output,
                      const std::map<std::string, std::string>& previous, const nlohmann::json& manifest) {
  remove_orphaned_temps(files, output);
  for (const auto& [path, e] : entries) {
    auto old = previous.find(path);
    const FileStat st = files.stat(output / path);
    if (old != previous.end() && old->second == e.file->sha256 && st.is_file() && st.size == e.file->size) continue;
    const fs::path temp = temp_sibling(output / path);
    copy_verified(files, e, temp);
    if (!files.rename(temp, output / path)) {
      files.remove(temp);
      throw FileSystemError((output / path).string() + ": cannot publish: a folder is in the way");
    }
    fault_point("published_file");
  }
  for (const auto& [path, sha] : previous) {
    if (entries.count(path) || !safe_relative(path) || !through_real_folders(files, output, path)) continue;
    if (files.stat(output / path).is_file() && files.sha256(output / path) == sha) files.remove(output / path);
  }
  files.sync(output);
  fault_point("manifest_next");
  files.write_atomic(output / "manifest.json", manifest.dump(1) + "\n");
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
bool unchanged(const FileSystem& files, const fs::path& output, const std::map<std::string, Entry>& entries,
               const nlohmann::json& manifest) {
  const fs::path manifest_file = output / "manifest.json";
  if (!files.stat(manifest_file).is_file()) return false;
  std::string written;
  try {
    written = files.read(manifest_file);
  } catch (const std::exception&) {
    return false;
  }
  if (written != manifest.dump(1) + "\n") return false;
  for (const auto& [path, e] : entries) {
    const FileStat st = files.stat(output / path);
    if (!st.is_file() || st.size != e.file->size) return false;
  }
  return true;
}

nlohmann::json manifest_entry(const std::string& path, const Entry& e) {
  nlohmann::json j = {{"path", path}, {"sha256", e.file->sha256}, {"kind", e.published.kind}, {"stage", e.stage}};
  if (!e.published.sensor.empty()) j["sensor"] = e.published.sensor;
  if (!e.published.observation.empty())
    j["observation"] = {{"id", e.published.observation}, {"timestamp", e.published.timestamp}};
  return j;
}

}  // namespace

nlohmann::json publish_outputs(const fs::path& output_path,
                               const std::vector<std::pair<std::string, Artifact>>& artifacts, FileSystem& files) {
  const std::map<std::string, Entry> entries = entries_to_publish(files, artifacts);
  // An output that is a link (to a bigger disk, say) is published where it points.
  const fs::path output =
      files.stat(output_path).type == FileStat::Type::link ? files.real_path(output_path) : output_path;
  std::set<fs::path> real_folders;
  for (const auto& [path, e] : entries)
    if (!through_real_folders(files, output, path, &real_folders))
      throw InputError((output / path).string(),
                       "a symbolic link or a file is on the way inside the output folder: OLT writes only into "
                       "folders of its own there; remove it");
  remove_orphaned_siblings(files, output);
  nlohmann::json listed = nlohmann::json::array();
  for (const auto& [path, e] : entries) listed.push_back(manifest_entry(path, e));
  const nlohmann::json manifest = {{"files", listed}};
  if (unchanged(files, output, entries, manifest)) return manifest;
  const std::map<std::string, std::string> previous = previous_manifest(files, output / "manifest.json");
  if (files.stat(output).exists() && !files.can_swap(output)) {
    publish_in_place(files, entries, output, previous, manifest);
    return manifest;
  }
  // The new output is built beside the old one and switched with it in one step: a run that dies or
  // meets a full disk before the switch leaves the old output whole, after it the new one.
  const fs::path staged = temp_sibling(output);
  try {
    files.make_folders(staged);
    Progress progress("files published", entries.size());
    for (const auto& [path, e] : entries) {
      stage_file(files, e, output, staged, previous, path);
      progress.advance();
    }
    for (const auto& path : files_to_keep(files, output, entries, previous)) files.link(output / path, staged / path);
    files.write(staged / "manifest.json", manifest.dump(1) + "\n");
    files.sync(staged);  // every file on disk before the switch that shows them
    fault_point("manifest_next");
    switch_to(files, staged, output);
    return manifest;
  } catch (...) {
    files.remove(staged);
    throw;
  }
}

}  // namespace olt
