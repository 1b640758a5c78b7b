#include "memory_file_system.h"

#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <map>
#include <mutex>
#include <set>
#include <utility>

#include "olt/core/error.h"

namespace olt::test {
namespace {

struct Node {
  FileStat::Type type = FileStat::Type::folder;
  std::shared_ptr<std::string> bytes;  ///< files; shared by hard links
  fs::path target;                     ///< links
  int64_t mtime = 0;
  uint64_t id = 0;
};

std::vector<std::string> parts_of(const fs::path& path) {
  std::vector<std::string> parts;
  for (const auto& part : path.lexically_normal())
    if (!part.empty() && part != "/" && part != ".") parts.push_back(part.string());
  return parts;
}

}  // namespace

struct MemoryFileSystem::State {
  mutable std::mutex mutex;
  std::map<std::string, Node> nodes;  // by absolute path; the root "/" is implied
  int64_t clock = 0;
  uint64_t next_id = 1;
  int64_t writes_left = -1;  // -1: no limit
  int64_t writes = 0, syncs = 0;
  // Power loss, as a journaling file system's ordered mode leaves it: every change to names and
  // folders kept, in order; of the bytes written since their file system was last synced, a part.
  // Each file's bytes written since then, with its file system and the length a sync made durable
  // (0 for a file written anew).
  std::map<std::shared_ptr<std::string>, std::pair<std::string, size_t>> unsynced;
  int64_t power_left = -1;  // writes until the power goes; -1: it does not
  bool power_off = false;
  int64_t syncs_left = -1;  // syncs until one fails; -1: none does
  std::map<std::string, std::shared_ptr<FileLock>> locks;
  std::set<std::string> mounts;
  bool clones = false;  ///< copy_hashed within a file system says it cloned
  int64_t clones_of_unsynced = 0;
  std::vector<std::string> changed;  ///< every path a change was made at, in order (for watches)

  // The mount point a path lies below (its file system); "" for the root's.
  std::string device_of(const std::string& path) const {
    std::string device;
    for (const auto& m : mounts)
      if ((path == m || path.compare(0, m.size() + 1, m + "/") == 0) && m.size() > device.size()) device = m;
    return device;
  }

  // The path with every symbolic link on the way replaced by its target (the last one only when
  // `follow_last`).
  std::string resolve(const fs::path& path, bool follow_last, int hops = 0) const {
    if (hops > 40) throw FileSystemError(path.string() + ": symbolic link loop");
    const std::vector<std::string> parts = parts_of(path);
    std::string current;
    for (size_t i = 0; i < parts.size(); ++i) {
      const std::string next = current + "/" + parts[i];
      auto it = nodes.find(next);
      const bool last = i + 1 == parts.size();
      if (it != nodes.end() && it->second.type == FileStat::Type::link && (!last || follow_last)) {
        const fs::path& target = it->second.target;
        fs::path joined = target.is_absolute() ? target : fs::path(current.empty() ? "/" : current) / target;
        for (size_t j = i + 1; j < parts.size(); ++j) joined /= parts[j];
        return resolve(joined, follow_last, hops + 1);
      }
      current = next;
    }
    return current.empty() ? "/" : current;
  }

  const Node* find(const std::string& key) const {
    auto it = nodes.find(key);
    return it == nodes.end() ? nullptr : &it->second;
  }

  bool is_folder(const std::string& key) const {
    const Node* n = find(key);
    return key == "/" || (n && n->type == FileStat::Type::folder);
  }

  void make_folders(const std::string& key) {
    std::string current;
    for (const auto& part : parts_of(key)) {
      current += "/" + part;
      auto [it, inserted] = nodes.emplace(current, Node{FileStat::Type::folder, nullptr, {}, ++clock, next_id});
      if (inserted) ++next_id, changed.push_back(current);
      if (it->second.type != FileStat::Type::folder)
        throw FileSystemError(current + ": cannot create folder: " + std::strerror(ENOTDIR));
    }
  }

  void check_power(const fs::path& path) const {
    if (power_off) throw FileSystemError(path.string() + ": cannot change: the power is off");
  }

  // What was not synced is half written back: each file cut in the middle of its bytes written since
  // (a file written anew: half there; a cut that a size check could miss only where nothing was
  // written).
  void lose_power() {
    for (auto& [bytes, durable] : unsynced)
      if (bytes->size() > durable.second) bytes->resize(durable.second + (bytes->size() - durable.second) / 2);
    unsynced.clear();
    power_off = true;
  }

  // `bytes` of the file at `key` are changed from `from` on: what was durable stays so up to there.
  void written(const std::string& key, const std::shared_ptr<std::string>& bytes, size_t from) {
    const auto [it, inserted] = unsynced.emplace(bytes, std::make_pair(device_of(key), from));
    if (!inserted) it->second.second = std::min(it->second.second, from);
  }

