#include "algorithms/allan/nnls.h"

#include <Eigen/QR>
#include <algorithm>
#include <limits>
#include <vector>

namespace fogpipe::allan {
namespace {

// Least-squares solution on the passive columns (others zero).
Eigen::VectorXd SolvePassive(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                             const std::vector<bool>& passive) {
  std::vector<Eigen::Index> cols;
  for (Eigen::Index j = 0; j < a.cols(); ++j)
    if (passive[j]) cols.push_back(j);
  Eigen::MatrixXd ap(a.rows(), static_cast<Eigen::Index>(cols.size()));
  for (size_t k = 0; k < cols.size(); ++k) ap.col(static_cast<Eigen::Index>(k)) = a.col(cols[k]);
  const Eigen::VectorXd sp = ap.colPivHouseholderQr().solve(b);
  Eigen::VectorXd s = Eigen::VectorXd::Zero(a.cols());
  for (size_t k = 0; k < cols.size(); ++k) s[cols[k]] = sp[static_cast<Eigen::Index>(k)];
  return s;
}

}  // namespace

NnlsResult SolveNnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b) {
  const Eigen::Index n = a.cols();
  NnlsResult r;
  r.x = Eigen::VectorXd::Zero(n);
  std::vector<bool> passive(static_cast<size_t>(n), false);
  const double tol = 10.0 * std::numeric_limits<double>::epsilon() *
                     static_cast<double>(std::max(a.rows(), n)) * a.cwiseAbs().maxCoeff() *
                     b.norm();
  const int max_outer = 3 * static_cast<int>(n) + 10;
  r.gradient = a.transpose() * (b - a * r.x);
  r.converged = true;
  for (;;) {
    // Most violated KKT condition among the active (zero) variables.
    Eigen::Index t = -1;
    double best = tol;
    for (Eigen::Index j = 0; j < n; ++j)
      if (!passive[j] && r.gradient[j] > best) best = r.gradient[j], t = j;
    if (t < 0) break;
    if (r.iterations >= max_outer) {
      r.converged = false;
      break;
    }
    ++r.iterations;
    passive[t] = true;
    Eigen::VectorXd s = SolvePassive(a, b, passive);
    // Inner loop: step back towards x until the passive solution is feasible.
    for (int inner = 0; inner < 3 * n + 10; ++inner) {
      bool feasible = true;
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[j] && s[j] <= 0.0) feasible = false;
      if (feasible) break;
      double alpha = 1.0;
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[j] && s[j] <= 0.0) alpha = std::min(alpha, r.x[j] / (r.x[j] - s[j]));
      r.x += alpha * (s - r.x);
      // The variable(s) that set alpha are zero up to rounding: release them.
      const double zero = 1e-14 * r.x.cwiseAbs().maxCoeff();
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[j] && r.x[j] <= zero) passive[j] = false, r.x[j] = 0.0;
      s = SolvePassive(a, b, passive);
    }
    r.x = s;
    for (Eigen::Index j = 0; j < n; ++j)
      if (!passive[j]) r.x[j] = 0.0;
    r.gradient = a.transpose() * (b - a * r.x);
  }
  return r;
}

}  // namespace fogpipe::allan
