#include "algorithms/method/method.h"

#include <algorithm>
#include <deque>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>
#include <utility>

#include "algorithms/allan/model_edf.h"
#include "algorithms/common/idle_pool.h"
#include "algorithms/method/white_noise.h"

namespace fogpipe::method {
namespace {

void Fail(MethodResult* result, Termination termination, const std::string& message) {
  result->summary.termination = termination;
  result->summary.message = message;
}

}  // namespace

bool MethodOptions::IsValid(std::string* error) const {
  std::string detail;
  auto fail = [&](const std::string& what) {
    if (error) *error = what + (detail.empty() ? "" : ": " + detail);
    return false;
  };
  if (!preprocess.IsValid(&detail)) return fail("preprocess");
  if (!emd.IsValid(&detail)) return fail("emd");
  if (!band_limit.IsValid(&detail)) return fail("band_limit");
  if (!component.ar.IsValid(&detail)) return fail("ar");
  if (!component.kalman.IsValid(&detail)) return fail("kalman");
  if (direct_ar_order < 0) return fail("direct_ar_order must be >= 0 (0 = by BIC)");
  if (!allan.IsValid(&detail)) return fail("allan");
  if (!noise_fit.IsValid(&detail)) return fail("noise_fit");
  if (!reference.IsValid(&detail)) return fail("reference");
  return true;
}

void SerialForEach(int n, const std::function<void(int)>& body) {
  for (int i = 0; i < n; ++i) body(i);
}

std::string ComponentName(int index, int num_imfs) {
  return index < num_imfs ? "imf" + std::to_string(index + 1) : "residue";
}

namespace {

/// Step 1 into result->preprocessed; false (with the failure in the summary) when it failed.
bool PreprocessStep(const Eigen::VectorXd& x, double sample_rate_hz, const MethodOptions& options,
                    MethodResult* result) {
  result->preprocessed = Preprocess(x, sample_rate_hz, options.preprocess);
  const PreprocessSummary& pre = result->preprocessed.summary;
  if (HasResult(pre.termination)) return true;
  Fail(result, pre.termination, "preprocessing: " + pre.message);
  return false;
}

/// After the EMD (and the band limit): the failure in the summary, or the decomposition noted.
bool NoteDecomposition(const MethodOptions& options, MethodResult* result) {
  const emd::EmdSummary& emd_summary = result->decomposition.summary;
  if (!HasResult(emd_summary.termination)) {
    Fail(result, emd_summary.termination, "EMD: " + emd_summary.message);
    return false;
  }
  result->band_limit_ratio = options.band_limit.cutoff_ratio;
  result->summary.num_imfs = static_cast<int>(result->decomposition.imf_info.size());
  result->summary.termination = Termination::kSuccess;
  return true;
}

}  // namespace

void PreprocessAndDecompose(const Eigen::VectorXd& x, double sample_rate_hz,
                            const MethodOptions& options, MethodResult* result) {
  std::string error;
  if (!options.IsValid(&error)) return Fail(result, Termination::kInvalidOptions, error);
  if (!PreprocessStep(x, sample_rate_hz, options, result)) return;
  result->decomposition = emd::Decompose(result->preprocessed.signal, options.emd);
  if (HasResult(result->decomposition.summary.termination))
    BandLimitImfs(options.band_limit, &result->decomposition);
  NoteDecomposition(options, result);
}

bool StreamOptions::IsValid(std::string* error) const {
  if (components_in_flight < 1) {
    if (error) *error = "components_in_flight must be >= 1";
    return false;
  }
  return true;
}

namespace {

/// The IMFs as EMD hands them on (emd::ImfSink): band limited, kept (in the store; without one,
/// in memory), their variances noted and their AR fits started. With a store at most
/// components_in_flight of them are in memory at once.
class ImfStream {
 public:
  ImfStream(const MethodOptions& options, const StreamOptions& stream)
      : options_(options),
        stream_(stream),
        limiter_(options.band_limit),
        buffers_(stream.store ? stream.components_in_flight : 0),
        idle_work_(static_cast<std::size_t>(std::max(0, stream.components_in_flight))) {
    for (int slot = 0; slot < stream.components_in_flight; ++slot) {
      limit_groups_.push_back(MakeTaskGroup(stream.tasks));
      fit_groups_.push_back(MakeTaskGroup(stream.tasks));
    }
  }
  ~ImfStream() {
    // Every task ends before the members it uses go: each group is waited for, whatever the
    // others rethrow.
    try {
      WaitLimited(std::numeric_limits<int>::max() - 1);
    } catch (...) {
    }
    for (auto* groups : {&limit_groups_, &fit_groups_}) {
      for (std::unique_ptr<TaskGroup>& group : *groups) {
        try {
          group->Wait();
        } catch (...) {
        }
      }
    }
  }

