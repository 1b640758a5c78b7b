#pragma once
// An allocator for large lists a run holds from stage to stage.
#include <cstddef>
#include <new>

namespace olt {

/// `bytes` straight from the system (anonymous pages; the whole huge pages among them advised,
/// olt/core/huge_pages.h), and back; or, while blocks freed are kept (keep_freed_pages), a block of
/// that many pages freed before, whose pages are there already.
void* map_pages(std::size_t bytes);
void unmap_pages(void* at, std::size_t bytes);

/// From now on, keep blocks unmap_pages is given, up to `bytes` in all, for map_pages to hand out
/// again (0, the default: each goes back to the system at once; blocks kept beyond a lower limit go
/// back now). A first write to a fresh 4 KB page costs some 15 us on the project's virtual machine,
/// and `olt watch` makes the same lists again each cycle (a stage's 2,240 files at 320 frames, in
/// blocks of the same sizes): mapped afresh, they were 150 of a cycle's 220 page faults.
void keep_freed_pages(std::size_t bytes);
/// What blocks kept for reuse hold now, bytes.
std::size_t freed_pages_kept();

/// For a large list a run holds from stage to stage (an artifact's 70,000 files at 10,000 frames):
/// its blocks of 64 KB and more are pages of their own, not the heap's. In the heap, such a list
/// grows among what a stage allocates and frees, and what it left in the middle stayed with the
/// process after the stage (keep_freed_memory) and could not go back to the system.
template <typename T>
struct PageAllocator {
  using value_type = T;
  static constexpr std::size_t kPagesFrom = 64 << 10;  ///< bytes

  PageAllocator() = default;
  template <typename U>
  PageAllocator(const PageAllocator<U>&) {}  // NOLINT(google-explicit-constructor): rebinding
  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    return static_cast<T*>(bytes >= kPagesFrom ? map_pages(bytes) : ::operator new(bytes));
  }
  void deallocate(T* at, std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes >= kPagesFrom)
      unmap_pages(at, bytes);
    else
      ::operator delete(at);
  }
  template <typename U>
  bool operator==(const PageAllocator<U>&) const {
    return true;
  }
  template <typename U>
  bool operator!=(const PageAllocator<U>&) const {
    return false;
  }
};

}  // namespace olt
