// Compile-time AR orders for the per-sample loops (internal to algorithms/kalman).
//
// The steady-state loops are latency-bound recursions over a handful of doubles; with the order
// known at compile time the compiler unrolls them and keeps the state in registers. Orders 1..8
// get their own instantiation, anything else the runtime-order one (P == 0).
#pragma once

#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

namespace fogpipe::kalman::internal {

constexpr int kMaxFixedOrder = 8;

/// p doubles: a plain array for P > 0, a std::vector for the runtime order P == 0.
template <int P>
struct Buffer {
  explicit Buffer(int) {}
  double* get() { return data; }
  double data[P];
};
template <>
struct Buffer<0> {
  explicit Buffer(int p) : data(static_cast<std::size_t>(p)) {}
  double* get() { return data.data(); }
  std::vector<double> data;
};

/// Calls f(std::integral_constant<int, P>) with P = p for 1 <= p <= kMaxFixedOrder, else P = 0.
template <typename F>
void WithFixedOrder(int p, F&& f) {
  switch (p) {
    case 1:
      return f(std::integral_constant<int, 1>());
    case 2:
      return f(std::integral_constant<int, 2>());
    case 3:
      return f(std::integral_constant<int, 3>());
    case 4:
      return f(std::integral_constant<int, 4>());
    case 5:
      return f(std::integral_constant<int, 5>());
    case 6:
      return f(std::integral_constant<int, 6>());
    case 7:
      return f(std::integral_constant<int, 7>());
    case 8:
      return f(std::integral_constant<int, 8>());
    default:
      return f(std::integral_constant<int, 0>());
  }
}

}  // namespace fogpipe::kalman::internal
