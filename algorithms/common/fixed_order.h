// Compile-time AR orders for the per-sample loops (internal to algorithms/: kalman, ar).
//
// The steady-state loops are latency-bound recursions over a handful of doubles; with the order
// known at compile time the compiler unrolls them and keeps the state in registers. Orders 1..8
// get their own instantiation, anything else the runtime-order one (P == 0).
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace fogpipe::fixed_order {

constexpr int kMaxFixedOrder = 8;

/// p values of type T (doubles, or a SIMD vector type), value-initialised for P == 0: a plain
/// array for P > 0, a heap block for the runtime order P == 0.
template <int P, typename T = double>
struct Buffer {
  explicit Buffer(int) {}
  T* get() { return data; }
  T data[P];
};
// The heap block is aligned to kAlignment whatever alignof(T) says: a vector type's alignment
// differs between the baseline and the AVX2 clones of FOGPIPE_LANE_KERNEL (kernels/lanes.h).
template <typename T>
struct Buffer<0, T> {
  static constexpr std::size_t kAlignment = 64;
  explicit Buffer(int p) : storage(static_cast<std::size_t>(p) * sizeof(T) + kAlignment) {
    const auto address = reinterpret_cast<std::uintptr_t>(storage.data());
    data = reinterpret_cast<T*>((address + kAlignment - 1) / kAlignment * kAlignment);
    for (int i = 0; i < p; ++i) new (data + i) T();
  }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  T* get() { return data; }
  std::vector<unsigned char> storage;
  T* data = nullptr;
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

constexpr int kMaxWideFixedOrder = 12;

/// As WithFixedOrder, for 1 <= p <= kMaxWideFixedOrder (the sweep's default orders are 2..12):
/// for the per-sample loops whose work grows like p or p^2, where an unrolled order 9..12 still
/// pays for its code size.
template <typename F>
void WithWideFixedOrder(int p, F&& f) {
  if (p <= kMaxFixedOrder) return WithFixedOrder(p, f);
  switch (p) {
    case 9:
      return f(std::integral_constant<int, 9>());
    case 10:
      return f(std::integral_constant<int, 10>());
    case 11:
      return f(std::integral_constant<int, 11>());
    case 12:
      return f(std::integral_constant<int, 12>());
    default:
      return f(std::integral_constant<int, 0>());
  }
}

}  // namespace fogpipe::fixed_order
