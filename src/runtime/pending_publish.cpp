#include "pending_publish.h"

#include <nlohmann/json.hpp>
#include <set>

#include "olt/core/error.h"
#include "olt/core/fault.h"
#include "olt/core/fs.h"
#include "olt/core/json_text.h"

namespace olt {

bool through_real_folders(const FileSystem& files, const fs::path& output, const std::string& path,
                          std::set<fs::path>* known) {
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

std::string journal_text(const std::vector<std::string_view>& put, const Listed& gone) {
  std::string text = "{\n \"put\": ";
  append_array(
      text, put.size(), [&](size_t i) { return nlohmann::json(std::string(put[i])); }, 1);
  text += ",\n \"gone\": ";
  append_array(
      text, gone.size(),
      [&](size_t i) {
        return nlohmann::json{{"path", gone[i].first}, {"sha256", gone[i].second}};
      },
      1);
  text += "\n}\n";
  return text;
}

namespace {

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

// Moves a staged file to `to`: a rename; where `to` is on another file system (a mount point inside
// the output), a copy beside it renamed over it. The staged file then stays until the pending
// folder goes, after `crossed` (the folders reached that way, whose file system the output's sync
// does not reach) was synced: a journal replayed after a crash copies it again.
bool move_into_place(FileSystem& files, const fs::path& from, const fs::path& to, std::set<fs::path>* crossed) {
  try {
    return files.rename(from, to);
  } catch (const CrossDevice&) {
  }
  if (!replace_with(files, to, [&](const fs::path& temp) { files.copy(from, temp); })) return false;
  crossed->insert(to.parent_path());
  return true;
}

}  // namespace

void apply_pending(FileSystem& files, const fs::path& output) {
  const fs::path pending = output / kPending;
  const Journal journal = read_journal(files, pending / "journal.json");
  std::set<fs::path> real_folders, crossed;
  for (const std::string& path : journal.put) {
    const fs::path from = pending / "files" / path, to = output / path;
    if (!files.stat(from).is_file()) continue;
    if (!stays_inside(path) || !through_real_folders(files, output, path, &real_folders))
      throw InputError(to.string(),
                       "a symbolic link or a file is on the way inside the output folder: OLT writes "
                       "only into folders of its own there; remove it, and run again to finish publishing");
    if (!real_folders.count(to.parent_path()))
      files.make_folders(to.parent_path()), real_folders.insert(to.parent_path());
    if (!move_into_place(files, from, to, &crossed))
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
  for (const fs::path& folder : crossed) {
    for (const auto& name : files.list(folder))  // copies a run killed before their rename left
      if (orphaned_temp(name)) files.remove(folder / name);
    files.sync(folder);
  }
  files.sync(output);  // the changes on disk before the journal that would make them again goes
  // Gone in one step (a removal killed midway, its journal already deleted, would stop every next run),
  // then removed under a temporary name, which the next run removes if this one dies first.
  const fs::path done = temp_sibling(output / "olt-publish");
  if (!files.rename(pending, done)) throw FileSystemError(done.string() + ": cannot finish publishing");
  files.remove(done);
}

}  // namespace olt
