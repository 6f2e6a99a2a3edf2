// Reuse of OpenCV's large image buffers from one image to the next during feature
// extraction. SIFT's scale space of a 6 MP photo is ~1.5 GB of float images (the 2x
// upsampled first octave alone is 25 MP per layer); the default allocator returns each
// buffer to the system when the image is done and the next image faults the same amount of
// fresh pages in again. Measured on the 2-core VM of the project (fountain_p11 0005.jpg,
// one thread, same output): 7.6-16.7 s per image with the default allocator, 1.9-2.1 s once
// the pool holds the buffers of the previous image. Buffers are reused by exact size, so a
// folder of same-sized photos reaches a steady state after the first image per thread.
#pragma once

#include <cstddef>

namespace pgba {

// While alive, every cv::Mat of at least 1 MiB allocated by any thread takes and returns its
// memory through a process-wide pool that keeps up to `max_retained_bytes` of freed buffers;
// on destruction the default allocator is restored and the retained buffers are freed.
// Instances must not overlap (one extraction at a time); output is unaffected.
class ScopedImageBufferPool {
 public:
  explicit ScopedImageBufferPool(size_t max_retained_bytes);
  ~ScopedImageBufferPool();
  ScopedImageBufferPool(const ScopedImageBufferPool&) = delete;
  ScopedImageBufferPool& operator=(const ScopedImageBufferPool&) = delete;
};

}  // namespace pgba
