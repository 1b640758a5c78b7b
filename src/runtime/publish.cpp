#include "olt/runtime/publish.h"

#include <algorithm>
#include <optional>
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

// The digest of the output's manifest file; empty without one (or one that cannot be read).
std::string manifest_digest(const FileSystem& files, const fs::path& manifest_file) {
  if (!files.stat(manifest_file).is_file()) return "";
  try {
    return files.sha256(manifest_file);  // not read whole: 31 MB at 80,000 files
  } catch (const std::exception&) {
    return "";
  }
}

// Nothing to publish: the output's manifest is, byte for byte, the one this run would write (their
// digests), and every file it lists is there with its size (what `changes` asks of a file before it
// keeps it; the folders on the way were checked before).
bool unchanged(const FileSystem& files, const fs::path& output, const Entries& entries, const std::string& digest,
               const std::string& existing_digest) {
  if (digest != existing_digest) return false;
  for (const Entry& e : entries) {
    const FileStat st = files.stat(output / e.published.path);
    if (!st.is_file() || st.size != e.file->size) return false;
  }
  return true;
}

// A copy of what the output's manifest lists, kept in the cache: its first line the manifest's
// digest, then a line per file, "<sha256> <bytes in its path> <path>", sorted by path. Read instead
// of the manifest (31 MB of JSON at 80,000 files, 0.3 s to parse) when it copies the manifest there.
std::string listing_text(const std::string& digest, const Entries& entries) {
  std::string text = digest + "\n";
  for (const Entry& e : entries)
    text += e.file->sha256 + " " + std::to_string(e.published.path.size()) + " " + e.published.path + "\n";
  return text;
}

