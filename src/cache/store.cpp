#include "olt/cache/store.h"

#include <algorithm>
#include <cstdint>
#include <set>
#include <string_view>
#include <unordered_set>
#include <utility>

#include "meta.h"
#include "olt/core/error.h"
#include "olt/core/fault.h"
#include "olt/core/hash.h"
#include "olt/core/json_text.h"
#include "olt/core/parallel.h"
#include "olt/core/process_memory.h"

namespace olt {

// The hash of a line per file, "<sha256>  <path>", hashed as they come (70,000 files at 10,000
// frames: 7 MB of lines not held).
std::string digest_of(const ArtifactFiles& files) {
  Sha256 hash;
  std::string line;  // "<sha256>  <path>\n", one buffer for all
  for (const auto& f : files) {
    line.clear();
    f.sha256.append_hex(line);
    line += "  ";
    line += f.path;
    line += '\n';
    hash.update(line);
  }
  return hash.hex();
}

Store::Store(fs::path root, FileSystem& files) : root_(std::move(root)), files_(files) {}

fs::path Store::object_dir(const std::string& key) const { return artifact_dir(root_ / "objects", key); }

bool safe_key(std::string_view key) {
  return key.size() >= 2 && key.find_first_not_of("0123456789abcdefghijklmnopqrstuvwxyz-") == std::string::npos;
}

bool safe_reference(std::string_view in, std::string_view as) { return safe_key(in) && stays_inside(as); }

namespace {

// An entry `olt watch` found or made before (see Store::find): its artifact, and its metadata file as
// it was.
struct KnownEntry {
  Artifact artifact;
  FileStat meta;
};

// The name an entry of the cache at `root` on `files` is kept under in `olt watch`'s memory.
std::string known_entry_name(const FileSystem& files, const fs::path& root, const std::string& key) {
  return "store entry " + std::to_string(reinterpret_cast<uintptr_t>(&files)) + " " + root.string() + " " + key;
}

// ... where it is kept: none where a process keeps nothing or the file system tells files apart by
// no identity (`meta`, the entry's metadata file).
std::optional<std::string> known_entry_name(const FileSystem& files, const fs::path& root, const std::string& key,
                                            const FileStat& meta) {
  if (!keeping_memory() || meta.identity == 0) return std::nullopt;
  return known_entry_name(files, root, key);
}

void remember_known(const std::optional<std::string>& name, const Artifact& a, const FileStat& meta) {
  if (name)
    remember<KnownEntry>(*name, std::make_shared<const KnownEntry>(KnownEntry{a, meta}),
                         sizeof(KnownEntry) + a.files.bytes());
}

// Whether every file the list refers to in another entry names it safely (what find_unchecked asks
// of an entry's metadata).
bool safe_references(const ArtifactFiles& files) {
  return std::all_of(files.begin(), files.end(),
                     [](const ListedFile& f) { return f.in.empty() || safe_reference(f.in, f.as); });
}

}  // namespace

std::optional<Artifact> Store::find_unchecked(const std::string& key) const {
  const fs::path dir = object_dir(key);
  try {  // a damaged entry is a cache miss, not an error: the stage runs again and replaces it
    std::optional<Meta> meta = read_meta_file(files_, dir / kMetaFile);
    if (!meta || meta->key != key) return std::nullopt;
    if (!safe_references(meta->files)) return std::nullopt;
    return Artifact{key, std::move(meta->digest), dir, std::move(meta->files), root_ / "objects"};
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

bool Store::holds(const std::string& key) const { return files_.stat(object_dir(key) / kMetaFile).is_file(); }

std::optional<Artifact> Store::find(const std::string& key) const {
  const FileStat meta_stat = files_.stat(object_dir(key) / kMetaFile);
  if (!meta_stat.is_file()) return std::nullopt;
  // In `olt watch`, an entry found or made before whose metadata file is the same file (inode, size,
  // time: entries are written once and renamed into place, so a replaced one is another file) is
  // that entry: its files are not checked again each cycle (the source's 30,000 at 10,000
  // observations), while the daemon keeps it.
  const std::optional<std::string> remembered_as = known_entry_name(files_, root_, key, meta_stat);
  if (remembered_as)
    if (const auto known = remembered<KnownEntry>(*remembered_as); known && known->meta.same_file(meta_stat))
      return known->artifact;
  std::optional<Artifact> listed = find_unchecked(key);
  if (!listed) return std::nullopt;
  try {
    const Artifact& a = *listed;
    // Every file there with its size: a stat each, in parallel (a stage's artifact can refer to
    // 70,000 files of its frames' entries).
    const bool whole = parallel_all(a.files.size(), [&](size_t i) {
      const ListedFile file = a.files[i];
      const FileStat st = files_.stat(a.path(file));
      return st.is_file() && st.size == file.size;
    });
    if (!whole) return std::nullopt;
    remember_known(remembered_as, a, meta_stat);
    return listed;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

fs::path Store::begin(const std::string& key) const {
  const fs::path temp = temp_sibling(root_ / "tmp" / key);
  files_.make_folders(temp);
  return temp;
}

namespace {

// The artifact's .artifact.json: dump(1) of {"digest", "files", "key"[, "references"]}, written a
// megabyte at a time (a stage's artifact lists every frame's files: 70,000 at 10,000 frames, 17 MB).
void write_meta(FileSystem& files, const fs::path& file, const Artifact& a, const std::set<std::string>& references) {
  std::string text = "{\n \"digest\": \"" + a.digest + "\",\n \"files\": ";
  bool started = false;
  const auto drain = [&](std::string& so_far) {
    started ? files.append(file, so_far) : files.write(file, so_far);
    started = true;
    so_far.clear();
  };
  // Each file's entry as dump(1) writes it (keys sorted: as, in, path, sha256, size), assembled
  // without a JSON value per entry (70,000 of them took 0.1-0.3 s).
  if (a.files.empty()) text += "[]";
  for (size_t i = 0; i < a.files.size(); ++i) {
    const ListedFile f = a.files[i];
    text += i ? ",\n  {\n" : "[\n  {\n";
    if (!f.in.empty()) {  // appended in place: no string of its own for each part (70,000 entries)
      text += "   \"as\": ";
      append_json_string(text, f.as);
      text += ",\n   \"in\": ";
      append_json_string(text, f.in);
      text += ",\n";
    }
    text += "   \"path\": ";
    append_json_string(text, f.path);
    text += ",\n   \"sha256\": \"";
    f.sha256.append_hex(text);
    text += "\",\n   \"size\": ";
    text += std::to_string(f.size);
    text += "\n  }";
    if (text.size() >= (1u << 20)) drain(text);
  }
  if (!a.files.empty()) text += "\n ]";
  text += ",\n \"key\": " + nlohmann::json(a.key).dump();
  if (!references.empty()) {
    text += ",\n \"references\": ";
    append_nested(text, nlohmann::json(references), 1);
  }
  text += "\n}";
  drain(text);
}

}  // namespace

Artifact Store::describe(const std::string& key, const fs::path& dir, ArtifactFiles described) const {
  // The files described stay in the list they came in (a stage with units refers to 70,000 at 10,000
  // frames, a source writes 30,000), which the run then holds until it publishes.
  Artifact a{key, "", dir, std::move(described), root_ / "objects"};
  a.files.sort();
  // Its own files: as they were hashed when written; those a library wrote, hashed here from their
  // bytes, in parallel; none that is no longer there.
  const std::vector<std::string> written = files_.files_below(dir);  // sorted
  a.files.erase_if(
      [&](const ListedFile& f) { return f.in.empty() && !std::binary_search(written.begin(), written.end(), f.path); });
  std::vector<size_t> unhashed;
  for (size_t i = 0; i < written.size(); ++i)
    if (const std::optional<ListedFile> f = a.files.find(written[i]); !f || !f->in.empty()) unhashed.push_back(i);
  std::vector<std::pair<Digest, uint64_t>> hashed(unhashed.size());
  parallel_for(unhashed.size(), [&](size_t k) {
    const fs::path file = dir / written[unhashed[k]];
    hashed[k] = {Digest(files_.sha256(file)), files_.stat(file).size};
  });
  for (size_t k = 0; k < unhashed.size(); ++k) a.files.add(written[unhashed[k]], hashed[k].first, hashed[k].second);
  a.files.sort();
  a.digest = digest_of(a.files);
  return a;
}

Artifact Store::commit(const std::string& key, const fs::path& temp, ArtifactFiles described) const {
  Artifact a = describe(key, temp, std::move(described));
  a.dir = object_dir(key);
  // The artifacts it refers to, each once: 70,000 files name 10,000 frames' entries, so they are told
  // apart as views first (a string and an ordered insert per file was 11 % of committing the
  // labeling stage at 10,000 frames, by perf).
  std::unordered_set<std::string_view> referred;
  for (const ListedFile f : a.files)
    if (!f.in.empty()) referred.insert(f.in);
  const std::set<std::string> references(referred.begin(), referred.end());
  write_meta(files_, temp / kMetaFile, a, references);
  fault_point("artifact_written");
  // Its metadata file as written (renaming the folder leaves the file as it is): what the entry is
  // remembered by, below, once it is in place.
  const FileStat meta = keeping_memory() ? files_.stat(temp / kMetaFile) : FileStat();
  files_.make_folders(a.dir.parent_path());
  if (!files_.rename(temp, a.dir)) {
    // The target exists: another writer won the race (keep theirs), or it is a damaged entry
    // (replace it).
    if (auto existing = find(key)) {
      files_.remove(temp);
      return *existing;
    }
    files_.remove(a.dir);
    if (!files_.rename(temp, a.dir)) {
      files_.remove(temp);
      throw FileSystemError(a.dir.string() + ": cannot store artifact: another process keeps writing it");
    }
  }
  fault_point("artifact_stored");
  // In `olt watch`, remembered as if found: its files were just written and listed, so finding it
  // later is one stat. The stages after this one need it the same cycle, and the next edit's
  // unchanged frames are those this one made (docs/benchmarks.md, "Entries the daemon made").
  if (const auto name = known_entry_name(files_, root_, key, meta); name && safe_references(a.files))
    remember_known(name, a, meta);
  const std::lock_guard<std::mutex> lock(committed_mutex_);
  add_committed(key);
  return a;
}

void Store::forget(const std::string& key) const {
  if (keeping_memory()) taken<KnownEntry>(known_entry_name(files_, root_, key));
}

std::vector<std::string> Store::forget_unused(const std::string& name, std::vector<std::string> keys) const {
  if (!keeping_memory()) return {};
  using Keys = std::vector<std::string>;
  Keys forgotten;
  if (const auto before = remembered<Keys>(name)) {
    const std::unordered_set<std::string_view> used(keys.begin(), keys.end());
    for (const std::string& key : *before)
      if (!used.count(key)) {
        forget(key);
        forgotten.push_back(key);
      }
  }
  size_t bytes = sizeof(Keys);
  for (const std::string& key : keys) bytes += sizeof(std::string) + key.capacity();
  remember<Keys>(name, std::make_shared<const Keys>(std::move(keys)), bytes);
  return forgotten;
}

void Store::add_committed(const std::string& key) const {
  constexpr size_t kHex = 64;  // a digest's, at the end
  const size_t name_size = key.size() - std::min(key.size(), kHex);
  const std::optional<Digest> digest = Digest::from_hex(std::string_view(key).substr(name_size));
  if (!digest) return committed_.push_back(key);
  const std::string_view name = std::string_view(key).substr(0, name_size);
  const size_t place =
      static_cast<size_t>(std::find(committed_names_.begin(), committed_names_.end(), name) - committed_names_.begin());
  if (place == committed_names_.size()) {
    if (place > UINT16_MAX) return committed_.push_back(key);
    committed_names_.emplace_back(name);
  }
  committed_digests_.push_back({*digest, static_cast<uint16_t>(place)});
}

std::vector<std::string> Store::take_committed() const {
  const std::lock_guard<std::mutex> lock(committed_mutex_);
  std::vector<std::string> keys = std::exchange(committed_, {});
  for (const CommittedKey& k : committed_digests_) keys.push_back(committed_names_[k.name] + k.digest.hex());
  std::deque<CommittedKey>().swap(committed_digests_);
  committed_names_.clear();
  return keys;
}

void Store::clear_committed() const {
  const std::lock_guard<std::mutex> lock(committed_mutex_);
  std::vector<std::string>().swap(committed_);
  std::deque<CommittedKey>().swap(committed_digests_);
  committed_names_.clear();
}

void Store::remove(const std::string& key) const {
  if (safe_key(key)) remove_object(object_dir(key), key);
}

void Store::discard(const fs::path& temp) const { files_.remove(temp); }

void Store::drop(const std::string& key) const {
  const fs::path dir = object_dir(key);
  std::vector<std::string> keys = {key};
  const auto meta =
      nlohmann::json::parse(files_.stat(dir / kMetaFile).is_file() ? files_.read(dir / kMetaFile) : "", nullptr, false);
  if (meta.is_object() && meta.contains("references") && meta["references"].is_array())
    for (const auto& r : meta["references"])
      if (r.is_string()) keys.push_back(r);
  for (const auto& k : keys)  // a key names a folder under objects/: nothing else is removed
    if (safe_key(k)) remove_object(object_dir(k), k);
}

void Store::remove_object(const fs::path& dir, const std::string& key) const {
  // Renamed out of objects/ first, so a reader never sees it half removed.
  const fs::path doomed = temp_sibling(root_ / "tmp" / ("gone-" + key));
  files_.make_folders(doomed.parent_path());
  files_.remove(files_.rename(dir, doomed) ? doomed : dir);
}

namespace {

// The record inside a record file, when the file is one of the current format.
std::optional<nlohmann::json> read_record(const FileSystem& files, const fs::path& file) {
  if (!files.stat(file).is_file()) return std::nullopt;
  auto wrapped = nlohmann::json::parse(files.read(file), nullptr, false);
  if (wrapped.is_discarded() || !wrapped.is_object() || wrapped.value("format", 0) != kRecordFormat ||
      !wrapped.contains("record"))
    return std::nullopt;
  return wrapped["record"];
}

}  // namespace

std::optional<nlohmann::json> Store::record(const std::string& job_id, const std::string& stage_id) const {
  return read_record(files_, root_ / "records" / job_id / (stage_id + ".json"));
}

std::vector<nlohmann::json> Store::records() const {
  std::vector<nlohmann::json> out;
  const fs::path records = root_ / "records";
  for (const auto& job : files_.list(records))
    for (const auto& file : files_.list(records / job))
      if (auto record = read_record(files_, records / job / file)) out.push_back(std::move(*record));
  return out;
}

bool Store::save_record(const std::string& job_id, const std::string& stage_id, const nlohmann::json& record) const {
  const nlohmann::json wrapped = {{"format", kRecordFormat}, {"record", record}};
  const fs::path file = root_ / "records" / job_id / (stage_id + ".json");
  const std::string text = wrapped.dump(1);
  // A run with nothing to do leaves its records as they are.
  if (files_.stat(file).is_file() && files_.read(file) == text) return false;
  replace_unsynced(files_, file, text);
  return true;
}

void Store::mark() const {
  if (!marked())
    files_.write_atomic(root_ / "olt-cache.json", nlohmann::json({{"olt_cache", kRecordFormat}}).dump() + "\n");
}

bool Store::marked() const { return files_.stat(root_ / "olt-cache.json").is_file(); }

void Store::log(const nlohmann::json& entry) const {
  nlohmann::json line = entry;
  line["format"] = kRecordFormat;
  // One write(2) of a short line with O_APPEND: concurrent writers do not interleave lines.
  files_.append(root_ / "log.jsonl", line.dump() + "\n");
  fault_point("log_appended");
}

FileDigests::FileDigests(fs::path memo_file, FileSystem& files) : memo_file_(std::move(memo_file)), files_(files) {
  if (files_.stat(memo_file_, true).is_file()) memo_ = nlohmann::json::parse(files_.read(memo_file_), nullptr, false);
  if (!memo_.is_object()) memo_ = nlohmann::json::object();
}

std::string FileDigests::digest(const fs::path& file) {
  const FileStat st = files_.stat(file, true);
  if (!st.exists()) throw InputError(file.string(), "file not found");
  const nlohmann::json stamp = {st.size, st.mtime_ns, st.identity};
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = memo_.find(file.string());
    // An entry of another shape, or a digest that is not one, is hashed again (the memo is a shortcut).
    if (it != memo_.end() && it->is_object() && it->value("stamp", nlohmann::json()) == stamp) {
      const auto sha = it->find("sha256");
      if (sha != it->end() && sha->is_string() && Digest::from_hex(sha->get_ref<const std::string&>())) return *sha;
    }
  }
  const std::string sha = files_.sha256(file);
  std::lock_guard<std::mutex> lock(mutex_);
  memo_[file.string()] = {{"stamp", stamp}, {"sha256", sha}};
  changed_ = true;
  return sha;
}

bool FileDigests::save() const {
  if (!changed_) return false;
  try {
    replace_unsynced(files_, memo_file_, memo_.dump());
    return true;
  } catch (const std::exception&) {
    return false;  // losing the memo only costs re-hashing next time
  }
}

}  // namespace olt
