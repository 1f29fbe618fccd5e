// Where the streamed method (method.h DecomposeAndModel) keeps each component's samples between
// the decomposition and the filters, and the filtered components the caller wants to store:
// holding every IMF of a long recording in memory at once is what made a day at 1 kHz need tens
// of gigabytes. The pipeline's store spills them to a scratch file (pipeline/graph/
// spill_store.h); MemoryComponentStore keeps them in memory (tests, small tools).
#pragma once

#include <Eigen/Core>
#include <map>
#include <mutex>
#include <utility>

namespace fogpipe::method {

class ComponentStore {
 public:
  /// kSignal: the preprocessed signal (k = 0) while the EMD runs on its array.
  enum class Kind { kComponent, kFiltered, kSignal };
  virtual ~ComponentStore() = default;
  /// Keeps x as column k of `kind` (k = 0 .. num_imfs, the residue last). Called from several
  /// threads at once, each with its own (kind, k); a column is put once.
  virtual void Put(Kind kind, int k, const Eigen::VectorXd& x) = 0;
  /// Column k of `kind` into *x (resized to its length). Throws std::runtime_error when it was
  /// never put or cannot be read back. Thread-safe.
  virtual void Get(Kind kind, int k, Eigen::VectorXd* x) const = 0;
  /// Whether column k of `kind` was put (and not released).
  virtual bool Has(Kind kind, int k) const = 0;
  /// The caller reads column k of `kind` no more: its space may be given back at once (a later
  /// Get throws as for a column never put). Nothing if it is not stored. Thread-safe.
  virtual void Release(Kind kind, int k) = 0;
};

/// A ComponentStore in memory.
class MemoryComponentStore : public ComponentStore {
 public:
  void Put(Kind kind, int k, const Eigen::VectorXd& x) override;
  void Get(Kind kind, int k, Eigen::VectorXd* x) const override;
  bool Has(Kind kind, int k) const override;
  void Release(Kind kind, int k) override;

 private:
  mutable std::mutex mutex_;
  std::map<std::pair<Kind, int>, Eigen::VectorXd> columns_;
};

}  // namespace fogpipe::method
