#include "algorithms/method/component_store.h"

#include <stdexcept>
#include <string>

namespace fogpipe::method {

void MemoryComponentStore::Put(Kind kind, int k, const Eigen::VectorXd& x) {
  std::lock_guard<std::mutex> lock(mutex_);
  columns_[{kind, k}] = x;
}

void MemoryComponentStore::Get(Kind kind, int k, Eigen::VectorXd* x) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = columns_.find({kind, k});
  if (it == columns_.end())
    throw std::runtime_error("component store: column " + std::to_string(k) + " was never stored");
  *x = it->second;
}

bool MemoryComponentStore::Has(Kind kind, int k) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return columns_.count({kind, k}) > 0;
}

void MemoryComponentStore::Release(Kind kind, int k) {
  std::lock_guard<std::mutex> lock(mutex_);
  columns_.erase({kind, k});
}

}  // namespace fogpipe::method
