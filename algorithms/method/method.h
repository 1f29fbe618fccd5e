// The paper's whole method on one axis (Liu, Liu & Shen 2018; docs/method.md, steps 1-4), as plain
// functions without threads of their own (work runs through a ForEach and a TaskGroup). The flow
// graph (pipeline/graph) runs the stages in its nodes; RunMethod() chains them (tests, tools).
//
//   x --Preprocess--> s --EMD--> imf_1..imf_n, residue
//     method 1: per component AR(p by BIC) + Kalman -> x1 = sum filtered IMFs + filtered residue
//               (eq. 12, summed in component order so the result never depends on scheduling)
//     method 2: one AR (order by BIC, or fixed: the paper's AR(6)) + one Kalman filter on s
//   Allan tables and Q, N, B, K, R for s (raw), x1 (method 1) and x2 (method 2).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "algorithms/allan/allan.h"
#include "algorithms/allan/noise_fit.h"
#include "algorithms/common/for_each.h"
#include "algorithms/common/status.h"
#include "algorithms/common/task_group.h"
#include "algorithms/emd/emd.h"
#include "algorithms/filters/reference_filters.h"
#include "algorithms/method/band_limit.h"
#include "algorithms/method/component.h"
#include "algorithms/method/component_store.h"
#include "algorithms/method/preprocess.h"

namespace fogpipe::method {

struct MethodOptions {
  PreprocessOptions preprocess;
  emd::EmdOptions emd;
  /// Each IMF's leakage below its band moved to the next component before modelling
  /// (band_limit.h); cutoff_ratio 0 keeps EMD's IMFs as they are.
  BandLimitOptions band_limit;
  /// AR and Kalman options of every IMF and of the residue (method 1).
  ComponentOptions component;
  /// Method 2's AR order: 0 = by BIC up to component.ar.max_order; the paper used 6.
  int direct_ar_order = 0;
  allan::AllanOptions allan;
  allan::NoiseFitOptions noise_fit;
  /// The reference filters run beside methods 1 and 2 on the preprocessed signal.
  filters::ReferenceFilterOptions reference;

  bool IsValid(std::string* error) const;
};

/// An Allan table with the five noise terms fitted to it.
struct AllanEvaluation {
  allan::AllanResult allan;
  allan::NoiseFitResult noise;
};

/// A reference filter's output (filters/reference_filters.h) and its Allan evaluation (empty when
/// the filter failed: output.termination says why; the recording does not fail for it).
struct ReferenceEvaluation {
  filters::ReferenceOutput output;
  AllanEvaluation allan;
};

struct MethodSummary {
  Termination termination = Termination::kInvalidOptions;
  std::string message;
  int num_imfs = 0;
};

struct MethodResult {
  Preprocessed preprocessed;
  emd::EmdResult decomposition;
  /// The BandLimitOptions::cutoff_ratio applied to decomposition.imfs (0: EMD's own IMFs).
  double band_limit_ratio = 0.0;
  /// One per IMF, then the residue (index num_imfs).
  std::vector<ComponentModel> components;
  /// Method 1: sum of the filtered components (eq. 12), units of the input, mean removed.
  Eigen::VectorXd method1;
  /// Method 2: the direct AR + Kalman on the preprocessed signal.
  ComponentModel direct;
  AllanEvaluation raw_allan, method1_allan, method2_allan;
  /// The reference filters in filters::ReferenceFilterNames() order (empty when disabled).
  std::vector<ReferenceEvaluation> reference;
  MethodSummary summary;
};

/// Runs body(i) for i in [0, n) (algorithms/common/for_each.h). The flow graph passes a
/// tbb::parallel_for; every body writes only its own slot, so the results are the same for any
/// schedule.
using fogpipe::ForEach;
/// The serial ForEach.
void SerialForEach(int n, const std::function<void(int)>& body);

/// How DecomposeAndModel() runs: where the components wait for their filters, and how much runs
/// at once.
struct StreamOptions {
  /// Where each component's samples wait for its filter. Null (default): in
  /// result->decomposition.imfs, and every component keeps its filtered output, as RunMethod()
  /// returns them. Otherwise every IMF and the residue go to the store as they are made,
  /// decomposition.imfs and .residue stay empty, and each filtered component is released once
  /// added into method 1 (stored first when store_filtered): memory no longer grows with the
  /// number of IMFs.
  ComponentStore* store = nullptr;
  /// With a store: put every filtered component into it (ComponentStore::Kind::kFiltered).
  bool store_filtered = false;
  /// Components whose samples are in memory at once, each with its AR fit or Kalman filter:
  /// while EMD sifts IMF k + 1, the AR models of up to this many earlier IMFs are fitted, and
  /// the filters then run this many components at a time. Default 2 (the machines this runs on
  /// have 2 cores per job); >= 1.
  int components_in_flight = 2;
  /// The AR fits beside the sifting, and method 2 beside the reference filters; empty: everything
  /// in order.
  TaskGroupFactory tasks;
  /// The filters of one batch of components; empty: in order.
  ForEach for_each;
  /// Called once the input x has been preprocessed and is no longer read: a caller that owns x
  /// may release it there (one signal's worth of memory less during the EMD).
  std::function<void()> on_preprocessed;
  /// Called once the decomposition is done (the pipeline times its stages with it).
  std::function<void()> on_decomposed;

  bool IsValid(std::string* error) const;
};

// ---- Stages (the flow graph's node bodies call these) ----

/// Preprocess + EMD (+ the band limit), all IMFs in result->decomposition. On failure the summary
/// says why and the rest is left empty. (The sweep starts from it; `run` streams instead.)
void PreprocessAndDecompose(const Eigen::VectorXd& x, double sample_rate_hz,
                            const MethodOptions& options, MethodResult* result);

/// Steps 1-3 streamed, as the paper's method consumes them: preprocessing; EMD, each IMF band
/// limited, stored and its AR model fitted as soon as it is extracted; then per component (IMFs,
/// residue) the Kalman filter on its model, q and R from its white-noise share (which needs
/// every component's mean period, hence after the EMD), added into method 1 in component order;
/// then method 2 beside the reference filters. The numbers are the same whatever `stream`
/// says (tested bit for bit against the store-less path and across thread counts).
void DecomposeAndModel(const Eigen::VectorXd& x, double sample_rate_hz,
                       const MethodOptions& options, const StreamOptions& stream,
                       MethodResult* result);

/// The reference filters on the preprocessed signal (through for_each, with `beside` in the
/// lane of the lighter two: filters::RunReferenceFilters). Needs the preprocessed signal
/// (DecomposeAndModel runs it; the sweep calls it after PreprocessAndDecompose).
void RunReferenceFilters(double sample_rate_hz, const MethodOptions& options,
                         const ForEach& for_each, MethodResult* result,
                         const std::function<void()>& beside = nullptr);
/// The Allan tables + noise fits of raw, methods 1 and 2 and every reference filter with an
/// output (through for_each, one slot per signal).
void EvaluateAllan(double sample_rate_hz, const MethodOptions& options, const ForEach& for_each,
                   MethodResult* result);

/// All stages (DecomposeAndModel without a store, then EvaluateAllan), serially or through
/// for_each.
MethodResult RunMethod(const Eigen::VectorXd& x, double sample_rate_hz,
                       const MethodOptions& options, const ForEach& for_each = SerialForEach);

/// Component names as stored and printed: "imf1".."imfN", "residue".
std::string ComponentName(int index, int num_imfs);

}  // namespace fogpipe::method
