#include "features/buffer_pool.h"

#include <sys/mman.h>

#include <cstdlib>
#include <deque>
#include <new>
#include <map>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/core/mat.hpp>

namespace pgba {
namespace {

constexpr size_t kMinPooledBytes = size_t(1) << 20;
// Blocks from this size on are 2 MiB aligned and advised as transparent huge pages: on the
// project's VM each 4 KiB page fault costs tens of microseconds (perf: half of a first
// image's SIFT time in the kernel's fault path), and a 2 MiB page replaces 512 of them.
constexpr size_t kHugePage = size_t(2) << 20;
constexpr size_t kMinHugeBytes = size_t(4) << 20;

uchar* Allocate(size_t n) {
  if (n < kMinHugeBytes) return static_cast<uchar*>(cv::fastMalloc(n));
  const size_t rounded = (n + kHugePage - 1) / kHugePage * kHugePage;
  void* p = std::aligned_alloc(kHugePage, rounded);
  if (p == nullptr) throw std::bad_alloc();
  madvise(p, rounded, MADV_HUGEPAGE);  // advice only: without THP it is 4 KiB pages
  return static_cast<uchar*>(p);
}

void Free(uchar* p, size_t n) {
  if (n < kMinHugeBytes)
    cv::fastFree(p);
  else
    std::free(p);
}

// cv::MatAllocator with OpenCV's standard layout (continuous rows, cv::fastMalloc'ed), whose
// large blocks go back to a free list instead of the system while the pool is enabled.
// Blocks allocated while enabled and freed after it was disabled are simply freed.
class PoolingMatAllocator : public cv::MatAllocator {
 public:
  cv::UMatData* allocate(int dims, const int* sizes, int type, void* data0, size_t* step, cv::AccessFlag,
                         cv::UMatUsageFlags) const override {
    size_t total = CV_ELEM_SIZE(type);
    for (int i = dims - 1; i >= 0; --i) {
      if (step) {
        if (data0 && step[i] != cv::Mat::AUTO_STEP) {
          total = step[i];
        } else {
          step[i] = total;
        }
      }
      total *= sizes[i];
    }
    cv::UMatData* u = new cv::UMatData(this);
    u->data = u->origdata = data0 ? static_cast<uchar*>(data0) : Take(total);
    u->size = total;
    if (data0) u->flags |= cv::UMatData::USER_ALLOCATED;
    return u;
  }
  bool allocate(cv::UMatData* u, cv::AccessFlag, cv::UMatUsageFlags) const override { return u != nullptr; }
  void deallocate(cv::UMatData* u) const override {
    if (!u) return;
    if (!(u->flags & cv::UMatData::USER_ALLOCATED)) Give(u->origdata, u->size);
    delete u;
  }

  void Enable(size_t max_retained_bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    enabled_ = true;
    max_retained_ = max_retained_bytes;
  }
  void DisableAndRelease() {
    std::lock_guard<std::mutex> lock(mutex_);
    enabled_ = false;
    while (!order_.empty()) EvictOldest();
  }

 private:
  uchar* Take(size_t n) const {
    if (n >= kMinPooledBytes) {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto it = free_.find(n);
      if (it != free_.end() && !it->second.empty()) {
        uchar* p = it->second.back();
        it->second.pop_back();
        retained_ -= n;
        for (auto o = order_.begin(); o != order_.end(); ++o)
          if (o->second == p) {
            order_.erase(o);
            break;
          }
        return p;
      }
    }
    return Allocate(n);
  }
  void Give(uchar* p, size_t n) const {
    if (n >= kMinPooledBytes) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (enabled_ && n <= max_retained_) {
        while (retained_ + n > max_retained_) EvictOldest();
        free_[n].push_back(p);
        order_.emplace_back(n, p);
        retained_ += n;
        return;
      }
    }
    Free(p, n);
  }
  // Frees the longest-retained block (mutex held).
  void EvictOldest() const {
    const auto [n, p] = order_.front();
    order_.pop_front();
    auto& list = free_[n];
    for (auto it = list.begin(); it != list.end(); ++it)
      if (*it == p) {
        list.erase(it);
        break;
      }
    retained_ -= n;
    Free(p, n);
  }

  mutable std::mutex mutex_;
  mutable std::map<size_t, std::vector<uchar*>> free_;
  mutable std::deque<std::pair<size_t, uchar*>> order_;  // retained blocks, oldest first
  mutable size_t retained_ = 0;
  bool enabled_ = false;
  size_t max_retained_ = 0;
};

// Never destroyed: Mats allocated through it may be freed at any time, even at exit.
PoolingMatAllocator& Pool() {
  static PoolingMatAllocator* pool = new PoolingMatAllocator();
  return *pool;
}

cv::MatAllocator* previous_allocator = nullptr;

}  // namespace

ScopedImageBufferPool::ScopedImageBufferPool(size_t max_retained_bytes) {
  Pool().Enable(max_retained_bytes);
  previous_allocator = cv::Mat::getDefaultAllocator();
  cv::Mat::setDefaultAllocator(&Pool());
}

ScopedImageBufferPool::~ScopedImageBufferPool() {
  cv::Mat::setDefaultAllocator(previous_allocator);
  Pool().DisableAndRelease();
}

}  // namespace pgba
