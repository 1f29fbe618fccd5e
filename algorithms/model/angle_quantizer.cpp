#include "algorithms/model/angle_quantizer.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "algorithms/kernels/kernels.h"
#include "algorithms/simulation/random.h"

namespace fogpipe::model {

bool AngleQuantizerOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* message) {
    if (error) *error = message;
    return false;
  };
  if (min_cells < 4) return fail("angle_quantizer.min_cells must be >= 4");
  if (!(cells_per_sigma > 0)) return fail("angle_quantizer.cells_per_sigma must be > 0");
  if (max_cells < min_cells) return fail("angle_quantizer.max_cells must be >= min_cells");
  if (max_rounds < 1) return fail("angle_quantizer.max_rounds must be >= 1");
  if (!(relative_tolerance > 0)) return fail("angle_quantizer.relative_tolerance must be > 0");
  if (!(max_acceleration >= 1)) return fail("angle_quantizer.max_acceleration must be >= 1");
  return true;
}

namespace {

// Stream of the draw: the record's length, so that a compare is reproducible.
constexpr std::uint64_t kDrawStream = 0x616E676C65710000ULL;

// The transition of u over one sample with increment count n: u_new - u_old = w - q n,
// w ~ N(mu, sigma^2), on the grid as a convolution over j = cell_new - cell_old, truncated at
// 7 sigma. weight[j - first] for j in [first, first + size).
struct Kernel {
  int first = 0;
  std::vector<double> weight;
};

Kernel MakeKernel(long long count, double q, double mu, double sigma, double cell, int cells) {
  const double shift = q * static_cast<double>(count) - mu;
  const int low =
      std::max(-(cells - 1), static_cast<int>(std::ceil((-7.0 * sigma - shift) / cell)));
  const int high = std::min(cells - 1, static_cast<int>(std::floor((7.0 * sigma - shift) / cell)));
  Kernel kernel;
  kernel.first = low;
  for (int j = low; j <= high; ++j) {
    const double z = (j * cell + shift) / sigma;
    kernel.weight.push_back(std::exp(-0.5 * z * z));
  }
  return kernel;
}

// out[a] = sum_k K_k old[a - first - k] over the taps that land on the grid, in tap order
// (kernels::ConvolutionSums). This is the draw's cost (twice per sample and EM round, about 200
// cells by 42 taps at 3 cells per sigma). One cell's additions wait on each other, so sixteen
// cells go side by side, their sums in four vector registers (32 measured no faster). The input is
// read from `padded`, the grid with zeros wherever a tap falls off it: a tap that lands nowhere
// adds K_k * 0 = +0, which leaves every partial sum (non-negative, from +0) as it was, so each cell
// keeps the bits of the sum over its landing taps alone, and the edge cells need no path of their
// own.
FOGPIPE_LANE_KERNEL void Convolve(const double* weight, int taps, int first, const double* old,
                                  int cells, double* out, std::vector<double>* padded) {
  using kernels::Lanes4;
  if (taps == 0) {  // a jump beyond the kernel's 7 sigma: no mass anywhere
    std::fill(out, out + cells, 0.0);
    return;
  }
  constexpr int kGroups = 4, kBlock = 4 * kGroups;
  const int blocks = (cells + kBlock - 1) / kBlock;
  // Inputs a - first - k for a < blocks * kBlock and k < taps, from `lowest` on.
  const int lowest = -first - (taps - 1);
  padded->assign(static_cast<size_t>(blocks * kBlock + taps - 1), 0.0);
  const int from = std::max(0, lowest),
            to = std::min(cells, lowest + static_cast<int>(padded->size()));
  for (int i = from; i < to; ++i) (*padded)[static_cast<size_t>(i - lowest)] = old[i];
  for (int b = 0; b < blocks; ++b) {
    const int a = b * kBlock;
    const double* x = padded->data() + (a - first - lowest);
    Lanes4 sum[kGroups];
    kernels::ConvolutionSums<Lanes4, kGroups>(
        [&](int k, int v) { return kernels::LoadLanes4(x + 4 * v - k); }, weight, 0, taps, sum);
    double cell_sums[kBlock];
    for (int v = 0; v < kGroups; ++v) kernels::StoreLanes4(cell_sums + 4 * v, sum[v]);
    for (int c = 0; c < kBlock && a + c < cells; ++c) out[a + c] = cell_sums[c];
  }
}

// alpha_new(a) = sum_b K(a - b) alpha_old(b), normalised; uniform where the truncated kernel
// leaves no mass (a jump further than 7 sigma, which the model deems impossible).
void Propagate(const Kernel& kernel, const Eigen::VectorXd& old, Eigen::VectorXd* out,
               std::vector<double>* padded) {
  const int cells = static_cast<int>(old.size());
  out->resize(cells);
  Convolve(kernel.weight.data(), static_cast<int>(kernel.weight.size()), kernel.first, old.data(),
           cells, out->data(), padded);
  const double total = out->sum();
  if (total > 0)
    *out /= total;
  else
    out->setConstant(1.0 / cells);
}

int Draw(const Eigen::VectorXd& weights, simulation::RandomSource* rng) {
  const double total = weights.sum();
  const int cells = static_cast<int>(weights.size());
  if (!(total > 0)) return std::min(cells - 1, static_cast<int>(rng->Uniform() * cells));
  const double target = rng->Uniform() * total;
  double sum = 0;
  for (int i = 0; i < cells; ++i) {
    sum += weights[i];
    if (sum > target) return i;
  }
  return cells - 1;
}

}  // namespace

