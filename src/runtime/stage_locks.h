#pragma once
// The cache's stage locks as one run takes them. A lock file is named by the first two hex digits of
// a stage's key (256 files under CACHE/locks/), so two stages a run makes side by side (`olt
// watch`'s steps) can meet at one file: they share it, locked once for the run, rather than the
// second waiting for the first as if for another process (and saying so). Two stages of the run with
// one key take turns: the second then finds what the first made. Private to the runtime.
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace olt {

/// A stage's hold on its lock (StageLocks::hold), until it goes; moved, never copied: it is let go
/// on the thread that took it (the key's turn is a mutex of that thread's).
class StageLock {
 public:
  StageLock() = default;
  explicit StageLock(std::shared_ptr<void> held) : held_(std::move(held)) {}
  StageLock(StageLock&&) = default;
  StageLock& operator=(StageLock&&) = default;
  StageLock(const StageLock&) = delete;
  StageLock& operator=(const StageLock&) = delete;

 private:
  std::shared_ptr<void> held_;
};

class StageLocks {
 public:
  /// Waits for the lock file and returns it held: a pointer (never null) that holds it while it
  /// lives, let go on whichever thread lets go of it last.
  using Acquire = std::function<std::shared_ptr<void>()>;

  /// `key`'s turn in this run, then lock `name`: from `acquire` unless a stage of this run holds it
  /// already. `on_turn_wait` is called once, before waiting, where a stage of this run with the same
  /// key has the turn. What `acquire` throws (a stop) leaves both free.
  StageLock hold(const std::string& name, const std::string& key, const Acquire& acquire,
                 const std::function<void()>& on_turn_wait = nullptr);

 private:
  // A lock file as the run holds it: taken and let go by one stage at a time, shared while held.
  struct Shared {
    std::mutex taking;
    std::weak_ptr<void> held;
  };
  std::mutex mutex_;  // over the two maps; their values are never removed, and stay where they are
  std::map<std::string, std::unique_ptr<Shared>> files_;      // by lock name
  std::map<std::string, std::unique_ptr<std::mutex>> turns_;  // by key
};

}  // namespace olt
