// `olt cache verify` and `olt cache gc`: the store checked against its own digests, and pruned to
// what some job still references.
#include <chrono>
#include <map>

#include "meta.h"
#include "olt/cache/store.h"
#include "olt/core/hash.h"

namespace olt {
namespace {

// Every folder under objects/<k0k1>/, by name.
std::map<std::string, fs::path> object_folders(const fs::path& root) {
  std::map<std::string, fs::path> folders;
  std::error_code ec;
  for (const auto& prefix : fs::directory_iterator(root / "objects", ec))
    for (const auto& entry : fs::directory_iterator(prefix.path(), ec))
      if (entry.is_directory()) folders[entry.path().filename().string()] = entry.path();
  return folders;
}

uint64_t folder_bytes(const fs::path& dir) {
  uint64_t bytes = 0;
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(dir, ec))
    if (e.is_regular_file(ec)) bytes += e.file_size(ec);
  return bytes;
}

// Problems of one artifact folder ("" when it is whole).
std::string check_artifact(const std::string& key, const fs::path& dir, Store::Verification& v) {
  std::error_code ec;
  if (!fs::exists(dir / kMetaFile, ec)) return "no " + std::string(kMetaFile);
  const auto meta = nlohmann::json::parse(read_file(dir / kMetaFile), nullptr, false);
  if (!meta.is_object() || !meta.contains("files") || !meta["files"].is_array())
    return "unreadable " + std::string(kMetaFile);
  if (meta.value("key", "") != key) return "its " + std::string(kMetaFile) + " names another key";
  std::vector<ArtifactFile> files;
  std::map<std::string, bool> listed;
  for (const auto& f : meta["files"]) {
    if (!f.is_object() || !f.contains("path") || !f.contains("sha256") || !f.contains("size"))
      return "malformed file entry in " + std::string(kMetaFile);
    const std::string path = f["path"];
    listed[path] = true;
    const fs::path file = dir / path;
    if (!fs::is_regular_file(file, ec)) return "file " + path + " is missing";
    if (fs::file_size(file, ec) != f["size"].get<uint64_t>()) return "file " + path + ": size differs";
    if (sha256_file(file) != f["sha256"].get<std::string>()) return "file " + path + ": sha256 differs";
    files.push_back({path, f["sha256"], f["size"]});
    ++v.files;
    v.bytes += f["size"].get<uint64_t>();
  }
  for (const auto& e : fs::recursive_directory_iterator(dir, ec)) {
    if (!e.is_regular_file(ec)) continue;
    const std::string path = fs::relative(e.path(), dir).generic_string();
    if (path != kMetaFile && !listed.count(path)) return "file " + path + " is not listed";
  }
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.path < b.path; });
  if (digest_of(files) != meta.value("digest", "")) return "digest differs";
  return "";
}

}  // namespace

Store::Verification Store::verify() const {
  Verification v;
  for (const auto& [key, dir] : object_folders(root_)) {
    ++v.artifacts;
    std::string problem;
    try {
      problem = check_artifact(key, dir, v);
    } catch (const std::exception& e) {
      problem = e.what();
    }
    if (!problem.empty()) v.problems.push_back({key, dir, problem});
  }
  return v;
}

Store::Collection Store::collect_garbage(const std::set<std::string>& roots, double min_tmp_age_s) const {
  const auto folders = object_folders(root_);
  std::set<std::string> reachable;
  std::vector<std::string> todo(roots.begin(), roots.end());
  while (!todo.empty()) {
    const std::string key = todo.back();
    todo.pop_back();
    if (!folders.count(key) || !reachable.insert(key).second) continue;
    const auto meta = nlohmann::json::parse(read_file(folders.at(key) / kMetaFile), nullptr, false);
    if (meta.is_object() && meta.contains("references") && meta["references"].is_array())
      for (const auto& r : meta["references"])
        if (r.is_string()) todo.push_back(r);
  }
  Collection c;
  std::error_code ec;
  for (const auto& [key, dir] : folders) {
    if (reachable.count(key)) {
      ++c.kept;
      continue;
    }
    c.bytes_freed += folder_bytes(dir);
    // Renamed out of objects/ first, so a reader never sees it half removed.
    const fs::path doomed = temp_sibling(root_ / "tmp" / ("gc-" + key));
    fs::create_directories(doomed.parent_path(), ec);
    fs::rename(dir, doomed, ec);
    fs::remove_all(ec ? dir : doomed, ec);
    ++c.removed;
  }
  const auto now = fs::file_time_type::clock::now();
  for (const auto& e : fs::directory_iterator(root_ / "tmp", ec)) {
    const auto age = std::chrono::duration<double>(now - e.last_write_time(ec)).count();
    if (age < min_tmp_age_s) continue;
    c.bytes_freed += folder_bytes(e.path());
    fs::remove_all(e.path(), ec);
    ++c.temporaries;
  }
  return c;
}

}  // namespace olt
