#include "olt/cache/store.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>

#include "meta.h"
#include "olt/core/error.h"
#include "olt/core/fault.h"
#include "olt/core/hash.h"

namespace olt {

std::string digest_of(const std::vector<ArtifactFile>& files) {
  std::string lines;
  for (const auto& f : files) lines += f.sha256 + "  " + f.path + "\n";
  return sha256_hex(lines);
}

Store::Store(fs::path root) : root_(std::move(root)) {}

fs::path Store::object_dir(const std::string& key) const { return root_ / "objects" / key.substr(0, 2) / key; }

std::optional<Artifact> Store::find(const std::string& key) const {
  const fs::path dir = object_dir(key);
  std::error_code ec;
  if (!fs::exists(dir / kMetaFile, ec)) return std::nullopt;
  // A damaged entry is a cache miss, not an error: the stage runs again and replaces it.
  try {
    const auto meta = nlohmann::json::parse(read_file(dir / kMetaFile));
    if (meta.value("key", "") != key) return std::nullopt;
    Artifact a{key, meta.at("digest"), dir, {}};
    for (const auto& f : meta.at("files")) {
      a.files.push_back({f.at("path"), f.at("sha256"), f.at("size")});
      if (fs::file_size(dir / a.files.back().path, ec) != a.files.back().size || ec) return std::nullopt;
    }
    return a;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

fs::path Store::begin(const std::string& key) const {
  const fs::path temp = temp_sibling(root_ / "tmp" / key);
  fs::create_directories(temp);
  return temp;
}

Artifact Store::describe(const std::string& key, const fs::path& dir,
                         const std::map<std::string, std::string>& known) const {
  Artifact a{key, "", dir, {}};
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    const std::string path = fs::relative(entry.path(), dir).generic_string();
    auto it = known.find(path);
    a.files.push_back(
        {path, it != known.end() ? it->second : sha256_file(entry.path()), static_cast<uint64_t>(entry.file_size())});
  }
  std::sort(a.files.begin(), a.files.end(), [](const auto& x, const auto& y) { return x.path < y.path; });
  a.digest = digest_of(a.files);
  return a;
}

Artifact Store::commit(const std::string& key, const fs::path& temp, const std::map<std::string, std::string>& known,
                       bool durable, const std::set<std::string>& references) const {
  Artifact a = describe(key, temp, known);
  a.dir = object_dir(key);
  nlohmann::json meta = {{"key", key}, {"digest", a.digest}, {"files", nlohmann::json::array()}};
  if (!references.empty()) meta["references"] = references;
  for (const auto& f : a.files) meta["files"].push_back({{"path", f.path}, {"sha256", f.sha256}, {"size", f.size}});
  write_file(temp / kMetaFile, meta.dump(1));
  if (durable) sync_file_system(temp);
  fault_point("artifact_written");
  fs::create_directories(a.dir.parent_path());
  std::error_code ec;
  fs::rename(temp, a.dir, ec);
  if (ec) {
    // The target exists: another writer won the race (keep theirs), or it is a damaged entry
    // (replace it).
    if (auto existing = find(key)) {
      fs::remove_all(temp);
      return *existing;
    }
    fs::remove_all(a.dir, ec);
    fs::rename(temp, a.dir, ec);
    if (ec) {
      fs::remove_all(temp);
      throw std::runtime_error(a.dir.string() + ": cannot store artifact: " + ec.message());
    }
  }
  fault_point("artifact_stored");
  return a;
}

void Store::discard(const fs::path& temp) const {
  std::error_code ec;
  fs::remove_all(temp, ec);
}

namespace {

// The record inside a record file, when the file is one of the current format.
std::optional<nlohmann::json> read_record(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return std::nullopt;
  auto wrapped = nlohmann::json::parse(read_file(file), nullptr, false);
  if (wrapped.is_discarded() || !wrapped.is_object() || wrapped.value("format", 0) != kRecordFormat ||
      !wrapped.contains("record"))
    return std::nullopt;
  return wrapped["record"];
}

}  // namespace

std::optional<nlohmann::json> Store::record(const std::string& job_id, const std::string& stage_id) const {
  return read_record(root_ / "records" / job_id / (stage_id + ".json"));
}

std::vector<nlohmann::json> Store::records() const {
  std::vector<nlohmann::json> out;
  std::error_code ec;
  for (const auto& job_dir : fs::directory_iterator(root_ / "records", ec))
    for (const auto& file : fs::directory_iterator(job_dir.path(), ec))
      if (auto record = read_record(file.path())) out.push_back(std::move(*record));
  return out;
}

void Store::save_record(const std::string& job_id, const std::string& stage_id, const nlohmann::json& record) const {
  const nlohmann::json wrapped = {{"format", kRecordFormat}, {"record", record}};
  write_file_atomic(root_ / "records" / job_id / (stage_id + ".json"), wrapped.dump(1));
}

void Store::log(const nlohmann::json& entry) const {
  fs::create_directories(root_);
  nlohmann::json line = entry;
  line["format"] = kRecordFormat;
  // One write(2) of a short line with O_APPEND: concurrent writers do not interleave lines.
  std::ofstream out(root_ / "log.jsonl", std::ios::app);
  out << line.dump() + "\n" << std::flush;
}

FileDigests::FileDigests(fs::path memo_file) : memo_file_(std::move(memo_file)) {
  std::error_code ec;
  if (fs::exists(memo_file_, ec)) {
    std::ifstream in(memo_file_);
    memo_ = nlohmann::json::parse(in, nullptr, false);
  }
  if (!memo_.is_object()) memo_ = nlohmann::json::object();
}

std::string FileDigests::digest(const fs::path& file) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) throw InputError(file.string(), "file not found");
  const nlohmann::json stamp = {static_cast<uint64_t>(st.st_size),
                                static_cast<int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec,
                                static_cast<uint64_t>(st.st_ino)};
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = memo_.find(file.string());
    if (it != memo_.end() && it->at("stamp") == stamp) return it->at("sha256");
  }
  const std::string sha = sha256_file(file);
  std::lock_guard<std::mutex> lock(mutex_);
  memo_[file.string()] = {{"stamp", stamp}, {"sha256", sha}};
  changed_ = true;
  return sha;
}

void FileDigests::save() const {
  if (!changed_) return;
  try {
    write_file_atomic(memo_file_, memo_.dump());
  } catch (const std::exception&) {
    // Losing the memo only costs re-hashing next time.
  }
}

}  // namespace olt