  /// On the EMD's thread: copies IMF k and queues its band limit; the sifting of the next IMF
  /// goes on meanwhile.
  void Take(int k, const Eigen::VectorXd& imf, const emd::ImfInfo& info) {
    if (Failed()) WaitAll();  // rethrows the failure: the EMD stops here
    Eigen::VectorXd* c = nullptr;
    const int slot = k % stream_.components_in_flight;
    if (stream_.store == nullptr) {
      kept_.emplace_back(imf);
      c = &kept_.back();
    } else {
      // The slot's buffer is reused once its component (k - components_in_flight) is band limited,
      // stored and fitted; the later components already taken go on meanwhile. Its band limit is
      // waited for first: that is the task that starts its fit.
      if (k >= stream_.components_in_flight) {
        WaitLimited(k - stream_.components_in_flight);
        if (Failed()) WaitAll();  // rethrows: the EMD stops before sifting another IMF
        fit_groups_[slot]->Wait();
      }
      buffers_[slot] = imf;
      c = &buffers_[slot];
    }
    infos_.push_back(info);
    variances_.push_back(0.0);
    fits_.emplace_back();
    Queue({k, slot, c, &infos_.back(), &variances_.back(), &fits_.back()});
  }

  /// After the EMD: every fit finished, and after a decomposition the last IMF's leakage in the
  /// residue.
  void Finish(bool decomposed, Eigen::VectorXd* residue) {
    WaitAll();
    idle_work_.Release();
    if (decomposed) limiter_.Finish(residue);
  }

  struct Prefit {
    ar::ArFit fit;
    bool done = false;
  };

 private:
  /// An IMF waiting for its band limit; the pointers stay valid (deques, buffers_).
  struct Pending {
    int k = 0;
    int slot = 0;  // k % components_in_flight
    Eigen::VectorXd* component = nullptr;
    emd::ImfInfo* info = nullptr;
    double* variance = nullptr;
    Prefit* fit = nullptr;
  };

  /// The band limit is a chain (IMF k receives the leakage of IMF k - 1), so the pending IMFs are
  /// limited in order, one task each, each task starting the next (in the group of the next
  /// one's slot, so that a wait for one component's band limit is a wait on its slot's group),
  /// while the EMD's thread sifts the next IMF; each limited component's AR fit is then a task of
  /// its own. The order of the arithmetic is that of a serial run, so the results do not depend
  /// on the schedule.
  void Queue(const Pending& pending) {
    {
      std::lock_guard<std::mutex> lock(queue_mutex_);
      if (failed_) return;
      queue_.push_back(pending);
      if (limiting_) return;  // the running chain takes it
      limiting_ = true;
      chain_slot_ = pending.slot;
    }
    limit_groups_[pending.slot]->Run([this] { LimitNext(); });
  }

  /// Returns once component k is band limited (and its fit started), or the chain failed. Waits
  /// on the group of the component the chain is at, as often as the chain moves on: a wait on a
  /// task group runs other tasks meanwhile, where a blocking wait could hold the last free thread.
  /// (The chain names the next slot before it starts the task there: a wait that finds that
  /// group still empty yields instead of spinning.)
  void WaitLimited(int k) {
    int seen_limited = -1, seen_slot = -1;
    for (;;) {
      int slot = 0, limited = 0;
      {
        std::lock_guard<std::mutex> lock(queue_mutex_);
        if (failed_ || limited_ > k || !limiting_) return;
        slot = chain_slot_;
        limited = limited_;
      }
      if (limited == seen_limited && slot == seen_slot) std::this_thread::yield();
      seen_limited = limited;
      seen_slot = slot;
      limit_groups_[slot]->Wait();
    }
  }

  /// The band limit chain to its end first: it starts the fits. Then every group, which rethrows
  /// a failure.
  void WaitAll() {
    WaitLimited(std::numeric_limits<int>::max() - 1);  // returns once the chain is idle
    for (std::unique_ptr<TaskGroup>& group : limit_groups_) group->Wait();
    for (std::unique_ptr<TaskGroup>& group : fit_groups_) group->Wait();
  }

  /// A failed component fails the decomposition (its task group rethrows at the next Wait):
  /// nothing more is queued or limited, and the EMD stops at its next IMF (Take).
  void Fail() {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    failed_ = true;
    limiting_ = false;
    queue_.clear();
  }

