#pragma once
// What one process keeps in memory between its runs of a job, within one budget: `olt watch`
// relabels the frames that see the edited box edit after edit. Their decoded depth and colour images
// (decoding them is about half of relabeling a frame), and what a stage made (each frame as it
// labeled it, to relabel only where the next edit reaches). `olt run` keeps nothing.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <typeindex>
#include <vector>

#include "olt/core/fs.h"

namespace olt {

/// From now on, keep up to `budget_bytes` of decoded images and values (0, the default: keep none),
/// the least recently read dropped first.
void keep_in_memory(size_t budget_bytes);

/// read_grey16 and read_color through the images kept. An image is found again by its path and its
/// file's size, modification time and inode, so a file replaced or edited is decoded afresh. The
/// images returned may be shared with the keeper and later readers: read them, never write into
/// them. Thread-safe.
cv::Mat remembered_grey16(const fs::path& file);
cv::Mat remembered_color(const fs::path& file);

/// Whether anything is kept (`olt watch`), so a stage need not build what it would keep.
bool keeping_memory();
/// What may be kept, bytes (0: nothing).
size_t memory_budget();

/// What is kept now: its bytes and values, and how many values were dropped, or never kept, so far to
/// stay within the budget (a budget too small for what each cycle reads again drops values every
/// cycle, and those are made again).
struct KeptMemory {
  size_t bytes = 0;   ///< held now, each named value's overhead (named_value_overhead) included
  size_t values = 0;  ///< decoded images and named values held now
  /// Since the process began: let go for the budget, or refused as larger than it, each counting
  /// one (a stage's per-frame list let go whole counts one), and the items of such a list not held
  /// with it (KeptPerItem), one each.
  uint64_t dropped = 0;
};
KeptMemory kept_memory();

/// What a value kept by name takes of the budget besides its own bytes: its name, held twice (in the
/// order of use and in the index), and the keeper's nodes (a frame's counts are ~100 bytes under a
/// name of ~140).
size_t named_value_overhead(const std::string& name);

namespace detail {  // remember and remembered, for any type: a value kept with its type
void remember_any(const std::string& name, std::shared_ptr<const void> value, std::type_index type, size_t bytes);
/// The value kept under `name` if it is of `type`, else null; `take`: no longer kept.
std::shared_ptr<const void> remembered_any(const std::string& name, std::type_index type, bool take = false);
/// Counts `values` not kept for the budget that never reached the keeper (KeptPerItem's items).
void count_not_kept(uint64_t values);
}  // namespace detail

/// A value a stage made, kept under a name of its own within the same budget (`bytes`: what it
/// holds), for the next run in this process (none kept when the budget is 0): `olt watch` keeps
/// each frame's labels, so the next edit relabels only the pixels it reaches. Thread-safe; the value
/// is shared with later readers: make it immutable.
template <class T>
void remember(const std::string& name, std::shared_ptr<const T> value, size_t bytes) {
  detail::remember_any(name, std::move(value), typeid(T), bytes);
}
/// The value kept under `name`, null when none is (never kept, dropped for the budget, or of
/// another type).
template <class T>
std::shared_ptr<const T> remembered(const std::string& name) {
  return std::static_pointer_cast<const T>(detail::remembered_any(name, typeid(T)));
}
/// remembered(name), no longer kept: where the caller then holds the only reference, nobody else
/// reads the value again (the labeling stage labels a frame's images over, rather than copy them).
template <class T>
std::shared_ptr<const T> taken(const std::string& name) {
  return std::static_pointer_cast<const T>(detail::remembered_any(name, typeid(T), true));
}

namespace detail {
template <class T>
struct MadeFrom {  // a value kept with what it was made from
  std::string made_of;
  std::shared_ptr<const T> value;
};
}  // namespace detail

/// The value kept under `name` if it was made from `made_of` (a digest of its inputs), else null.
template <class T>
std::shared_ptr<const T> remembered_from(const std::string& name, const std::string& made_of) {
  const auto kept = remembered<detail::MadeFrom<T>>(name);
  return kept && kept->made_of == made_of ? kept->value : nullptr;
}
/// `value`, made from `made_of`, kept under `name` in place of what was kept there: one value a name
/// however often its inputs change. (Named by the digest instead, every edit's value would stay kept
/// in `olt watch` until the budget is full.)
template <class T>
void remember_from(const std::string& name, std::string made_of, std::shared_ptr<const T> value, size_t bytes) {
  const size_t own = sizeof(detail::MadeFrom<T>) + made_of.size();
  remember<detail::MadeFrom<T>>(
      name, std::make_shared<const detail::MadeFrom<T>>(detail::MadeFrom<T>{std::move(made_of), std::move(value)}),
      bytes + own);
}

/// What remember_from kept under `name`, no longer kept (its entry let go, say).
template <class T>
void forget_from(const std::string& name) {
  taken<detail::MadeFrom<T>>(name);
}

/// The value kept under `name` when it was made from `made_of`, else `make()`, kept in its place for
/// the next run (`bytes_of` says what it holds) when anything is kept and `made_of` is not empty (an
/// input without a digest is not kept): what a stage derives from an input that an edit seldom
/// changes (the report's decoded scene, by its digest), made once per `olt watch`.
template <class T, class Make, class Bytes>
std::shared_ptr<const T> remembered_or_made(const std::string& name, const std::string& made_of, const Make& make,
                                            const Bytes& bytes_of) {
  const bool keep = !made_of.empty() && keeping_memory();
  if (keep)
    if (auto kept = remembered_from<T>(name, made_of)) return kept;
  auto made = std::make_shared<const T>(make());
  if (keep) remember_from<T>(name, made_of, made, bytes_of(*made));
  return made;
}

/// What a run makes per item (per frame), kept for the next run in this process as one list under
/// `name`, each item with what it was made from: the next run takes item i again where it is made
/// from the same. One lookup of the keeper a run, not one an item: at 10,000 frames the items'
/// lookups contended for its lock. made_or_before is called by one thread per item, in any order;
/// the items are held, up to the budget (the rest made again next run), until remember_all. While a
/// run makes its list, the last run's is held too: the budget bounds what is kept between runs.
/// `made_of_all`: what every item is made from besides its own (the list of the last run made from
/// other is not taken from, and this run's replaces it under the same name).
template <class T>
class KeptPerItem {
 public:
  KeptPerItem(std::string name, size_t items, std::string made_of_all = {})
      : name_(std::move(name)), made_of_all_(std::move(made_of_all)), keeping_(keeping_memory()) {
    if (!keeping_) return;
    before_ = remembered_from<List>(name_, made_of_all_);
    now_.resize(items);
    held_ = sizeof(List) + items * sizeof(Item) + named_value_overhead(name_);
  }
  /// Item i as the last run made it from `made_of`, else `make()` (`bytes_of`: what it holds).
  template <class Make, class Bytes>
  std::shared_ptr<const T> made_or_before(size_t i, std::string made_of, const Make& make, const Bytes& bytes_of) {
    if (!keeping_) return std::make_shared<const T>(make());
    std::shared_ptr<const T> value;
    size_t bytes = 0;
    if (before_ && i < before_->size() && (*before_)[i].value && (*before_)[i].made_of == made_of) {
      value = (*before_)[i].value;
      bytes = (*before_)[i].bytes;
    } else {
      value = std::make_shared<const T>(make());
      bytes = bytes_of(*value);
    }
    // Held for the next run while the list stays within the budget (counted as remember_all counts it).
    const size_t adds = bytes + made_of.capacity();
    if (held_.fetch_add(adds) + adds <= memory_budget()) {
      now_.at(i) = {std::move(made_of), value, bytes};
    } else {
      held_.fetch_sub(adds);
      ++not_held_;  // made again next run: told in kept_memory().dropped by remember_all
    }
    return value;
  }
  /// The items made or taken this run, kept for the next (once each item's made_or_before is done);
  /// the last call of this run's list.
  void remember_all() {
    if (!keeping_) return;
    keeping_ = false;
    size_t bytes = sizeof(List) + now_.capacity() * sizeof(Item);
    for (const Item& item : now_)
      if (item.value) bytes += item.bytes + item.made_of.capacity();
    remember_from<List>(name_, made_of_all_, std::make_shared<const List>(std::move(now_)), bytes);
    detail::count_not_kept(not_held_);
  }

 private:
  struct Item {
    std::string made_of;
    std::shared_ptr<const T> value;
    size_t bytes = 0;
  };
  using List = std::vector<Item>;
  std::string name_, made_of_all_;
  bool keeping_;
  std::shared_ptr<const List> before_;
  List now_;
  std::atomic<size_t> held_{0};        ///< what now_ holds and the keeper adds, bytes
  std::atomic<uint64_t> not_held_{0};  ///< items this run made or took but could not hold
};

}  // namespace olt