  void count_write(const fs::path& path) {
    check_power(path);
    if (power_left == 0) {
      lose_power();
      check_power(path);
    }
    if (power_left > 0) --power_left;
    if (writes_left == 0) throw FileSystemError(path.string() + ": write failed: " + std::strerror(ENOSPC));
    if (writes_left > 0) --writes_left;
    ++writes;
  }

  // The file node at `path` (following links), created empty with its folders when missing.
  Node& file_for_writing(const fs::path& path) {
    const std::string key = resolve(path, true);
    make_folders(fs::path(key).parent_path().string());
    auto [it, inserted] = nodes.emplace(key, Node{FileStat::Type::file, std::make_shared<std::string>(), {}, 0, 0});
    if (inserted) it->second.id = next_id++;
    if (it->second.type != FileStat::Type::file) throw FileSystemError(path.string() + ": cannot write: not a file");
    it->second.mtime = ++clock;
    changed.push_back(key);
    return it->second;
  }

  void erase_below(const std::string& key) {
    changed.push_back(key);
    nodes.erase(nodes.lower_bound(key + "/"), nodes.lower_bound(key + "0"));  // '0' follows '/'
    nodes.erase(key);
  }
};

MemoryFileSystem::MemoryFileSystem() : state_(std::make_shared<State>()) {}
MemoryFileSystem::~MemoryFileSystem() = default;

std::string MemoryFileSystem::read(const fs::path& file) const {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  const Node* n = state_->find(state_->resolve(file, true));
  if (!n) throw InputError(file.string(), "file not found");
  if (n->type != FileStat::Type::file)
    throw InputError(file.string(),
                     n->type == FileStat::Type::folder ? "expected a file, found a folder" : "not a regular file");
  return *n->bytes;
}

void MemoryFileSystem::write(const fs::path& file, std::string_view bytes) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  state_->count_write(file);
  Node& node = state_->file_for_writing(file);
  node.bytes->assign(bytes);
  state_->written(state_->resolve(file, true), node.bytes, 0);
}

void MemoryFileSystem::append(const fs::path& file, std::string_view bytes) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  state_->count_write(file);
  Node& node = state_->file_for_writing(file);
  state_->written(state_->resolve(file, true), node.bytes, node.bytes->size());
  node.bytes->append(bytes);
}

void MemoryFileSystem::write_atomic(const fs::path& file, std::string_view bytes) {
  // As the real one: the bytes synced before the rename makes them the file's.
  const bool replaced = replace_with(*this, file, [&](const fs::path& temp) {
    write(temp, bytes);
    const std::lock_guard<std::mutex> lock(state_->mutex);
    state_->unsynced.erase(state_->nodes.at(state_->resolve(temp, true)).bytes);
  });
  if (!replaced) throw FileSystemError(file.string() + ": cannot replace: it is a folder");
}

void MemoryFileSystem::link(const fs::path& from, const fs::path& to) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  const Node* source = state_->find(state_->resolve(from, true));
  if (!source || source->type != FileStat::Type::file) throw FileSystemError(from.string() + ": cannot link: no file");
  state_->count_write(to);
  const std::string key = state_->resolve(to, false);
  state_->make_folders(fs::path(key).parent_path().string());
  if (state_->find(key)) throw FileSystemError(to.string() + ": cannot link: " + std::strerror(EEXIST));
  state_->nodes[key] = *source;
  state_->changed.push_back(key);
}

void MemoryFileSystem::copy(const fs::path& from, const fs::path& to) {
  std::string bytes;
  try {
    bytes = read(from);
  } catch (const InputError& e) {  // as the real one: what is copied is the run's, not the user's
    throw FileSystemError(to.string() + ": cannot copy " + from.string() + ": " + e.what());
  }
  write(to, bytes);
}

FileSystem::Copied MemoryFileSystem::copy_hashed(const fs::path& from, const fs::path& to) {
  bool unsynced = false;
  {
    const std::lock_guard<std::mutex> lock(state_->mutex);
    const State& s = *state_;
    const auto node = s.nodes.find(s.resolve(from, true));
    unsynced = node != s.nodes.end() && node->second.bytes && s.unsynced.count(node->second.bytes) > 0;
  }
  Copied copied = FileSystem::copy_hashed(from, to);
  const std::lock_guard<std::mutex> lock(state_->mutex);
  State& s = *state_;
  copied.cloned = s.clones && s.device_of(s.resolve(from, true)) == s.device_of(s.resolve(to, true));
  s.clones_of_unsynced += copied.cloned && unsynced;
  return copied;
}

int64_t MemoryFileSystem::clones_of_unsynced() const {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->clones_of_unsynced;
}

void MemoryFileSystem::clone_copies() {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  state_->clones = true;
}

void MemoryFileSystem::mount(const fs::path& folder) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  state_->mounts.insert(state_->resolve(folder, true));
}

