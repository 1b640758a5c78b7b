#include "pending_publish.h"

#include <mutex>
#include <nlohmann/json.hpp>
#include <set>

#include "olt/core/error.h"
#include "olt/core/fault.h"
#include "olt/core/fs.h"
#include "olt/core/json_text.h"
#include "olt/core/parallel.h"
#include "olt/core/pieces.h"

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

void journal_pieces(size_t put_count, const std::function<std::string(size_t)>& put, const Listed& gone,
                    const PieceSink& sink) {
  Pieces out(sink);
  const auto drain = [&](std::string&) { out.next(); };
  out.text() = "{\n \"put\": ";
  append_array(
      out.text(), put_count, [&](size_t i) { return nlohmann::json(std::string(put(i))); }, 1, drain);
  out.text() += ",\n \"gone\": ";
  append_array(
      out.text(), gone.size(),
      [&](size_t i) {
        return nlohmann::json{{"path", gone[i].first}, {"sha256", gone[i].second}};
      },
      1, drain);
  out.text() += "\n}\n";
  out.flush();
}

namespace {

// Removes `folder` and the folders above it, up to `output`, while they are empty.
void remove_empty_folders(FileSystem& files, fs::path folder, const fs::path& output) {
  for (; folder != output && folder.native().size() > output.native().size() && files.list(folder).empty();
       folder = folder.parent_path())
    files.remove(folder);
}

// What a pending publish's journal.json says: the paths to put as one text (80,000 at 10,000
// observations: 3 MB, where as many strings in a document and a list took 14 MB), read whole before
// any change is made.
struct Journal {
  std::string put;               ///< the paths, one after the other
  std::vector<size_t> put_ends;  ///< where each path ends in `put`
  Listed gone;
  std::string_view path(size_t i) const {
    const size_t begin = i == 0 ? 0 : put_ends[i - 1];
    return std::string_view(put).substr(begin, put_ends[i] - begin);
  }
};

Journal read_journal(const FileSystem& files, const fs::path& file) {
  const auto unreadable = [&](const std::string& why) {
    return InputError(file.string(), "not a publish journal OLT can read (" + why +
                                         "); it is left by a run that was publishing: remove " +
                                         file.parent_path().string() + " and run again");
  };
  // Parsed as it is read, not held whole (3 MB at 80,000 paths); the paths' text has room for as
  // many bytes as the file's at once, rather than growing by doubling (6 MB held at once, with the
  // text, 9 MB).
  const std::unique_ptr<std::istream> text = files.read_stream(file);
  Journal journal;
  journal.put.reserve(files.stat(file).size);
  nlohmann::json rest;
  try {
    // Parsed as events, each element taken as it is met: no document of 80,000 strings is built.
    std::string list;  // the member whose elements are being read
    rest = nlohmann::json::parse(*text, [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
      using Event = nlohmann::json::parse_event_t;
      if (depth == 1 && event == Event::key) list = parsed.get<std::string>();
      if (depth != 2 || (event != Event::value && event != Event::object_end)) return true;
      if (list == "put") {
        journal.put += parsed.get_ref<const std::string&>();
        journal.put_ends.push_back(journal.put.size());
      } else if (list == "gone") {
        journal.gone.emplace_back(parsed.at("path").get<std::string>(), parsed.at("sha256").get<std::string>());
      }
      return false;
    });
  } catch (const nlohmann::json::exception& e) {
    throw unreadable(e.what());
  }
  // Both lists there, every element taken (an element of another shape is left in them).
  for (const char* list : {"put", "gone"})
    if (!rest.is_object() || !rest.contains(list) || !rest[list].is_array() || !rest[list].empty())
      throw unreadable(std::string("expected \"") + list + "\": a list of " +
                       (list == std::string("put") ? "paths" : "{\"path\", \"sha256\"} objects"));
  return journal;
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

void apply_pending(FileSystem& files, const fs::path& output, Pending how) {
  const fs::path pending = output / kPending;
  const Journal journal = read_journal(files, pending / "journal.json");
  // The folders on the way first, those of a folder's files once (they come together), then made:
  // nothing changes where one of them is in the way.
  std::set<fs::path> real_folders;
  std::vector<size_t> first_of_folder;  // a file of each folder, by its place in the journal
  for (size_t i = 0; i < journal.put_ends.size(); ++i) {
    const std::string_view path = journal.path(i);
    if (!stays_inside(path) || ((i == 0 || folder_of(path) != folder_of(journal.path(i - 1))) &&
                                !through_real_folders(files, output, std::string(path), &real_folders)))
      throw InputError((output / path).string(),
                       "a symbolic link or a file is on the way inside the output folder: OLT writes "
                       "only into folders of its own there; remove it, and run again to finish publishing");
    if (i == 0 || folder_of(path) != folder_of(journal.path(i - 1))) first_of_folder.push_back(i);
  }
  for (const size_t i : first_of_folder) {
    const fs::path folder = (output / journal.path(i)).parent_path();
    if (!real_folders.count(folder)) files.make_folders(folder), real_folders.insert(folder);
  }
  // Then the files, on both threads: the kernel's work of a rename that replaces a file runs beside
  // another's (the moves after a one-box edit of the robot, 212 files: 3.1-3.7 ms on one thread,
  // 2.5-2.8 ms on two; docs/benchmarks.md, thirty-fourth session).
  std::set<fs::path> crossed;
  std::mutex crossed_mutex;
  parallel_for(journal.put_ends.size(), [&](size_t i) {
    const std::string_view path = journal.path(i);
    const fs::path from = pending / "files" / path, to = output / path;
    if (how != Pending::staged_now && !files.stat(from).is_file()) return;  // moved before a crash
    std::set<fs::path> crossed_here;
    if (!move_into_place(files, from, to, &crossed_here))
      throw FileSystemError(to.string() + ": cannot publish: a folder is in the way; remove it, and run again");
    if (!crossed_here.empty()) {
      const std::lock_guard<std::mutex> lock(crossed_mutex);
      crossed.insert(crossed_here.begin(), crossed_here.end());
    }
    fault_point("file_moved");
  });
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
  std::vector<fs::path> synced = {output};
  for (const fs::path& folder : crossed) {
    for (const auto& name : files.list(folder))  // copies a run killed before their rename left
      if (orphaned_temp(name)) files.remove(folder / name);
    synced.push_back(folder);
  }
  files.sync(synced);  // the changes on disk before the journal that would make them again goes
  // Gone in one step (a removal killed midway, its journal already deleted, would stop every next run),
  // then removed under a temporary name, which the next run removes if this one dies first.
  const fs::path done = temp_sibling(output / "olt-publish");
  if (!files.rename(pending, done)) throw FileSystemError(done.string() + ": cannot finish publishing");
  files.remove(done);
}

}  // namespace olt
