// `olt cache verify` and `olt cache gc`: the store checked against its own digests, and pruned to
// what some job still references.
#include <chrono>
#include <map>

#include "meta.h"
#include "olt/cache/store.h"
#include "olt/core/error.h"
#include "olt/core/hash.h"

namespace olt {
namespace {

// Every folder under objects/<k0k1>/, by name.
std::map<std::string, fs::path> object_folders(const FileSystem& files, const fs::path& root) {
  std::map<std::string, fs::path> folders;
  if (!files.stat(root / "objects").is_folder()) return folders;  // missing, or a link: left alone
  for (const auto& prefix : files.list(root / "objects")) {
    if (!files.stat(root / "objects" / prefix).is_folder()) continue;
    for (const auto& name : files.list(root / "objects" / prefix))
      if (files.stat(root / "objects" / prefix / name).is_folder()) folders[name] = root / "objects" / prefix / name;
  }
  return folders;
}

uint64_t folder_bytes(const FileSystem& files, const fs::path& dir) {
  uint64_t bytes = 0;
  for (const auto& path : files.files_below(dir)) bytes += files.stat(dir / path).size;
  return bytes;
}

// Problems of one artifact folder ("" when it is whole).
std::string check_artifact(const FileSystem& files, const std::string& key, const fs::path& dir,
                           const fs::path& objects, Store::Verification& v) {
  if (!files.stat(dir / kMetaFile).exists()) return "no " + std::string(kMetaFile);
  const auto meta = nlohmann::json::parse(files.read(dir / kMetaFile), nullptr, false);
  if (!meta.is_object() || !meta.contains("files") || !meta["files"].is_array())
    return "unreadable " + std::string(kMetaFile);
  if (meta.value("key", "") != key) return "its " + std::string(kMetaFile) + " names another key";
  ArtifactFiles listed_files;
  std::map<std::string, bool> listed;
  for (const auto& f : meta["files"]) {
    if (!f.is_object() || !f.contains("path") || !f.contains("sha256") || !f.contains("size"))
      return "malformed file entry in " + std::string(kMetaFile);
    const std::string path = f["path"], in = f.value("in", ""), as = f.value("as", "");
    listed[path] = true;
    if (!in.empty() && !safe_reference(in, as)) return "file " + path + " refers outside the cache";
    const fs::path at = in.empty() ? dir / path : artifact_dir(objects, in) / as;
    const FileStat st = files.stat(at);
    if (!st.is_file()) return "file " + path + (in.empty() ? "" : " (" + as + " of " + in + ")") + " is missing";
    if (st.size != f["size"].get<uint64_t>()) return "file " + path + ": size differs";
    const std::optional<Digest> sha256 = Digest::from_hex(f["sha256"].get<std::string>());
    if (!sha256) return "file " + path + ": its sha256 is not a digest";
    if (*sha256 != files.sha256(at)) return "file " + path + ": sha256 differs";
    listed_files.add(path, *sha256, f["size"].get<uint64_t>(), in, as);
    ++v.files;
    v.bytes += f["size"].get<uint64_t>();
  }
  for (const auto& path : files.files_below(dir))
    if (path != kMetaFile && !listed.count(path)) return "file " + path + " is not listed";
  listed_files.sort();
  if (digest_of(listed_files) != meta.value("digest", "")) return "digest differs";
  return "";
}

}  // namespace

Store::Verification Store::verify() const {
  Verification v;
  for (const auto& [key, dir] : object_folders(files_, root_)) {
    ++v.artifacts;
    std::string problem;
    try {
      problem = check_artifact(files_, key, dir, root_ / "objects", v);
    } catch (const std::exception& e) {
      problem = e.what();
    }
    if (!problem.empty()) v.problems.push_back({key, dir, problem});
  }
  return v;
}

Store::Collection Store::collect_garbage(const std::set<std::string>& roots, double min_tmp_age_s) const {
  if (!marked())
    throw InputError(root_.string(),
                     "not an OLT cache (no olt-cache.json, which every run writes): gc removes "
                     "nothing from it");
  const auto folders = object_folders(files_, root_);
  std::set<std::string> reachable;
  std::vector<std::string> todo(roots.begin(), roots.end());
  while (!todo.empty()) {
    const std::string key = todo.back();
    todo.pop_back();
    if (!folders.count(key) || !reachable.insert(key).second) continue;
    const auto meta = nlohmann::json::parse(files_.read(folders.at(key) / kMetaFile), nullptr, false);
    if (meta.is_object() && meta.contains("references") && meta["references"].is_array())
      for (const auto& r : meta["references"])
        if (r.is_string()) todo.push_back(r);
  }
  Collection c;
  for (const auto& [key, dir] : folders) {
    if (reachable.count(key)) {
      ++c.kept;
      continue;
    }
    c.bytes_freed += folder_bytes(files_, dir);
    remove_object(dir, key);
    ++c.removed;
  }
  const int64_t now_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
  for (const auto& name : files_.list(root_ / "tmp")) {
    if (name.rfind(".tmp.", 0) != 0) continue;  // not OLT's
    const fs::path temp = root_ / "tmp" / name;
    if (static_cast<double>(now_ns - files_.stat(temp).mtime_ns) * 1e-9 < min_tmp_age_s) continue;
    c.bytes_freed += folder_bytes(files_, temp);
    files_.remove(temp);
    ++c.temporaries;
  }
  return c;
}

}  // namespace olt
