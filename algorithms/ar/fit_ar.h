// AR(p) modelling, the front door: FitAr() picks the order by BIC and estimates the coefficients.
//
// Pipeline per call: mean removal -> models of every order 1..P from one order-recursive pass of
// the selection estimator -> BIC (order_selection.h) -> the chosen order -> refinement (ML only)
// -> stationarity and standard errors (ar_model.h) -> diagnostics (diagnostics.h).
// The order run is the best one (BIC's, or the fixed order and below) whose coefficients are
// stationary as stored in double precision (stationarity.h): Burg's reflection coefficients are
// below 1, but for slow components the rounded phi can still have a root outside the unit circle.
//
// Order selection per estimator (every estimator is order-recursive, so BIC costs one pass):
//   kBurg               Burg's sigma_p^2 (burg.h), N = number of samples.
//   kLeastSquaresQr     the nested QR residuals (least_squares.h), N = samples - P.
//   kYuleWalker         Levinson-Durbin's sigma_p^2 (yule_walker.h), N = number of samples.
//   kMaximumLikelihood  Burg's BIC selects the order, then the exact likelihood is maximised at
//                       that order only, starting from Burg (maximum_likelihood.h). ML at every
//                       order would cost P likelihood optimisations for a BIC that differs from
//                       Burg's by O(1) when N ln(sigma^2) differs by O(1): the same order in
//                       practice.
//   With fixed_order > 0 the orders 1..fixed_order are still computed (bic is reported) and
//   fixed_order is used.
//
// ML and Burg differ by O(1/N) in phi, far inside the sampling error, so for fogpipe's record
// lengths they are interchangeable and Burg (no extra passes) stays the default. The measured
// differences are in algorithms/ar/README.md (printed by maximum_likelihood_test.cpp).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>

#include "algorithms/ar/ar_model.h"
#include "algorithms/ar/burg.h"
#include "algorithms/ar/diagnostics.h"
#include "algorithms/common/status.h"

namespace fogpipe::ar {

enum class Estimator { kBurg, kLeastSquaresQr, kYuleWalker, kMaximumLikelihood };

/// "burg", "least_squares_qr", "yule_walker", "maximum_likelihood".
const char* ToString(Estimator estimator);

struct ArOptions {
  /// Largest order tried by BIC (1..kMaxOrderLimit).
  int max_order = 20;
  /// 0: choose the order by BIC. > 0: use this order (must be <= max_order), or the highest order
  /// below it that is stationary as stored (ArSummary::order_note says so).
  int fixed_order = 0;
  /// Coefficient estimator; Burg is the default (accurate near the unit circle, stationary in exact
  /// arithmetic).
  Estimator estimator = Estimator::kBurg;
  /// Compute ArDiagnostics (three extra passes over the data; see the benchmark for the cost).
  bool compute_diagnostics = true;
  /// Iteration controls of the ML refinement.
  int ml_max_iterations = 50;

  static constexpr int kMaxOrderLimit = 200;

  bool IsValid(std::string* error) const;
};

struct ArSummary {
  Termination termination = Termination::kInvalidOptions;
  std::string message;
  /// Orders for which a model and a BIC were computed (1..orders_tried).
  int orders_tried = 0;
  /// ML only: Gauss-Newton iterations; 0 otherwise.
  int ml_iterations = 0;
  /// Empty, or why the model's order is not BIC's (or the fixed) order: that order's coefficients
  /// are not stationary as stored (order_selection.h, SelectStationaryOrder), e.g. "AR(13) (BIC's
  /// order) is not stationary in double precision (max root modulus 1.00014); AR(9) used".
  std::string order_note;
};

struct ArFit {
  ArModel model;
  /// bic(p - 1) for p = 1..(fixed_order or max_order); +inf for orders that could not be computed.
  Eigen::VectorXd bic;
  ArDiagnostics diagnostics;  ///< Zeros unless compute_diagnostics and a result exists.
  ArSummary summary;
};

/// Fits an AR model to x (any units; the mean is removed and stored). Never throws for data
/// problems: see summary.termination (kInsufficientData when N <= 2 P + 20, kNumericalFailure for
/// non-finite or constant input, kNoConvergence when ML stopped early; the Burg start is then kept
/// if ML did not improve on it).
ArFit FitAr(const Eigen::Ref<const Eigen::VectorXd>& x, const ArOptions& options);

/// The N-sized work arrays of FitAr: Burg's two error arrays, the first of which then holds the
/// diagnostics' residuals; 2 N doubles after a fit. A caller that fits many series of one length
/// keeps one and passes it to each call, so that no fit allocates fresh pages.
struct ArWork {
  BurgWork burg;
};

/// FitAr with its work arrays in *work (may be null); the result is the same bit for bit.
ArFit FitAr(const Eigen::Ref<const Eigen::VectorXd>& x, const ArOptions& options, ArWork* work);

/// FitAr for a caller that can read its series again but should not hold it beside Burg's two
/// error arrays (the streamed method, whose components wait in a store): Burg's forward errors
/// are formed in *x itself (x - mean, in place), the backward ones in work->burg.backward, and
/// once the model is chosen `reload(x)` must fill *x with the series again for the diagnostics
/// (whose residuals then go to the spent backward array). Extra memory N doubles instead of 2 N;
/// the result equals FitAr(*x, options, work) bit for bit (the same arithmetic on the same
/// values). For an estimator other than Burg this is FitAr(*x, options, work): *x is untouched
/// and `reload` is not called. `reload` may throw; *x's contents are then unspecified.
ArFit FitArInPlace(Eigen::VectorXd* x, const ArOptions& options, ArWork* work,
                   const std::function<void(Eigen::VectorXd*)>& reload);

}  // namespace fogpipe::ar
