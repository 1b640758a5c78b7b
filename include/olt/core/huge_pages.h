#pragma once
// Huge pages for large buffers: a buffer filled at once (a 19 MB scene read and decoded) takes a page
// fault per huge page (2 MB on x86-64), not per 4 KB page. On the project's virtual machine a 4 KB
// fault costs some 15 us: 70 ms for those 19 MB, against 5 ms in huge pages.
#include <cstddef>

namespace olt {

/// The kernel's huge page size (its transparent huge pages' size, read once), 2 MB where it does
/// not say.
std::size_t huge_page_bytes();

/// Asks the kernel to back the whole huge pages inside [at, at + bytes) with huge pages; nothing
/// outside the range is touched, and a range that holds no whole huge page is left as it is. Call
/// it before the pages are first written: pages already there stay small. Heap memory may be
/// advised too (the advice then stays with that part of the heap after the buffer is freed, and
/// may back its later, smaller blocks with huge pages); where the kernel has no transparent huge
/// pages, or has them for everything already, nothing changes.
void advise_huge_pages(void* at, std::size_t bytes);

}  // namespace olt
