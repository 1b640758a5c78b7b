#pragma once
// Process-wide allocator setting for image work.

namespace olt {

/// Keeps freed memory in the process instead of returning it to the system. Every frame
/// allocates and frees a few megabytes of images; by default glibc maps such blocks fresh from the
/// kernel each time, and the page faults of touching them cost more than the labeling itself
/// (3.5 ms of a 640x480 frame's 3.6 ms on this project's VMs). With this, they are reused.
void keep_freed_memory();

/// Returns the memory kept that way to the system: between stages, so that what one stage freed
/// does not add to the next one's peak (a 10,000-observation labeling stage leaves ~130 MB).
void return_freed_memory();

}  // namespace olt
