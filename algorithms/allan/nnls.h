// Non-negative least squares, min ||A x - b|| subject to x >= 0, by the active-set algorithm of
// Lawson & Hanson, "Solving Least Squares Problems" (1974), chapter 23 (algorithm NNLS).
#pragma once

#include <Eigen/Core>

namespace fogpipe::allan {

struct NnlsResult {
  Eigen::VectorXd x;         ///< Solution, all entries >= 0.
  Eigen::VectorXd gradient;  ///< w = A^T (b - A x): <= tol where x = 0 (KKT), ~0 where x > 0.
  int iterations = 0;        ///< Outer iterations (variables freed).
  bool converged = false;    ///< False if the iteration cap (3 n + 10) was hit.
};

/// Solves the problem for a tall or square A (rows >= 1). Columns should be scaled to comparable
/// norms by the caller; the KKT tolerance is 10 eps max(rows, cols) max|A_ij| ||b||.
NnlsResult SolveNnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b);

}  // namespace fogpipe::allan