bool MemoryFileSystem::rename(const fs::path& from, const fs::path& to) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  State& s = *state_;
  s.check_power(to);
  const std::string source = s.resolve(from, false), target = s.resolve(to, false);
  if (!s.find(source)) throw FileSystemError(from.string() + ": cannot move: " + std::strerror(ENOENT));
  if (!s.is_folder(fs::path(target).parent_path().string()))
    throw FileSystemError(to.string() + ": cannot move here: " + std::strerror(ENOENT));
  if (source == target) return true;
  if (s.device_of(source) != s.device_of(target))
    throw CrossDevice(to.string() + ": cannot move " + from.string() + " here: " + std::strerror(EXDEV));
  if (s.is_folder(target)) {
    auto below = s.nodes.lower_bound(target + "/");
    if (below != s.nodes.end() && below->first.compare(0, target.size() + 1, target + "/") == 0) return false;
  }
  s.erase_below(target);
  std::map<std::string, Node> moved;
  for (auto it = s.nodes.lower_bound(source + "/"); it != s.nodes.lower_bound(source + "0"); ++it)
    moved[target + it->first.substr(source.size())] = it->second;
  moved[target] = s.nodes.at(source);
  s.erase_below(source);
  s.nodes.insert(moved.begin(), moved.end());
  s.changed.push_back(target);
  return true;
}

fs::path MemoryFileSystem::real_path(const fs::path& path) const {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->resolve(path, true);
}

std::vector<std::string> MemoryFileSystem::list(const fs::path& folder) const {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  const std::string key = state_->resolve(folder, true);
  std::vector<std::string> names;
  if (!state_->is_folder(key)) return names;
  const std::string prefix = key == "/" ? "/" : key + "/";
  for (auto it = state_->nodes.lower_bound(prefix); it != state_->nodes.end(); ++it) {
    if (it->first.compare(0, prefix.size(), prefix) != 0) break;
    const std::string rest = it->first.substr(prefix.size());
    if (!rest.empty() && rest.find('/') == std::string::npos) names.push_back(rest);
  }
  return names;
}

FileStat MemoryFileSystem::stat(const fs::path& path, bool follow_link) const {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  const std::string key = state_->resolve(path, follow_link);
  if (key == "/") return {FileStat::Type::folder, 0, 0, 0};
  const Node* n = state_->find(key);
  if (!n) return {};
  return {n->type, n->bytes ? n->bytes->size() : 0, n->mtime, n->id};
}

void MemoryFileSystem::make_folders(const fs::path& folder) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  state_->check_power(folder);
  state_->make_folders(state_->resolve(folder, true));
}

void MemoryFileSystem::remove(const fs::path& path) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  state_->check_power(path);
  state_->erase_below(state_->resolve(path, false));
}

void MemoryFileSystem::sync(const std::vector<fs::path>& paths) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  State& s = *state_;
  std::set<std::string> devices;
  for (const fs::path& path : paths) {
    s.check_power(path);
    devices.insert(s.device_of(s.resolve(path, true)));
  }
  if (s.syncs_left == 0) {
    s.syncs_left = -1;
    throw SyncFailed((paths.empty() ? std::string("/") : paths.front().string()) +
                     ": sync failed: " + std::strerror(EIO));
  }
  if (s.syncs_left > 0) --s.syncs_left;
  for (auto it = s.unsynced.begin(); it != s.unsynced.end();)
    it = devices.count(it->second.first) ? s.unsynced.erase(it) : std::next(it);
  s.syncs += static_cast<int64_t>(devices.size());
}

// Held shared by any number, or by one alone. Let go on any thread, as flock is: the last of a run's
// stages sharing a lock lets go, whichever took it (runtime/stage_locks.h).
struct MemoryFileSystem::FileLock {
  std::mutex mutex;
  std::condition_variable freed;
  int shared = 0;
  bool alone = false;

  bool try_take(bool as_shared) {
    const std::lock_guard<std::mutex> lock(mutex);
    if (!free_for(as_shared)) return false;
    take(as_shared);
    return true;
  }
  void wait_and_take(bool as_shared) {
    std::unique_lock<std::mutex> lock(mutex);
    freed.wait(lock, [&] { return free_for(as_shared); });
    take(as_shared);
  }
  void let_go(bool as_shared) {
    {
      const std::lock_guard<std::mutex> lock(mutex);
      if (as_shared)
        --shared;
      else
        alone = false;
    }
    freed.notify_all();
  }

 private:
  bool free_for(bool as_shared) const { return !alone && (as_shared || shared == 0); }
  void take(bool as_shared) {
    if (as_shared)
      ++shared;
    else
      alone = true;
  }
};