// The listing at `file` when it copies the manifest of digest `manifest_digest`; nothing when it is
// missing, of another manifest, or not one (a listing is only a shortcut: the manifest is read then).
std::optional<Listed> read_listing(const FileSystem& files, const fs::path& file, const std::string& manifest_digest) {
  if (file.empty() || manifest_digest.empty() || !files.stat(file).is_file()) return std::nullopt;
  try {
    const std::string text = files.read(file);
    if (text.compare(0, manifest_digest.size() + 1, manifest_digest + "\n") != 0) return std::nullopt;
    Listed listed;
    for (size_t at = manifest_digest.size() + 1; at < text.size();) {
      const size_t space = text.find(' ', at);
      const size_t second = space == std::string::npos ? space : text.find(' ', space + 1);
      if (second == std::string::npos || second == space + 1) return std::nullopt;
      const std::string digits = text.substr(space + 1, second - space - 1);
      if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
      const size_t length = std::stoul(digits), end = second + 1 + length;
      if (end >= text.size() || text[end] != '\n') return std::nullopt;
      std::string path = text.substr(second + 1, length);
      if (!listed.empty() && !(listed.back().first < path)) return std::nullopt;  // sorted, as written
      listed.emplace_back(std::move(path), text.substr(at, space - at));
      at = end + 1;
    }
    return listed;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// The manifest's text, byte for byte as nlohmann::json's dump(1) of {"files": [...]} writes it (keys
// in its sorted order, strings and numbers written by it), assembled without the document: as JSON
// values, 80,000 entries took 0.2-0.5 s to build and dump, and ~1 KB each.
std::string manifest_text(const Entries& entries) {
  if (entries.empty()) return "{\n \"files\": []\n}\n";
  const auto quoted = [](const std::string& s) { return nlohmann::json(s).dump(); };
  std::string text = "{\n \"files\": [\n";
  for (size_t i = 0; i < entries.size(); ++i) {
    const Entry& e = entries[i];
    const Published& p = e.published;
    text += i ? ",\n  {\n" : "  {\n";
    text += "   \"kind\": " + quoted(p.kind) + ",\n";
    if (!p.observation.empty())
      text += "   \"observation\": {\n    \"id\": " + quoted(p.observation) +
              ",\n    \"timestamp\": " + nlohmann::json(p.timestamp).dump() + "\n   },\n";
    text += "   \"path\": " + quoted(p.path) + ",\n";
    if (!p.sensor.empty()) text += "   \"sensor\": " + quoted(p.sensor) + ",\n";
    text += "   \"sha256\": " + quoted(e.file->sha256) + ",\n";
    text += "   \"stage\": " + quoted(e.stage) + "\n  }";
  }
  text += "\n ]\n}\n";
  return text;
}

// A publish's changes to the output: the entries to put (indices into the entries) and the files
// the last manifest listed that this one does not (path, listed digest).
struct Changes {
  std::vector<size_t> put;
  Listed gone;
};

// What differs between the output and the entries: an entry is put unless the last manifest lists
// it with its digest and a file of its size is there (a listed file edited by hand to other bytes of
// the same size is left as it is, like any file the manifest does not describe).
Changes changes(const FileSystem& files, const fs::path& output, const Entries& entries, const Listed& previous) {
  std::vector<char> put(entries.size(), 0);
  parallel_for(entries.size(), [&](size_t i) {
    const Entry& e = entries[i];
    const FileStat st = files.stat(output / e.published.path);
    if (st.is_folder())
      throw InputError((output / e.published.path).string(),
                       "a folder is where OLT publishes a file (from stage '" + e.stage + "'); remove it");
    const std::string* old = find_listed(previous, e.published.path);
    put[i] = !(old && *old == e.file->sha256 && st.is_file() && st.size == e.file->size);
  });
  Changes out;
  for (size_t i = 0; i < entries.size(); ++i)
    if (put[i]) out.put.push_back(i);
  for (const auto& listed : previous)
    if (!find_entry(entries, listed.first) && stays_inside(listed.first)) out.gone.push_back(listed);
  return out;
}

// A publish's changes wait in `output/.olt-publish`, complete and durable, before the first is
// made: files/<path> to move into place, journal.json ({"put": [path], "gone": [{"path",
// "sha256"}]}), manifest.json. Renaming the folder, filled under a temporary name, to this one is the
// moment a publish happens: before it, nothing of the output has changed; after it, the changes are
// made, by this run or, killed, by the next.
const char* const kPending = ".olt-publish";

std::string journal_text(const Entries& entries, const Changes& changes) {
  std::string text = "{\n \"put\": ";
  append_array(
      text, changes.put.size(), [&](size_t i) { return nlohmann::json(entries[changes.put[i]].published.path); }, 1);
  text += ",\n \"gone\": ";
  append_array(
      text, changes.gone.size(),
      [&](size_t i) {
        return nlohmann::json{{"path", changes.gone[i].first}, {"sha256", changes.gone[i].second}};
      },
      1);
  text += "\n}\n";
  return text;
}

// Removes `folder` and the folders above it, up to `output`, while they are empty.
void remove_empty_folders(FileSystem& files, fs::path folder, const fs::path& output) {
  for (; folder != output && folder.native().size() > output.native().size() && files.list(folder).empty();
       folder = folder.parent_path())
    files.remove(folder);
}

// What a pending publish's journal.json says.
struct Journal {
  std::vector<std::string> put;
  Listed gone;
};

Journal read_journal(const FileSystem& files, const fs::path& file) {
  const std::string text = files.read(file);
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    Journal journal;
    for (const auto& path : j.at("put")) journal.put.push_back(path.get<std::string>());
    for (const auto& gone : j.at("gone"))
      journal.gone.emplace_back(gone.at("path").get<std::string>(), gone.at("sha256").get<std::string>());
    return journal;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string(), std::string("not a publish journal OLT can read (") + e.what() +
                                        "); it is left by a run that was publishing: remove " +
                                        file.parent_path().string() + " and run again");
  }
}

