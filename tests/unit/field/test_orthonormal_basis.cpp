// The branchless orthonormal basis shared by BeamField's PSF frames and the ObjectField's
// hemisphere frames: orthonormal, right-handed, the identity at +z, on both hemispheres.

#include <gtest/gtest.h>

#include <cmath>

#include "visfield/core/orthonormal_basis.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"

namespace vf {
namespace {

using V = hd::Vec3<double>;

V cross(const V& a, const V& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

TEST(OrthonormalBasis, IsOrthonormalAndRightHandedEverywhere) {
  Rng rng(11);
  for (int q = 0; q < 100000; ++q) {
    const Vec3f f = uniform_sphere(rng.uniform(), rng.uniform());
    const double l = std::sqrt(double(f.x) * f.x + double(f.y) * f.y + double(f.z) * f.z);
    const V w{f.x / l, f.y / l, q % 100 == 0 ? 0.0 : f.z / l};
    const double lw = std::sqrt(hd::dot(w, w));
    const V wn{w.x / lw, w.y / lw, w.z / lw};
    const OrthonormalBasis<double> b = orthonormal_basis(wn);
    EXPECT_NEAR(hd::dot(b.u, b.u), 1.0, 1e-12);
    EXPECT_NEAR(hd::dot(b.v, b.v), 1.0, 1e-12);
    EXPECT_NEAR(hd::dot(b.u, b.v), 0.0, 1e-12);
    EXPECT_NEAR(hd::dot(b.u, wn), 0.0, 1e-12);
    EXPECT_NEAR(hd::dot(b.v, wn), 0.0, 1e-12);
    const V c = cross(b.u, b.v);
    EXPECT_NEAR(c.x, wn.x, 1e-12);
    EXPECT_NEAR(c.y, wn.y, 1e-12);
    EXPECT_NEAR(c.z, wn.z, 1e-12);
  }
}

TEST(OrthonormalBasis, IsTheIdentityAtPlusZ) {
  const OrthonormalBasis<double> b = orthonormal_basis(V{0.0, 0.0, 1.0});
  EXPECT_EQ(b.u.x, 1.0);
  EXPECT_EQ(b.u.y, 0.0);
  EXPECT_EQ(b.u.z, 0.0);
  EXPECT_EQ(b.v.x, 0.0);
  EXPECT_EQ(b.v.y, 1.0);
  EXPECT_EQ(b.v.z, 0.0);
}

}  // namespace
}  // namespace vf
