#include "algorithms/ar/fit_ar.h"

#include <algorithm>
#include <limits>
#include <sstream>

#include "algorithms/ar/burg.h"
#include "algorithms/ar/least_squares.h"
#include "algorithms/ar/maximum_likelihood.h"
#include "algorithms/ar/order_selection.h"
#include "algorithms/ar/stationarity.h"
#include "algorithms/ar/yule_walker.h"

namespace fogpipe::ar {

const char* ToString(Estimator estimator) {
  switch (estimator) {
    case Estimator::kBurg:
      return "burg";
    case Estimator::kLeastSquaresQr:
      return "least_squares_qr";
    case Estimator::kYuleWalker:
      return "yule_walker";
    case Estimator::kMaximumLikelihood:
      return "maximum_likelihood";
  }
  return "unknown";
}

bool ArOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (max_order < 1 || max_order > kMaxOrderLimit)
    return fail("max_order must be in [1, " + std::to_string(kMaxOrderLimit) + "]");
  if (fixed_order < 0 || fixed_order > max_order)
    return fail("fixed_order must be 0 (BIC) or in [1, max_order]");
  if (ml_max_iterations < 1) return fail("ml_max_iterations must be >= 1");
  return true;
}

ArFit FitAr(const Eigen::Ref<const Eigen::VectorXd>& x, const ArOptions& options) {
  return FitAr(x, options, nullptr);
}

