#include "olt/runtime/publish.h"

#include <map>

#include "olt/core/error.h"
#include "olt/core/fault.h"
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
bool through_real_folders(const FileSystem& files, const fs::path& output, const std::string& path) {
  fs::path at = output;
  const fs::path relative(path);
  for (auto it = relative.begin(); it != relative.end() && std::next(it) != relative.end(); ++it) {
    at /= *it;
    const FileStat st = files.stat(at);
    if (!st.exists()) return true;
    if (!st.is_folder()) return false;
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

// Copies the entry to `target` through a temporary sibling, unless the manifest already lists it
// with its digest and a file of its size is there.
void publish_file(FileSystem& files, const Entry& e, const fs::path& target,
                  const std::map<std::string, std::string>& previous, const std::string& path) {
  auto old = previous.find(path);
  if (old != previous.end() && old->second == e.file->sha256) {
    const FileStat st = files.stat(target);
    if (st.is_file() && st.size == e.file->size) return;
  }
  const fs::path temp = temp_sibling(target);
  files.copy(e.artifact->dir / e.published.file, temp);
  if (files.sha256(temp) != e.file->sha256) {
    files.remove(temp);
    throw DamagedArtifact(e.stage, e.artifact->key,
                          "its cache entry is damaged: " + (e.artifact->dir / e.published.file).string() +
                              " does not hold the bytes recorded for it");
  }
  if (!files.rename(temp, target)) {
    files.remove(temp);
    throw FileSystemError(target.string() + ": cannot publish: a folder is in the way");
  }
  fault_point("published_file");
}

nlohmann::json manifest_entry(const std::string& path, const Entry& e) {
  nlohmann::json j = {{"path", path}, {"sha256", e.file->sha256}, {"kind", e.published.kind}, {"stage", e.stage}};
  if (!e.published.sensor.empty()) j["sensor"] = e.published.sensor;
  if (!e.published.observation.empty())
    j["observation"] = {{"id", e.published.observation}, {"timestamp", e.published.timestamp}};
  return j;
}

}  // namespace

nlohmann::json publish_outputs(const fs::path& output, const std::vector<std::pair<std::string, Artifact>>& artifacts,
                               FileSystem& files) {
  const std::map<std::string, Entry> entries = entries_to_publish(files, artifacts);
  // A run killed while publishing leaves temporary files: gone before this one publishes.
  remove_orphaned_temps(files, output);
  const fs::path manifest_file = output / "manifest.json";
  const std::map<std::string, std::string> previous = previous_manifest(files, manifest_file);
  nlohmann::json listed = nlohmann::json::array();
  for (const auto& [path, e] : entries)
    if (!through_real_folders(files, output, path))
      throw InputError((output / path).string(),
                       "a symbolic link or a file is on the way inside the output folder: OLT writes only into "
                       "folders of its own there; remove it");
  for (const auto& [path, e] : entries) {
    publish_file(files, e, output / path, previous, path);
    listed.push_back(manifest_entry(path, e));
  }
  // Files the last manifest listed and this one does not: removed where they hold the bytes it listed.
  for (const auto& [path, sha] : previous) {
    if (entries.count(path) || !safe_relative(path) || !through_real_folders(files, output, path)) continue;
    const fs::path stale = output / path;
    if (files.stat(stale).is_file() && files.sha256(stale) == sha) files.remove(stale);
  }
  const nlohmann::json manifest = {{"files", listed}};
  if (files.stat(output).exists()) files.sync(output);  // the files on disk before the manifest that lists them
  fault_point("manifest_next");
  files.write_atomic(manifest_file, manifest.dump(1) + "\n");
  return manifest;
}

}  // namespace olt
