// The grid of a parameter sweep (fogpipe sweep): AR order x q scale x R scale, and the named
// criteria by which its settings are ranked.
//
// The paper (Liu, Liu & Shen 2018) gives no values for the Kalman q and R and picks its AR orders
// by judgment, so users sweep them. Per component:
//   q = q_scale * sigma_e^2, sigma_e^2 the AR(p) innovation variance of the component;
//   R = r_scale * R_k, R_k the component's share of the white noise (white_noise.h).
// q is referred to sigma_e^2 rather than to the default rule of noise_defaults.h because that rule
// gives q = 0 whenever sigma_e^2 <= R_k, which on white-noise-dominated IMFs is the common case
// (measured: on 10 Hz simulated recordings with N = 0.05 deg/sqrt(h) every IMF had q = 0), and a
// scale of 0 sweeps nothing. `fogpipe run`'s own rule (q by noise_defaults, R = R_k) is evaluated
// at every AR order as well, as the "default" settings (SweepSetting::default_rule).
#pragma once

#include <string>
#include <vector>

namespace fogpipe::method {

struct SweepGrid {
  /// AR order of every component (IMFs and residue), each >= 1.
  std::vector<int> ar_orders = {2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  /// Multipliers of the default process-noise variance q, each > 0.
  std::vector<double> q_scales = {0.1, 1.0, 10.0};
  /// Multipliers of the default measurement-noise variance R, each > 0.
  std::vector<double> r_scales = {0.1, 1.0, 10.0};

  bool IsValid(std::string* error) const;
  /// Number of settings, the default rule of every order included.
  int size() const {
    return static_cast<int>(ar_orders.size() * (q_scales.size() * r_scales.size() + 1));
  }
  int max_order() const;
};

/// One point of the grid.
struct SweepSetting {
  int ar_order = 0;
  double q_scale = 1.0;
  double r_scale = 1.0;
  /// `fogpipe run`'s rule (q from noise_defaults.h, R = R_k); the scales are then 1 and unused.
  bool default_rule = false;
};

/// Every setting, AR order slowest; per order first the default rule, then every q scale with
/// every R scale (R fastest). This is the row order of the sweep table.
std::vector<SweepSetting> GridSettings(const SweepGrid& grid);

/// "2:12" (inclusive range), "2:12:2" (with step) or "2,4,8" (list). False with *error otherwise.
bool ParseIntList(const std::string& text, std::vector<int>* values, std::string* error);
/// "0.1,1,10" (list) or "1e-2:1e2:5" (FROM:TO:COUNT, log-spaced inclusive). False with *error.
bool ParseScaleList(const std::string& text, std::vector<double>* values, std::string* error);

}  // namespace fogpipe::method
