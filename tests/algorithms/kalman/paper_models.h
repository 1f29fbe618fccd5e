// Test support: the AR models of Liu, Liu & Shen (2018), Table 2 (docs/method.md, "Step 2"),
// converted from MATLAB's A(q) convention to recursion coefficients, phi_i = -a_i. imf8 is left
// out: its printed a3 has a sign typo (docs/method.md, "The imf8 sign typo").
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace fogpipe::kalman::testing {

struct PaperModel {
  std::string name;
  Eigen::VectorXd phi;
};

inline Eigen::VectorXd FromMatlabA(std::initializer_list<double> a) {
  Eigen::VectorXd phi(static_cast<Eigen::Index>(a.size()));
  Eigen::Index i = 0;
  for (double v : a) phi[i++] = -v;
  return phi;
}

inline std::vector<PaperModel> PaperTable2Models() {
  return {
      {"imf1", FromMatlabA({0.5039, 0.3110, 0.0732, 0.0105})},
      {"imf2", FromMatlabA({-1.3904, 1.6244, -0.9363, 0.4655})},
      {"imf3", FromMatlabA({-2.8311, 3.5874, -2.2984, 0.6686})},
      {"imf4", FromMatlabA({-3.4971, 4.8028, -3.0620, 0.7692})},
      {"imf5", FromMatlabA({-3.7904, 5.4640, -3.5507, 0.8783})},
      {"imf6", FromMatlabA({-3.9151, 5.7665, -3.7869, 0.9356})},
      {"imf7", FromMatlabA({-2.9976, 2.9970, -0.9994})},
      {"imf9", FromMatlabA({-2.0004, 1.0005})},  // |root|^2 = 1.0005: slightly unstable
      {"residue", FromMatlabA({-1.9989, 0.9989})},
  };
}

}  // namespace fogpipe::kalman::testing