namespace {

class MemoryLock : public FileSystem::Lock {
 public:
  MemoryLock(std::shared_ptr<MemoryFileSystem::FileLock> lock, bool shared) : lock_(std::move(lock)), shared_(shared) {}
  ~MemoryLock() override { lock_->let_go(shared_); }

 private:
  std::shared_ptr<MemoryFileSystem::FileLock> lock_;
  bool shared_;
};

}  // namespace

std::shared_ptr<MemoryFileSystem::FileLock> MemoryFileSystem::file_lock(const fs::path& file) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  auto& slot = state_->locks[file.lexically_normal().string()];
  if (!slot) slot = std::make_shared<FileLock>();
  return slot;
}

std::unique_ptr<FileSystem::Lock> MemoryFileSystem::try_lock(const fs::path& file, bool shared) {
  const std::shared_ptr<FileLock> lock = file_lock(file);
  if (!lock->try_take(shared)) return nullptr;
  return std::make_unique<MemoryLock>(lock, shared);
}

std::unique_ptr<FileSystem::Lock> MemoryFileSystem::lock(const fs::path& file, bool shared,
                                                         const std::function<void()>& on_wait,
                                                         const std::atomic<bool>* stop) {
  const std::shared_ptr<FileLock> lock = file_lock(file);
  const auto take = [&] { return lock->try_take(shared); };
  if (!take()) {
    if (on_wait) on_wait();
    if (!stop)
      lock->wait_and_take(shared);
    else if (!retry_until_stopped(take, *stop))
      return nullptr;
  }
  return std::make_unique<MemoryLock>(lock, shared);
}

// Looks through the paths changed since it began (`seen`, their count then) for one in or at its
// folders.
class MemoryFileSystem::Watch : public FolderWatch {
 public:
  Watch(std::shared_ptr<State> state, std::set<std::string> folders)
      : state_(std::move(state)), seen_(state_->changed.size()), folders_(std::move(folders)) {}

  bool changed() override {
    const std::lock_guard<std::mutex> watch_lock(mutex_);
    const std::lock_guard<std::mutex> lock(state_->mutex);
    changed_ = changed_ || read_changes();
    return changed_;
  }

  // As inotify: a folder of its own removed or moved (a change at its path) is no longer followed.
  bool restart(const std::vector<fs::path>& folders) override {
    const std::lock_guard<std::mutex> watch_lock(mutex_);
    const std::lock_guard<std::mutex> lock(state_->mutex);
    read_changes();
    if (lost_) return false;
    for (const fs::path& folder : folders) {
      const std::string key = state_->resolve(folder, false);
      if (!state_->is_folder(key)) return false;
      folders_.insert(key);
    }
    changed_ = false;
    return true;
  }

 private:
  // The changes made since it last looked: whether one was in or at its folders.
  bool read_changes() {
    bool any = false;
    for (; seen_ < state_->changed.size(); ++seen_) {
      const std::string& path = state_->changed[seen_];
      lost_ = lost_ || folders_.count(path);
      any = any || folders_.count(path) || folders_.count(fs::path(path).parent_path().string());
    }
    return any;
  }

  std::shared_ptr<State> state_;
  std::mutex mutex_;
  size_t seen_;
  std::set<std::string> folders_;
  bool changed_ = false;
  bool lost_ = false;
};

std::unique_ptr<FolderWatch> MemoryFileSystem::watch(const std::vector<fs::path>& folders) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  std::set<std::string> keys;
  for (const fs::path& folder : folders) {
    const std::string key = state_->resolve(folder, false);
    if (!state_->is_folder(key)) return nullptr;
    keys.insert(key);
  }
  return std::make_unique<Watch>(state_, std::move(keys));
}

void MemoryFileSystem::symlink(const fs::path& target, const fs::path& link) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  const std::string key = state_->resolve(link, false);
  state_->make_folders(fs::path(key).parent_path().string());
  state_->nodes[key] = Node{FileStat::Type::link, nullptr, target, ++state_->clock, state_->next_id++};
  state_->changed.push_back(key);
}

void MemoryFileSystem::fail_writes_after(int64_t writes) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  state_->writes_left = writes;
}

void MemoryFileSystem::cut_power_after(int64_t writes) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  state_->power_left = writes;
}

void MemoryFileSystem::fail_sync_after(int64_t syncs) {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  state_->syncs_left = syncs;
}

void MemoryFileSystem::lose_power() {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  state_->lose_power();
}

void MemoryFileSystem::restore_power() {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  state_->power_off = false;
  state_->power_left = -1;
}

int64_t MemoryFileSystem::writes() const {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->writes;
}

int64_t MemoryFileSystem::syncs() const {
  const std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->syncs;
}

void Place::symlink(const fs::path& target, const fs::path& link) {
  if (!real()) return memory_.symlink(target, link);
  fs::create_directories(link.parent_path());
  fs::create_symlink(target, link);
}

}  // namespace olt::test
