#include "stage_locks.h"

namespace olt {

StageLock StageLocks::hold(const std::string& name, const std::string& key, const Acquire& acquire,
                           const std::function<void()>& on_turn_wait) {
  std::mutex* turn = nullptr;
  Shared* file = nullptr;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    auto& t = turns_[key];
    if (!t) t = std::make_unique<std::mutex>();
    turn = t.get();
    auto& f = files_[name];
    if (!f) f = std::make_unique<Shared>();
    file = f.get();
  }
  // The turn first, then the file: a stage waiting for its turn holds no file lock meanwhile. The
  // file is let go under `taking`, as it is taken: a stage that finds it let go knows it unlocked, so
  // locks it again without meeting the lock and saying it waits for another process.
  struct Held {
    Shared* shared = nullptr;
    std::unique_lock<std::mutex> turn;
    std::shared_ptr<void> file;
    Held() = default;
    Held(const Held&) = delete;
    Held& operator=(const Held&) = delete;
    ~Held() {
      const std::lock_guard<std::mutex> taking(shared->taking);
      file.reset();
    }  // then the turn
  };
  auto held = std::make_shared<Held>();
  held->shared = file;
  held->turn = std::unique_lock<std::mutex>(*turn, std::try_to_lock);
  if (!held->turn.owns_lock()) {
    if (on_turn_wait) on_turn_wait();
    held->turn.lock();
  }
  // One stage takes the file at a time: one waiting for another process holds back the stages
  // beside it that would share it, which would wait all the same.
  const std::lock_guard<std::mutex> taking(file->taking);
  held->file = file->held.lock();
  if (!held->file) {
    held->file = acquire();
    file->held = held->file;
  }
  return StageLock(std::move(held));
}

}  // namespace olt