// Makes the changes waiting in output/.olt-publish, then removes it. Each step can be made again
// (a file already moved is not in files/ any more), so a run killed here is finished by the next.
void apply_pending(FileSystem& files, const fs::path& output) {
  const fs::path pending = output / kPending;
  const Journal journal = read_journal(files, pending / "journal.json");
  std::set<fs::path> real_folders;
  for (const std::string& path : journal.put) {
    const fs::path from = pending / "files" / path, to = output / path;
    if (!files.stat(from).is_file()) continue;
    if (!stays_inside(path) || !through_real_folders(files, output, path, &real_folders))
      throw InputError(to.string(),
                       "a symbolic link or a file is on the way inside the output folder: OLT writes "
                       "only into folders of its own there; remove it, and run again to finish publishing");
    if (!real_folders.count(to.parent_path()))
      files.make_folders(to.parent_path()), real_folders.insert(to.parent_path());
    if (!files.rename(from, to))
      throw FileSystemError(to.string() + ": cannot publish: a folder is in the way; remove it, and run again");
    fault_point("file_moved");
  }
  for (const auto& [path, sha256] : journal.gone) {
    if (!stays_inside(path) || !through_real_folders(files, output, path)) continue;
    const fs::path file = output / path;
    if (files.stat(file).is_file() && files.sha256(file) == sha256) {
      files.remove(file);
      remove_empty_folders(files, file.parent_path(), output);
    }
  }
  if (files.stat(pending / "manifest.json").is_file() &&
      !files.rename(pending / "manifest.json", output / "manifest.json"))
    throw FileSystemError((output / "manifest.json").string() + ": cannot publish: a folder is in the way");
  files.sync(output);  // the changes on disk before the journal that would make them again goes
  files.remove(pending);
}

// Temporaries beside the output (.tmp.<output name>.<pid>.<n>, where earlier versions staged a whole
// output) and changes staged inside it (.tmp.olt-publish.<pid>.<n>) of runs that died before they
// published.
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

void publish_outputs(const fs::path& output_path, const std::vector<std::pair<std::string, Artifact>>& artifacts,
                     FileSystem& files, const fs::path& listing) {
  const Entries entries = entries_to_publish(files, artifacts);
  const fs::path output = output_folder(files, output_path);
  std::set<fs::path> real_folders;
  for (const Entry& e : entries)
    if (!through_real_folders(files, output, e.published.path, &real_folders))
      throw InputError((output / e.published.path).string(),
                       "a symbolic link or a file is on the way inside the output folder: OLT writes only into "
                       "folders of its own there; remove it");
  finish_publishing(output, files);
  const std::string manifest = manifest_text(entries), digest = sha256_hex(manifest);
  const std::string existing = manifest_digest(files, output / "manifest.json");
  if (unchanged(files, output, entries, digest, existing)) return;
  const std::optional<Listed> listed = read_listing(files, listing, existing);
  const Changes todo =
      changes(files, output, entries, listed ? *listed : previous_manifest(files, output / "manifest.json"));
  // Staged inside the output (the same file system, a mount point included) under a temporary name,
  // made durable, then renamed to .olt-publish: a run that dies or meets a full disk before that
  // leaves the output as it was.
  const fs::path staged = temp_sibling(output / "olt-publish");  // .tmp.olt-publish.<host>.<pid>.<n>
  try {
    files.make_folders(staged / "files");
    Progress progress("files published", todo.put.size());
    parallel_for(todo.put.size(), [&](size_t i) {
      const Entry& e = entries[todo.put[i]];
      copy_verified(files, e, staged / "files" / e.published.path);
      fault_point("published_file");
      progress.advance();
    });
    files.write(staged / "manifest.json", manifest);
    files.write(staged / "journal.json", journal_text(entries, todo));
    // The listing of the new manifest, before it is published: a run that stops before that leaves a
    // listing of a manifest that is not there, which is not read.
    if (!listing.empty()) files.write_atomic(listing, listing_text(digest, entries));
    files.sync(staged);
    fault_point("manifest_next");
    if (!files.rename(staged, output / kPending))
      throw FileSystemError((output / kPending).string() + ": cannot publish: a folder is in the way");
  } catch (...) {
    files.remove(staged);
    throw;
  }
  fault_point("publish_committed");
  apply_pending(files, output);
}

}  // namespace olt