Eigen::VectorXd ImputeAngleOnLattice(const Eigen::VectorXd& rate_rad_s, double sample_rate_hz,
                                     const AngleLattice& lattice, double noise_per_sample_rad,
                                     const AngleQuantizerOptions& options, AngleQuantizerFit* fit) {
  fit->lattice = lattice;
  fit->noise_per_sample_rad = noise_per_sample_rad;
  fit->ok = false;
  const Eigen::Index n = rate_rad_s.size();
  if (!options.IsValid(&fit->message)) return rate_rad_s;
  if (!lattice.on_lattice || !(lattice.step_rad > 0)) {
    fit->message = "angle_quantizer: the rate is not an angle counter (" + lattice.message + ")";
    return rate_rad_s;
  }
  if (!(noise_per_sample_rad > 0) || !(sample_rate_hz > 0) || n < 2) {
    fit->message = "angle_quantizer: no white rate noise to draw the angle with";
    return rate_rad_s;
  }
  const double q = lattice.step_rad, dt = 1.0 / sample_rate_hz;
  fit->rate_step_rad_s = q * sample_rate_hz;
  std::vector<long long> counts(static_cast<size_t>(n));
  double mean_count = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double increment = rate_rad_s[k] * dt;
    if (!std::isfinite(increment)) {
      fit->message = "angle_quantizer: non-finite samples";
      return rate_rad_s;
    }
    counts[static_cast<size_t>(k)] = std::llround((increment - lattice.offset_rad) / q);
    mean_count += static_cast<double>(counts[static_cast<size_t>(k)]);
  }
  const double mu = q * mean_count / static_cast<double>(n);
  const double sigma = noise_per_sample_rad;
  const int cells = std::clamp(static_cast<int>(std::ceil(options.cells_per_sigma * q / sigma)),
                               options.min_cells, options.max_cells);
  fit->cells = cells;
  const double cell = q / cells;
  std::map<long long, Kernel> kernels;
  const auto kernel = [&](long long count) -> const Kernel& {
    auto found = kernels.find(count);
    if (found == kernels.end())
      found = kernels.emplace(count, MakeKernel(count, q, mu, sigma, cell, cells)).first;
    return found->second;
  };
  // States t = 0..n: t = 0 before the first sample, t = k + 1 after sample k (its transition
  // reads counts[k]). Forward filter, kept every `block` states.
  const Eigen::Index states = n + 1;
  const Eigen::Index block =
      std::max<Eigen::Index>(1, static_cast<Eigen::Index>(std::ceil(std::sqrt(double(states)))));
  std::vector<Eigen::VectorXd> kept;
  Eigen::VectorXd alpha = Eigen::VectorXd::Constant(cells, 1.0 / cells), next(cells);
  std::vector<double> padded;  // Convolve's zero-padded input, reused
  for (Eigen::Index t = 0; t < states; ++t) {
    if (t > 0) {
      Propagate(kernel(counts[static_cast<size_t>(t - 1)]), alpha, &next, &padded);
      alpha.swap(next);
    }
    if (t % block == 0) kept.push_back(alpha);
  }
  // Backward sampling, block by block from the last: recompute the block's filter from its kept
  // state, then draw u_t given u_{t+1}.
  // The block's filters and the draw's weights reuse their storage from block to block and
  // sample to sample (fresh pages and a malloc per sample cost more than the arithmetic).
  simulation::RandomSource rng(simulation::DeriveSeed(static_cast<std::uint64_t>(n), kDrawStream));
  Eigen::VectorXd u(states);
  int next_cell = -1;
  std::vector<Eigen::VectorXd> filtered(static_cast<size_t>(block), Eigen::VectorXd(cells));
  Eigen::VectorXd weights(cells);
  for (Eigen::Index b = static_cast<Eigen::Index>(kept.size()) - 1; b >= 0; --b) {
    const Eigen::Index t0 = b * block, t1 = std::min(states, t0 + block);
    filtered[0] = kept[static_cast<size_t>(b)];
    for (Eigen::Index t = t0 + 1; t < t1; ++t)
      Propagate(kernel(counts[static_cast<size_t>(t - 1)]), filtered[t - t0 - 1], &filtered[t - t0],
                &padded);
    for (Eigen::Index t = t1 - 1; t >= t0; --t) {
      const Eigen::VectorXd& filter = filtered[static_cast<size_t>(t - t0)];
      int drawn = 0;
      if (next_cell < 0) {
        drawn = Draw(filter, &rng);
      } else {
        // p(u_t | u_{t+1}, counts) ~ alpha_t(u_t) K(u_{t+1} - u_t), K of the step into t + 1:
        // non-zero only where next_cell - i lies in the kernel's support.
        const Kernel& into = kernel(counts[static_cast<size_t>(t)]);
        weights.setZero();
        const int size = static_cast<int>(into.weight.size());
        const int i0 = std::max(0, next_cell - into.first - size + 1),
                  i1 = std::min(cells, next_cell - into.first + 1);
        for (int i = i0; i < i1; ++i)
          weights[i] = filter[i] * into.weight[next_cell - i - into.first];
        drawn = Draw(weights.sum() > 0 ? weights : filter, &rng);
      }
      u[t] = -0.5 * q + (drawn + rng.Uniform()) * cell;
      next_cell = drawn;
    }
  }
  Eigen::VectorXd corrected(n);
  for (Eigen::Index k = 0; k < n; ++k)
    corrected[k] = rate_rad_s[k] + (u[k + 1] - u[k]) * sample_rate_hz;
  fit->ok = true;
  fit->message = "";
  return corrected;
}

double NextEmNoise(double sigma, double refitted, double previous_sigma, double previous_refitted,
                   const AngleQuantizerOptions& options, bool* settled) {
  *settled = std::abs(refitted - sigma) <= options.relative_tolerance * sigma;
  // A failed refit: the plain step, which the next draw refuses (no white noise to draw with).
  if (*settled || !(sigma > 0) || !(refitted > 0) || !std::isfinite(refitted)) return refitted;
  const double l = std::log(sigma), g = std::log(refitted) - l;
  double slope = -1.0;  // the plain EM step
  if (previous_sigma > 0 && previous_refitted > 0 && previous_sigma != sigma) {
    const double l0 = std::log(previous_sigma), g0 = std::log(previous_refitted) - l0;
    const double secant = (g - g0) / (l - l0);
    if (std::isfinite(secant) && secant < 0)
      slope = std::clamp(secant, -1.0, -1.0 / options.max_acceleration);
  }
  if (slope == -1.0) return refitted;
  return std::exp(l - g / slope);
}

}  // namespace fogpipe::model
