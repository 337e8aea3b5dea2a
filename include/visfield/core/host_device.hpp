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

/// π in the precision of Real.
template <class Real>
inline constexpr Real kPi = static_cast<Real>(3.14159265358979323846);

}  // namespace vf::hd