  bool Failed() {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    return failed_;
  }

  /// The chain's task for the component at the front of the queue.
  void LimitNext() {
    Pending p;
    {
      std::lock_guard<std::mutex> lock(queue_mutex_);
      // A fit that failed meanwhile (Fail) emptied the queue: the chain ends here.
      if (failed_ || queue_.empty()) {
        limiting_ = false;
        return;
      }
      p = queue_.front();
      queue_.pop_front();
    }
    try {
      limiter_.Next(p.component, p.info);
      *p.variance = ComponentVariance(*p.component);
      if (stream_.store) stream_.store->Put(ComponentStore::Kind::kComponent, p.k, *p.component);
    } catch (...) {
      Fail();
      throw;
    }
    fit_groups_[p.slot]->Run([this, k = p.k, c = p.component, fit = p.fit] {
      if (IsConstantComponent(*c)) return;  // ModelComponent passes it through unfitted
      // A failed fit (a store that cannot read back, no memory) fails the decomposition as a
      // failed band limit does; a serial group runs this task inside the chain's, which the
      // throw then leaves.
      try {
        std::unique_ptr<ar::ArWork> work = TakeWork();
        if (stream_.store) {
          // The component is in the store: its buffer serves as Burg's forward error array and
          // is read back for the diagnostics (the slot's next component overwrites it anyway).
          fit->fit =
              ar::FitArInPlace(c, options_.component.ar, work.get(), [this, k](Eigen::VectorXd* x) {
                stream_.store->Get(ComponentStore::Kind::kComponent, k, x);
              });
        } else {
          fit->fit = ar::FitAr(*c, options_.component.ar, work.get());
        }
        fit->done = true;
        ReturnWork(std::move(work));
      } catch (...) {
        Fail();
        throw;
      }
    });
    int next_slot = -1;
    {
      std::lock_guard<std::mutex> lock(queue_mutex_);
      ++limited_;
      if (queue_.empty()) {
        limiting_ = false;
      } else {
        next_slot = chain_slot_ = queue_.front().slot;
      }
    }
    if (next_slot >= 0) limit_groups_[next_slot]->Run([this] { LimitNext(); });
  }

  /// The work arrays of a fit: a set kept from an earlier fit when one is free. Every component
  /// has the record's length, so the arrays are reused as they are. At most components_in_flight
  /// idle sets are kept (N doubles each with a store, whose fits use the component's own buffer
  /// as the second array; 2 N without), as many as the fits that run at once would allocate, and
  /// they are released when the EMD ends.
  std::unique_ptr<ar::ArWork> TakeWork() {
    std::unique_ptr<ar::ArWork> work = idle_work_.Take();
    return work ? std::move(work) : std::make_unique<ar::ArWork>();
  }
  void ReturnWork(std::unique_ptr<ar::ArWork> work) { idle_work_.Give(&work); }

