#pragma once
// An allocator for large lists a run holds from stage to stage.
#include <cstddef>
#include <new>

namespace olt {

/// `bytes` straight from the system (anonymous pages; the whole huge pages among them advised,
/// olt/core/huge_pages.h), and back.
void* map_pages(std::size_t bytes);
void unmap_pages(void* at, std::size_t bytes);

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
