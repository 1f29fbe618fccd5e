// The `angle_quantizer` term of `fogpipe compare`: a coarse angle counter's error taken out of the
// rate before the fit (angle_lattice.h says when a record is one).
//
// The counter records theta_k = q N_k (N_k the running sum of the integer increments n_k; the
// lattice's offset c per sample is carried along), and the true angle x_k lies in the box
// [q N_k - q/2, q N_k + q/2] (its position against the lattice at the start is unobservable and
// irrelevant: the rate is a difference of angles). Between samples the angle moves by the rate
// times dt: under the model's white rate noise N and a constant drift mu, x_k - x_{k-1} ~
// N(mu, sigma^2), sigma = N sqrt(dt). Given the counts, the angle within the boxes is then a
// hidden Markov chain: u_k = x_k - q N_k in [-q/2, q/2], u_k = u_{k-1} + (x_k - x_{k-1}) - q n_k.
//
// Why a draw and not the conditional mean. Below sigma ~ q / 3 the counter has destroyed the
// angle's detail within a step: E[x | counts] is smoother than x, and its differences lack part
// of the white noise (tried: the default model then fails at every short tau; docs/compare.md).
// A draw from p(x | counts) (forward filtering, backward sampling; Frühwirth-Schnatter 1994,
// Carter & Kohn 1994: data augmentation, Tanner & Wong 1987) has, under the model, the law of an
// unquantized angle and the counts' information at every scale above a step: its differences are
// what the rate would have been without the counter, up to the draw's randomness within the
// boxes. The rest of the fit (N, B, K and the other terms) and the views then see the rate they
// describe. sigma is not known beforehand: compare starts from the N of the model fitted to the
// raw counter, refits N on the draw and draws again until N settles (a stochastic EM, Celeux &
// Diebolt 1985; compare.cpp, AngleQuantizerOptions). Each draw is seeded by the record's length,
// so a compare is reproducible.
//
// Why the EM is accelerated. The EM map F (sigma of a draw -> sigma refitted on it) contracts at
// the rate of the missing information (Dempster, Laird & Rubin 1977): on a counter whose step is
// 50-70 times sigma the counts hardly tell sigma within a step, F moves it by a few percent per
// draw at a rate near 0.8, and plain iteration spends all its draws on the way down
// (docs/compare.md). NextEmNoise takes Aitken's extrapolation of the sequence (Louis 1982) in its
// one-dimensional form, a secant on g(l) = log F(e^l) - l through the last two draws
// (Steffensen's method): the step -g / slope, the remaining distance to the fixed point if F is
// locally linear. Safeguards: the slope is held in [-1, -1 / max_acceleration] (the step goes
// the EM's way, at least the EM's step and at most max_acceleration of them; a positive or
// undefined slope, which a contraction cannot have, gives the EM's step). The EM still settles
// on its own move (F(sigma) within relative_tolerance of sigma), not on the extrapolated
// distance: where F's rate nears 1 its fixed point is ill-determined (a small bias of F moves it
// far), and the extrapolation would run every draw into it. The first round is the plain EM
// step, so a record on which the EM settled after one refit is unchanged.

// The chain is filtered on a grid of `cells` over the box (at least `min_cells`, and fine enough
// for sigma to span `cells_per_sigma` of them, at most `max_cells`); the transition is a Gaussian
// convolution truncated at 7 sigma. The filter's probabilities are kept every ~sqrt(n) samples and
// recomputed per block for the backward pass, so memory is O(sqrt(n) cells). Each drawn u is
// uniform within its cell: the grid adds a white angle error of variance (q / cells)^2 / 12,
// which the model's Q absorbs.
#pragma once

#include <Eigen/Core>
#include <string>

#include "algorithms/model/angle_lattice.h"

namespace fogpipe::model {

struct AngleQuantizerOptions {
  int min_cells = 48;                ///< grid cells over one step, at least
  double cells_per_sigma = 3.0;      ///< sigma spans at least this many cells (up to max_cells)
  int max_cells = 256;               ///< grid cells, at most
  int max_rounds = 8;                ///< draws at most (compare: the stochastic EM's rounds)
  double relative_tolerance = 0.02;  ///< ... until the refitted N moves by less than this
  double max_acceleration = 10.0;    ///< an EM step is extrapolated at most this far (1: plain EM)
  bool IsValid(std::string* error) const;
};

/// What the term found and used (SI).
struct AngleQuantizerFit {
  AngleLattice lattice;             ///< the counter (step, offset, coarseness)
  double noise_per_sample_rad = 0;  ///< sigma = N sqrt(dt) the draw used
  double rate_step_rad_s = 0;       ///< q / dt, the step as a rate
  int cells = 0;                    ///< the grid's cells over one step
  int rounds = 0;                   ///< draws the stochastic EM made (compare)
  bool ok = false;
  std::string message;
};

/// The rate with the counter's error replaced by a draw of the angle within the boxes (see the
/// header comment). `lattice` must be on_lattice; `noise_per_sample_rad` > 0. On failure (not
/// on a lattice, non-finite samples) returns the rate unchanged and fit->ok false with a message.
Eigen::VectorXd ImputeAngleOnLattice(const Eigen::VectorXd& rate_rad_s, double sample_rate_hz,
                                     const AngleLattice& lattice, double noise_per_sample_rad,
                                     const AngleQuantizerOptions& options, AngleQuantizerFit* fit);

/// One round of compare's stochastic EM on sigma (header comment): a draw used `sigma` and N
/// refitted on it gave `refitted` (per-sample sigma both). Returns the sigma of the next draw;
/// *settled when `refitted` is within relative_tolerance of `sigma`. `previous_sigma`
/// and `previous_refitted` are the round before's (0 on the first round: the plain EM step).
double NextEmNoise(double sigma, double refitted, double previous_sigma, double previous_refitted,
                   const AngleQuantizerOptions& options, bool* settled);

}  // namespace fogpipe::model
