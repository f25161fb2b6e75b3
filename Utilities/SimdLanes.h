// Lanes of an AVX2 register for sums over neighbour pairs, several pairs at a time: 8 floats or
// 4 doubles (Lanes<Real>), and the slots they read. A slot is four Reals of one particle (x, y, z
// and one more, a mass or a volume; or a velocity and a 0), so that one 16- or 32-byte load fetches
// a neighbour's slot and Lanes::transpose turns kPairBlock slots into the lanes of their four
// components. Gathering each component one by one instead (12-byte Vector3r arrays) cost about
// 5-6 cycles per pair on Zen 3 (bench/pair_loops.cpp).
//
// Where the build has no AVX2 + FMA, CONSPH_SIMD_AVX2 is undefined and the callers run a plain
// loop over the same slots and rows.
#pragma once
#include <cstddef>
#include <vector>

#include "Utilities/ParallelFor.h"
#include "Utilities/Types.h"

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define CONSPH_SIMD_AVX2 1
#endif

namespace consph {

// Pairs per block: the lanes of an AVX2 register (8 floats or 4 doubles).
inline constexpr Index kPairBlock = sizeof(Real) == 4 ? 8 : 4;

// Whether the plugins run their sums a block of pairs at a time (DFSPH's iterations, the
// viscosities): in float builds, where it was measured (bench/RESULTS.md, "Packed pair sums").
// Double builds keep the one-pair-at-a-time loops, bit for bit as before: with the block sums the
// same formulas in another summation order (equal to 3e-16 per particle) moved the resting tank's
// pressure-field RMS in tests/physics/test_probes.cpp from 0.0199 to 0.0204 rho0 g H against its
// bound of 0.02, a reading that sits on its bound and moves with round-off; until that is
// understood, CI's double physics suite runs the loops it was measured with.
inline constexpr bool kPackedPairSums = sizeof(Real) == 4;

// slots[4 i .. 4 i + 3] = fill(i) for every particle i < n (fill writes the four Reals it is given).
template <class Fill>
void packSlots(std::vector<Real>& slots, std::size_t n, Fill&& fill) {
  slots.resize(4 * n);
  parallelFor(n, [&](std::size_t i) { fill(i, &slots[4 * i]); });
}

#if defined(CONSPH_SIMD_AVX2)
namespace simd {

template <class R>
struct Lanes;

template <>
struct Lanes<float> {
  using V = __m256;
  static V set1(float a) { return _mm256_set1_ps(a); }
  static V zero() { return _mm256_setzero_ps(); }
  static V load(const float* p) { return _mm256_loadu_ps(p); }
  static V add(V a, V b) { return _mm256_add_ps(a, b); }
  static V sub(V a, V b) { return _mm256_sub_ps(a, b); }
  static V mul(V a, V b) { return _mm256_mul_ps(a, b); }
  static V div(V a, V b) { return _mm256_div_ps(a, b); }
  static V fmadd(V a, V b, V c) { return _mm256_fmadd_ps(a, b, c); }   // a b + c
  static V fnmadd(V a, V b, V c) { return _mm256_fnmadd_ps(a, b, c); }  // c - a b
  // base[j[k]] in lane k.
  static V gather(const float* base, const Index* j) {
    return _mm256_i32gather_ps(base, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(j)), 4);
  }
  // Lane k of x, y, z, w: the slot of particle j[k].
  static void transpose(const float* slots, const Index* j, V& x, V& y, V& z, V& w) {
    auto twoSlots = [&](int k) {  // slot j[k] in the lower half, j[k + 4] in the upper
      return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(slots + 4 * std::size_t(j[k]))),
                                  _mm_loadu_ps(slots + 4 * std::size_t(j[k + 4])), 1);
    };
    const V t0 = twoSlots(0), t1 = twoSlots(1), t2 = twoSlots(2), t3 = twoSlots(3);
    const V u0 = _mm256_unpacklo_ps(t0, t1), u1 = _mm256_unpackhi_ps(t0, t1);  // x0 x1 y0 y1 | x4 x5 y4 y5; z.., w..
    const V u2 = _mm256_unpacklo_ps(t2, t3), u3 = _mm256_unpackhi_ps(t2, t3);
    x = _mm256_shuffle_ps(u0, u2, _MM_SHUFFLE(1, 0, 1, 0));
    y = _mm256_shuffle_ps(u0, u2, _MM_SHUFFLE(3, 2, 3, 2));
    z = _mm256_shuffle_ps(u1, u3, _MM_SHUFFLE(1, 0, 1, 0));
    w = _mm256_shuffle_ps(u1, u3, _MM_SHUFFLE(3, 2, 3, 2));
  }
  // ((l0 + l4) + (l2 + l6)) + ((l1 + l5) + (l3 + l7)), always in this order.
  static float sum(V v) {
    __m128 s = _mm_add_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
    s = _mm_add_ps(s, _mm_movehl_ps(s, s));
    s = _mm_add_ss(s, _mm_movehdup_ps(s));
    return _mm_cvtss_f32(s);
  }
};

template <>
struct Lanes<double> {
  using V = __m256d;
  static V set1(double a) { return _mm256_set1_pd(a); }
  static V zero() { return _mm256_setzero_pd(); }
  static V load(const double* p) { return _mm256_loadu_pd(p); }
  static V add(V a, V b) { return _mm256_add_pd(a, b); }
  static V sub(V a, V b) { return _mm256_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm256_mul_pd(a, b); }
  static V div(V a, V b) { return _mm256_div_pd(a, b); }
  static V fmadd(V a, V b, V c) { return _mm256_fmadd_pd(a, b, c); }
  static V fnmadd(V a, V b, V c) { return _mm256_fnmadd_pd(a, b, c); }
  static V gather(const double* base, const Index* j) {
    // The masked form with a zero source: the plain one starts from _mm256_undefined_pd, which
    // GCC 12 reports as maybe-uninitialised.
    const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    return _mm256_mask_i32gather_pd(_mm256_setzero_pd(), base, _mm_loadu_si128(reinterpret_cast<const __m128i*>(j)), all, 8);
  }
  static void transpose(const double* slots, const Index* j, V& x, V& y, V& z, V& w) {
    const V t0 = _mm256_loadu_pd(slots + 4 * std::size_t(j[0])), t1 = _mm256_loadu_pd(slots + 4 * std::size_t(j[1]));
    const V t2 = _mm256_loadu_pd(slots + 4 * std::size_t(j[2])), t3 = _mm256_loadu_pd(slots + 4 * std::size_t(j[3]));
    const V u0 = _mm256_unpacklo_pd(t0, t1), u1 = _mm256_unpackhi_pd(t0, t1);  // x0 x1 | z0 z1; y0 y1 | w0 w1
    const V u2 = _mm256_unpacklo_pd(t2, t3), u3 = _mm256_unpackhi_pd(t2, t3);
    x = _mm256_permute2f128_pd(u0, u2, 0x20);
    z = _mm256_permute2f128_pd(u0, u2, 0x31);
    y = _mm256_permute2f128_pd(u1, u3, 0x20);
    w = _mm256_permute2f128_pd(u1, u3, 0x31);
  }
  // (l0 + l2) + (l1 + l3).
  static double sum(V v) {
    __m128d s = _mm_add_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
    s = _mm_add_sd(s, _mm_unpackhi_pd(s, s));
    return _mm_cvtsd_f64(s);
  }
};

}  // namespace simd
#endif

}  // namespace consph
