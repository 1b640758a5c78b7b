#pragma once
// The cache's stage locks as one run takes them. A lock file is named by the first two digits of a
// stage's key (256 files under CACHE/locks/), so two stages a run makes side by side (`olt watch`'s
// steps) can meet at one file: they share it, locked once for the run, rather than the second
// waiting for the first as if for another process (and saying so). Two stages of the run with one
// key take turns: the second then finds what the first made. Private to the runtime.
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace olt {

class StageLocks {
 public:
  /// The file lock, once held (by the caller's wait for it): a pointer to it, held while it lives.
  using Acquire = std::function<std::shared_ptr<void>()>;

  /// Held until the returned handle goes (on the thread that took it): `key`'s turn in this run, then
  /// lock `name`, from `acquire` unless a stage of this run holds it already. `on_turn_wait` is called
  /// once, before waiting, where a stage of this run with the same key holds the turn.
  std::shared_ptr<void> hold(const std::string& name, const std::string& key, const Acquire& acquire,
                             const std::function<void()>& on_turn_wait = nullptr);

 private:
  // A lock file as the run holds it: taken by one stage at a time, shared once held.
  struct Shared {
    std::mutex taking;
    std::weak_ptr<void> held;
  };
  std::mutex mutex_;                                          // over the two maps (their values stay where they are)
  std::map<std::string, std::unique_ptr<Shared>> files_;      // by lock name
  std::map<std::string, std::unique_ptr<std::mutex>> turns_;  // by key
};

}  // namespace olt
