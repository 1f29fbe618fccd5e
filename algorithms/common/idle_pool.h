// Work memory kept between the tasks that use it: an object given back is handed to the next
// task that asks, instead of being freed and allocated again. Freshly allocated large arrays are
// fresh pages, which cost about as much as the arithmetic done in them on the machines fogpipe
// runs on (docs/performance.md). Taking and giving are thread-safe.
#pragma once

#include <cstddef>
#include <iterator>
#include <limits>
#include <mutex>
#include <utility>
#include <vector>

namespace fogpipe {

template <typename T>
class IdlePool {
 public:
  /// Keeps at most `capacity` idle objects; one given back beyond that is dropped. Unbounded by
  /// default: the pool then holds at most what was in use at once.
  explicit IdlePool(std::size_t capacity = std::numeric_limits<std::size_t>::max())
      : capacity_(capacity) {}

  /// The most recently given idle object for which fits(object) holds, else T().
  template <typename Fits>
  T Take(const Fits& fits) {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = idle_.rbegin(); it != idle_.rend(); ++it) {
      if (!fits(*it)) continue;
      T t = std::move(*it);
      idle_.erase(std::next(it).base());
      return t;
    }
    return T();
  }
  /// The most recently given idle object, else T().
  T Take() {
    return Take([](const T&) { return true; });
  }
  /// Keeps *t for the next Take (or drops it when the pool is full); *t is left as T().
  void Give(T* t) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (idle_.size() < capacity_) idle_.push_back(std::move(*t));
    }
    *t = T();
  }
  /// Frees every idle object.
  void Release() {
    const std::lock_guard<std::mutex> lock(mutex_);
    idle_.clear();
  }

 private:
  std::size_t capacity_;
  std::mutex mutex_;
  std::vector<T> idle_;
};

}  // namespace fogpipe