 public:
  const MethodOptions& options_;
  const StreamOptions& stream_;
  BandLimiter limiter_;
  std::vector<std::unique_ptr<TaskGroup>> limit_groups_;  // the band limit chain, per slot
  std::vector<std::unique_ptr<TaskGroup>> fit_groups_;    // the AR fits, one group per slot
  std::vector<Eigen::VectorXd> buffers_;  // with a store: one per component in flight
  // Deques: the running fits hold pointers into them while more are appended.
  std::deque<Eigen::VectorXd> kept_;  // without a store: every IMF
  std::deque<Prefit> fits_;
  std::deque<emd::ImfInfo> infos_;  // as band limited
  std::deque<double> variances_;    // the components' (ComponentVariance)
  std::mutex queue_mutex_;
  std::deque<Pending> queue_;  // IMFs taken, not yet band limited
  bool limiting_ = false;      // the chain is running (its task is in limit_groups_[chain_slot_])
  int chain_slot_ = 0;         // the slot of the component the chain is at
  int limited_ = 0;            // components band limited (in order), their fits started
  bool failed_ = false;        // a component's band limit or store failed
  IdlePool<std::unique_ptr<ar::ArWork>> idle_work_;  // of the fits, between fits
};

/// Step 1 and EMD, the IMFs handed to `imfs` as extracted. False (with the failure in the
/// summary) when no decomposition came out.
bool DecomposeStreamed(const Eigen::VectorXd& x, double sample_rate_hz,
                       const MethodOptions& options, const StreamOptions& stream, ImfStream* imfs,
                       MethodResult* result) {
  const bool preprocessed = PreprocessStep(x, sample_rate_hz, options, result);
  if (stream.on_preprocessed) stream.on_preprocessed();  // x is not read after this
  if (!preprocessed) return false;
  const emd::ImfSink sink = [imfs](int k, const Eigen::VectorXd& imf, const emd::ImfInfo& info) {
    imfs->Take(k, imf, info);
  };
  Eigen::VectorXd& signal = result->preprocessed.signal;
  if (stream.store != nullptr) {
    // The signal waits in the store while its array serves as the EMD's remainder: it is not held
    // beside it (N doubles less during the EMD), and it is read back for the residue.
    stream.store->Put(ComponentStore::Kind::kSignal, 0, signal);
    result->decomposition = emd::Decompose(&signal, options.emd, sink, [&](Eigen::VectorXd* x) {
      stream.store->Get(ComponentStore::Kind::kSignal, 0, x);
    });
    stream.store->Release(ComponentStore::Kind::kSignal, 0);
  } else {
    result->decomposition = emd::Decompose(signal, options.emd, sink);
  }
  emd::EmdResult& d = result->decomposition;
  const bool decomposed = HasResult(d.summary.termination);
  imfs->Finish(decomposed, &d.residue);
  if (decomposed) d.imf_info.assign(imfs->infos_.begin(), imfs->infos_.end());
  return NoteDecomposition(options, result);
}

/// Step 3 per component, components_in_flight at a time in component order, each added into
/// method 1 (eq. 12, summed in component order: the result never depends on the schedule) and
/// then released when there is a store. Then method 2 and the reference filters.
void FilterComponents(double sample_rate_hz, const MethodOptions& options,
                      const StreamOptions& stream, ImfStream* imfs, MethodResult* result) {
  emd::EmdResult& d = result->decomposition;
  const int num_imfs = result->summary.num_imfs;
  const Eigen::VectorXd& signal = result->preprocessed.signal;
  const Eigen::Index n = signal.size();
  ComponentStore* store = stream.store;

  const ForEach for_each = stream.for_each ? stream.for_each : ForEach(SerialForEach);
  // R per component (white_noise.h): the raw white-noise variance shared by mean period.
  const WhiteNoiseLevels levels = EstimateWhiteNoiseLevels(signal, for_each);
  std::vector<double> variances(imfs->variances_.begin(), imfs->variances_.end());
  variances.push_back(ComponentVariance(d.residue));
  const std::vector<double> r = ShareWhiteNoise(levels, ComponentPeriods(d, n), variances);

  // Method 2 and the reference filters only need the signal.
  ComponentOptions direct_options = options.component;
  direct_options.ar.fixed_order = options.direct_ar_order;
  // The raw signal's white noise is white: innovation matching is the consistent rule there.
  direct_options.noise_rule = ComponentNoiseRule::kInnovationMatch;
  if (store) store->Put(ComponentStore::Kind::kComponent, num_imfs, d.residue);
  result->components.assign(num_imfs + 1, ComponentModel());
  result->method1 = Eigen::VectorXd::Zero(n);
  std::string failure;
  const int batch = stream.components_in_flight;
  for (int start = 0; start <= num_imfs && failure.empty(); start += batch) {
    const int count = std::min(batch, num_imfs + 1 - start);
    for_each(count, [&](int j) {
      const int k = start + j;
      const Eigen::VectorXd* x = k == num_imfs ? &d.residue : nullptr;
      if (x == nullptr && store == nullptr) x = &imfs->kept_[k];
      if (x == nullptr) {
        store->Get(ComponentStore::Kind::kComponent, k, &imfs->buffers_[j]);
        x = &imfs->buffers_[j];
      }
      ar::ArFit* prefit = k < num_imfs && imfs->fits_[k].done ? &imfs->fits_[k].fit : nullptr;
      result->components[k] = ModelComponent(*x, r[k], options.component, prefit);
    });
    for (int k = start; k < start + count && failure.empty(); ++k) {
      ComponentModel& c = result->components[k];
      if (!c.ok()) {
        failure = ComponentName(k, num_imfs) + ": " + c.message();
        break;
      }
      result->method1 += c.Output();
      if (store == nullptr) continue;
      if (stream.store_filtered) store->Put(ComponentStore::Kind::kFiltered, k, c.Output());
      c.kalman.filtered = Eigen::VectorXd();
      c.kalman.smoothed = Eigen::VectorXd();
    }
  }
  if (store) {
    d.residue = Eigen::VectorXd();
    for (Eigen::VectorXd& buffer : imfs->buffers_) buffer = Eigen::VectorXd();
  }
  // Then method 2 beside the reference filters: after the components rather than beside them,
  // so that the peak memory is the larger of the two phases, not their sum.
  if (failure.empty()) {
    RunReferenceFilters(sample_rate_hz, options, for_each, result, [&] {
      result->direct = ModelComponent(signal, levels.Total(), direct_options);
    });
  }
  if (store == nullptr) {
    d.imfs.reserve(imfs->kept_.size());
    for (Eigen::VectorXd& imf : imfs->kept_) d.imfs.push_back(std::move(imf));
  }
  if (!failure.empty()) {
    result->method1 = Eigen::VectorXd();
    return Fail(result, Termination::kNumericalFailure, failure);
  }
  if (!result->direct.ok()) {
    return Fail(result, Termination::kNumericalFailure, "method 2: " + result->direct.message());
  }
}

}  // namespace

void DecomposeAndModel(const Eigen::VectorXd& x, double sample_rate_hz,
                       const MethodOptions& options, const StreamOptions& stream,
                       MethodResult* result) {
  std::string error;
  if (!options.IsValid(&error)) return Fail(result, Termination::kInvalidOptions, error);
  if (!stream.IsValid(&error)) return Fail(result, Termination::kInvalidOptions, error);
  ImfStream imfs(options, stream);
  const bool decomposed = DecomposeStreamed(x, sample_rate_hz, options, stream, &imfs, result);
  if (stream.on_decomposed) stream.on_decomposed();
  if (decomposed) FilterComponents(sample_rate_hz, options, stream, &imfs, result);
}

void RunReferenceFilters(double sample_rate_hz, const MethodOptions& options,
                         const ForEach& for_each, MethodResult* result,
                         const std::function<void()>& beside) {
  if (!HasResult(result->summary.termination)) {
    if (beside) beside();
    return;
  }
  std::vector<filters::ReferenceOutput> outputs = filters::RunReferenceFilters(
      result->preprocessed.signal, sample_rate_hz, options.reference, for_each, beside);
  result->reference.assign(outputs.size(), ReferenceEvaluation());
  for (std::size_t i = 0; i < outputs.size(); ++i)
    result->reference[i].output = std::move(outputs[i]);
}

void EvaluateAllan(double sample_rate_hz, const MethodOptions& options, const ForEach& for_each,
                   MethodResult* result) {
  if (!HasResult(result->summary.termination)) return;
  std::vector<const Eigen::VectorXd*> signals = {&result->preprocessed.signal, &result->method1,
                                                 &result->direct.Output()};
  std::vector<AllanEvaluation*> outputs = {&result->raw_allan, &result->method1_allan,
                                           &result->method2_allan};
  for (ReferenceEvaluation& r : result->reference) {
    if (!HasResult(r.output.termination)) continue;
    signals.push_back(&r.output.signal);
    outputs.push_back(&r.allan);
  }
  for_each(static_cast<int>(signals.size()), [&](int i) {
    outputs[i]->allan = allan::ComputeAllan(*signals[i], sample_rate_hz, options.allan);
    if (HasResult(outputs[i]->allan.summary.termination)) {
      outputs[i]->noise = allan::FitNoiseTermsAndModelEdf(
          options.noise_fit, options.allan.confidence, &outputs[i]->allan.table);
    }
  });
  // Terms of the filtered outputs above the raw fit's upper limits describe the filter.
  if (HasResult(result->raw_allan.allan.summary.termination)) {
    for (std::size_t i = 1; i < outputs.size(); ++i) {
      if (HasResult(outputs[i]->allan.summary.termination))
        allan::MarkTermsAboveUnfiltered(result->raw_allan.noise, &outputs[i]->noise);
    }
  }
  const char* names[3] = {"raw", "method 1", "method 2"};
  for (int i = 0; i < 3; ++i) {
    if (!HasResult(outputs[i]->allan.summary.termination)) {
      return Fail(
          result, outputs[i]->allan.summary.termination,
          std::string("Allan variance of ") + names[i] + ": " + outputs[i]->allan.summary.message);
    }
  }
}

MethodResult RunMethod(const Eigen::VectorXd& x, double sample_rate_hz,
                       const MethodOptions& options, const ForEach& for_each) {
  MethodResult result;
  StreamOptions stream;
  stream.for_each = for_each;
  DecomposeAndModel(x, sample_rate_hz, options, stream, &result);
  EvaluateAllan(sample_rate_hz, options, for_each, &result);
  return result;
}

}  // namespace fogpipe::method