namespace {

// FitAr's steps. With `owner` (FitArInPlace: x views *owner, the estimator is Burg and work is
// given), Burg forms its forward errors in *owner's own array and `reload` refills it after.
ArFit Fit(const Eigen::Ref<const Eigen::VectorXd>& x, const ArOptions& options, ArWork* work,
          Eigen::VectorXd* owner, const std::function<void(Eigen::VectorXd*)>& reload) {
  ArFit fit;
  std::string error;
  if (!options.IsValid(&error)) {
    fit.summary.termination = Termination::kInvalidOptions;
    fit.summary.message = error;
    return fit;
  }
  const int top = options.fixed_order > 0 ? options.fixed_order : options.max_order;
  const Eigen::Index n = x.size();
  // 20 more samples than twice the top order: the least-squares rows and the Ljung-Box lag 20.
  if (n <= 2 * static_cast<Eigen::Index>(top) + 20) {
    fit.summary.termination = Termination::kInsufficientData;
    fit.summary.message = "AR fit needs more than 2 * order + 20 samples, got " + std::to_string(n);
    return fit;
  }
  if (!x.allFinite()) {
    fit.summary.termination = Termination::kNumericalFailure;
    fit.summary.message = "input contains non-finite values";
    return fit;
  }
  const double mean = x.mean();
  // Burg subtracts the mean while copying into its two error arrays; the other estimators work on
  // a centred copy. Peak extra memory: 2 N doubles (Burg, ML), N (Yule-Walker, QR), plus O(P^2).
  Eigen::VectorXd xc;
  OrderSequence seq;
  switch (options.estimator) {
    case Estimator::kBurg:
    case Estimator::kMaximumLikelihood:
      if (owner != nullptr) {
        // x's array becomes the forward error array (f = x - mean reads each sample before it
        // overwrites it) and is handed back, spent, afterwards.
        work->burg.forward.swap(*owner);
        seq = BurgAllOrders(x, top, mean, &work->burg);
        owner->swap(work->burg.forward);
      } else {
        seq = BurgAllOrders(x, top, mean, work != nullptr ? &work->burg : nullptr);
      }
      break;
    case Estimator::kLeastSquaresQr:
      xc = x.array() - mean;
      seq = LeastSquaresAllOrders(xc, top);
      break;
    case Estimator::kYuleWalker:
      xc = x.array() - mean;
      seq = YuleWalkerAllOrders(xc, top);
      break;
  }
  fit.summary.orders_tried = seq.orders_completed;
  fit.bic.setConstant(top, std::numeric_limits<double>::infinity());
  fit.bic.head(seq.orders_completed) = Bic(seq.innovation_variance, seq.num_effective);
  if (seq.orders_completed == 0) {
    fit.summary.termination = Termination::kNumericalFailure;
    fit.summary.message = "no AR model could be formed (constant input?)";
    return fit;
  }

  std::ostringstream msg;
  // BIC's order, or the fixed order as far as the recursion reached; then the order actually run:
  // the best one whose coefficients are stationary as stored (SelectStationaryOrder).
  int preferred = 0;
  if (options.fixed_order > 0) {
    preferred = std::min(options.fixed_order, seq.orders_completed);
    if (preferred < options.fixed_order)
      msg << "prediction error vanished at order " << preferred << "; fixed order "
          << options.fixed_order << " not reachable. ";
  } else {
    preferred = SelectOrderByBic(fit.bic.head(seq.orders_completed));
  }
  const int order = SelectStationaryOrder(
      fit.bic.head(seq.orders_completed), options.fixed_order > 0 ? preferred : 0,
      [&seq](int q) { return IsStationaryAsStored(seq.phi[q - 1]); });
  if (order != preferred) {
    std::ostringstream note;
    note << "AR(" << preferred << ")" << (options.fixed_order > 0 ? "" : " (BIC's order)")
         << " is not stationary in double precision (max root modulus "
         << MaxRootModulusAsStored(seq.phi[preferred - 1]) << "); AR(" << order << ") used";
    fit.summary.order_note = note.str();
    msg << fit.summary.order_note << ". ";
  }
  Eigen::VectorXd phi = seq.phi[order - 1];
  double sigma2 = seq.innovation_variance(order - 1);
  fit.summary.termination = Termination::kSuccess;

  if (options.estimator == Estimator::kMaximumLikelihood) {
    MaximumLikelihoodOptions ml_options;
    ml_options.max_iterations = options.ml_max_iterations;
    xc = x.array() - mean;
    const MaximumLikelihoodResult ml =
        FitMaximumLikelihood(xc, seq.reflection.head(order), ml_options);
    fit.summary.ml_iterations = ml.iterations;
    if (!ml.valid) {
      fit.summary.termination = Termination::kNumericalFailure;
      fit.summary.message = "maximum likelihood could not start from the Burg model";
      return fit;
    }
    if (IsStationaryAsStored(ml.phi)) {
      phi = ml.phi;
      sigma2 = ml.innovation_variance;
    } else {
      msg << "the maximum-likelihood refinement is not stationary in double precision; the Burg "
             "start is kept. ";
    }
    if (!ml.converged) {
      fit.summary.termination = Termination::kNoConvergence;
      msg << "maximum likelihood stopped after " << ml.iterations << " iterations. ";
    }
  }

  xc.resize(0);  // not needed by the diagnostics
  fit.model = MakeArModel(phi, sigma2, mean, n);
  msg << ToString(options.estimator) << " AR(" << order << ")"
      << (options.fixed_order > 0 ? " (fixed order)" : " selected by BIC") << ", max root modulus "
      << fit.model.max_root_modulus;
  if (!fit.model.stationary) msg << "; NOT stationary";
  fit.summary.message = msg.str();
  if (options.compute_diagnostics) {
    // Burg's error arrays are spent: one of them holds the residuals.
    if (owner != nullptr) {
      reload(owner);
      fit.diagnostics = ComputeDiagnostics(*owner, fit.model, work->burg.backward.data());
    } else if (work != nullptr && work->burg.forward.size() == n) {
      fit.diagnostics = ComputeDiagnostics(x, fit.model, work->burg.forward.data());
    } else {
      fit.diagnostics = ComputeDiagnostics(x, fit.model);
    }
  }
  return fit;
}

}  // namespace

ArFit FitAr(const Eigen::Ref<const Eigen::VectorXd>& x, const ArOptions& options, ArWork* work) {
  return Fit(x, options, work, nullptr, nullptr);
}

ArFit FitArInPlace(Eigen::VectorXd* x, const ArOptions& options, ArWork* work,
                   const std::function<void(Eigen::VectorXd*)>& reload) {
  if (options.estimator != Estimator::kBurg || work == nullptr) return FitAr(*x, options, work);
  // The view is taken before Burg swaps the array away: it follows the samples, not *x.
  const Eigen::Ref<const Eigen::VectorXd> view(*x);
  return Fit(view, options, work, x, reload);
}

}  // namespace fogpipe::ar
