#pragma once
/// \file What lets a header be compiled for both the CPU and a CUDA device: the function qualifier
/// and the scalar maths functions under one name for float and double. Headers that include it
/// use no STL, TBB or exceptions, so that the CUDA kernels run the very code the CPU runs.

#include <math.h>

#if defined(__CUDACC__)
#define VF_HOST_DEVICE __host__ __device__
#else
#define VF_HOST_DEVICE
#endif

// Unrolls the next loop in device code (where indexing a register-held array needs constant
// indices); the host compiler chooses for itself.
#if defined(__CUDA_ARCH__)
#define VF_UNROLL _Pragma("unroll")
#else
#define VF_UNROLL
#endif

namespace vf::hd {

/// sqrt for float and double; host and device.
VF_HOST_DEVICE inline float sqrt(float x) { return ::sqrtf(x); }
/// sqrt for double; host and device.
VF_HOST_DEVICE inline double sqrt(double x) { return ::sqrt(x); }
/// |x| for float; host and device.
VF_HOST_DEVICE inline float abs(float x) { return ::fabsf(x); }
/// |x| for double; host and device.
VF_HOST_DEVICE inline double abs(double x) { return ::fabs(x); }
/// floor for float; host and device.
VF_HOST_DEVICE inline float floor(float x) { return ::floorf(x); }
/// floor for double; host and device.
VF_HOST_DEVICE inline double floor(double x) { return ::floor(x); }
/// cos for float; host and device.
VF_HOST_DEVICE inline float cos(float x) { return ::cosf(x); }
/// cos for double; host and device.
VF_HOST_DEVICE inline double cos(double x) { return ::cos(x); }
/// sin for float; host and device.
VF_HOST_DEVICE inline float sin(float x) { return ::sinf(x); }
/// sin for double; host and device.
VF_HOST_DEVICE inline double sin(double x) { return ::sin(x); }
/// atan2 for float; host and device.
VF_HOST_DEVICE inline float atan2(float y, float x) { return ::atan2f(y, x); }
/// atan2 for double; host and device.
VF_HOST_DEVICE inline double atan2(double y, double x) { return ::atan2(y, x); }
/// copysign for float; host and device.
VF_HOST_DEVICE inline float copysign(float x, float s) { return ::copysignf(x, s); }
/// copysign for double; host and device.
VF_HOST_DEVICE inline double copysign(double x, double s) { return ::copysign(x, s); }
/// a·b + c rounded once (IEEE fused multiply-add), float: the same bits on every CPU and device
/// (one instruction where the CPU has FMA, a library call otherwise); host and device.
VF_HOST_DEVICE inline float fma(float a, float b, float c) { return ::fmaf(a, b, c); }
/// a·b + c rounded once, double; host and device.
VF_HOST_DEVICE inline double fma(double a, double b, double c) { return ::fma(a, b, c); }
/// 1/x and 1/y from one division, 1/(x·y) times y and times x (within 1.5 ulp of the quotients;
/// x·y must neither overflow nor vanish): the SIMD field lookup's divider is its busiest unit.
VF_HOST_DEVICE inline void reciprocals(float x, float y, float& inv_x, float& inv_y) {
  const float p = 1.0f / (x * y);
  inv_x = y * p;
  inv_y = x * p;
}

/// atan(x) for |x| <= 1 as the field lookups compute it in float: an odd minimax polynomial of
/// degree 11 (|error| < 2e-6 rad) evaluated by Horner's rule in explicit fused multiply-adds, which
/// round once on every CPU, SIMD lane and CUDA thread alike, so all compute the very same float. O(1).
VF_HOST_DEVICE inline float atan_unit(float x) {
  const float x2 = x * x;
  float p = -0.01172120f;
  p = fma(p, x2, 0.05265332f);
  p = fma(p, x2, -0.11643287f);
  p = fma(p, x2, 0.19354346f);
  p = fma(p, x2, -0.33262347f);
  p = fma(p, x2, 0.99997726f);
  return x * p;
}
/// atan(x) for |x| <= 1 in double: the library's (the exact reference for the float polynomial).
VF_HOST_DEVICE inline double atan_unit(double x) { return ::atan(x); }

/// atan2(y, x) as the field lookups compute it in float: atan_unit of the smaller over the larger
/// magnitude, then the octant and quadrant folded back (0 when both are 0; y = −0 counts as
/// positive). Same operations in the same order as the SIMD and CUDA lookups. O(1).
VF_HOST_DEVICE inline float lookup_atan2(float y, float x) {
  const float ax = ::fabsf(x), ay = ::fabsf(y);
  const float big = ax < ay ? ay : ax, small = ay < ax ? ay : ax;
  float a = atan_unit(big > 0.0f ? small / big : 0.0f);
  if (ay > ax) a = 1.57079632679489661923f - a;
  if (x < 0.0f) a = 3.14159265358979323846f - a;
  return y < 0.0f ? -a : a;
}
/// atan2 in double: the library's.
VF_HOST_DEVICE inline double lookup_atan2(double y, double x) { return ::atan2(y, x); }

/// sin and cos of phi in [0, π/2] as the lattice directions are computed in float: Taylor
/// polynomials to x^13 and x^14 (truncation below 1e-9, so float rounding is all the error),
/// evaluated with separate multiplies and adds so that SIMD lanes and CUDA threads get the same
/// bits. O(1).
VF_HOST_DEVICE inline void quadrant_sincos(float phi, float& s, float& c) {
  const float x2 = phi * phi;
  float ps = 1.0f / 6227020800.0f;
  ps = ps * x2 - 1.0f / 39916800.0f;
  ps = ps * x2 + 1.0f / 362880.0f;
  ps = ps * x2 - 1.0f / 5040.0f;
  ps = ps * x2 + 1.0f / 120.0f;
  ps = ps * x2 - 1.0f / 6.0f;
  ps = ps * x2 + 1.0f;
  s = phi * ps;
  float pc = -1.0f / 87178291200.0f;
  pc = pc * x2 + 1.0f / 479001600.0f;
  pc = pc * x2 - 1.0f / 3628800.0f;
  pc = pc * x2 + 1.0f / 40320.0f;
  pc = pc * x2 - 1.0f / 720.0f;
  pc = pc * x2 + 1.0f / 24.0f;
  pc = pc * x2 - 0.5f;
  c = pc * x2 + 1.0f;
}
/// sin and cos in double: the library's.
VF_HOST_DEVICE inline void quadrant_sincos(double phi, double& s, double& c) {
  s = ::sin(phi);
  c = ::cos(phi);
}

/// min of two values of one type; host and device.
template <class T>
VF_HOST_DEVICE inline T min(T a, T b) { return b < a ? b : a; }
/// max of two values of one type; host and device.
template <class T>
VF_HOST_DEVICE inline T max(T a, T b) { return a < b ? b : a; }
/// x clamped to [lo, hi]; host and device.
template <class T>
VF_HOST_DEVICE inline T clamp(T x, T lo, T hi) { return x < lo ? lo : (hi < x ? hi : x); }

/// A plain 3-vector of float or double for the device-neutral lookups (no operators on purpose:
/// the few formulas spell their components out).
template <class Real>
struct Vec3 {
  Real x, y, z;
};

/// Dot product; host and device.
template <class Real>
VF_HOST_DEVICE inline Real dot(const Vec3<Real>& a, const Vec3<Real>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
/// a · b in two fused multiply-adds, z first: x·x' + (y·y' + z·z'), the product z·z' rounded, the
/// rest rounded once a step (the field lookups' dot, the same bits on CPU, SIMD lanes and device).
template <class Real>
VF_HOST_DEVICE inline Real fused_dot(const Vec3<Real>& a, const Vec3<Real>& b) { return fma(a.x, b.x, fma(a.y, b.y, a.z * b.z)); }

/// π in the precision of Real.
template <class Real>
inline constexpr Real kPi = static_cast<Real>(3.14159265358979323846);

}  // namespace vf::hd
