#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <thread>

#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/core/statistics.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/core/text.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {
namespace {

TEST(Transform, RotationScaleTranslationRoundTrip) {
  Transform t;
  t.rotation = Mat3::euler_xyz({30.0f, -45.0f, 60.0f});
  t.translation = {1, 2, 3};
  t.scale = 2.5f;
  const Vec3f p{0.3f, -0.7f, 1.1f};
  // The inverse the queries use maps the point back: the origin of a ray through it.
  const Vec3f back = t.inverse().apply(Ray{t.apply_point(p), {0, 0, 1}}).org;
  EXPECT_NEAR(back.x, p.x, 1e-5f);
  EXPECT_NEAR(back.y, p.y, 1e-5f);
  EXPECT_NEAR(back.z, p.z, 1e-5f);
  EXPECT_NEAR(length(t.apply_vector({1, 0, 0})), 2.5f, 1e-5f);
  const Vec3f z = Mat3::rotation({0, 0, 1}, 90.0f) * Vec3f{1, 0, 0};
  EXPECT_NEAR(z.y, 1.0f, 1e-6f);
}

TEST(Transform, InverseMapsRaysWithTheSameParameter) {
  Transform t;
  t.rotation = Mat3::euler_xyz({10.0f, 70.0f, -20.0f});
  t.translation = {-3, 0.5f, 8};
  t.scale = 0.25f;
  const Ray world{{1, 2, 3}, {0.3f, -0.4f, 0.5f}, 0.5f, 7.0f};
  const Ray local = t.inverse().apply(world);
  EXPECT_EQ(local.tmin, world.tmin);
  EXPECT_EQ(local.tmax, world.tmax);
  for (const float s : {0.0f, 1.0f, 4.5f}) {
    const Vec3f a = t.apply_point(local.org + local.dir * s), b = world.org + world.dir * s;
    EXPECT_NEAR(length(a - b), 0.0f, 1e-5f * length(b)) << "t = " << s;
  }
  // The identity passes rays through bit for bit.
  const Ray same = Transform{}.inverse().apply(world);
  EXPECT_EQ(same.org, world.org);
  EXPECT_EQ(same.dir, world.dir);
  EXPECT_TRUE(Transform{}.inverse().identity);
  EXPECT_FALSE(t.inverse().identity);
}

TEST(Transform, NormalsMoveAsTheCrossProductOfMovedEdges) {
  Transform t;
  t.rotation = Mat3::rotation({1, 2, 3}, 40.0f);
  t.scale = 3.0f;
  t.translation = {5, 5, 5};
  const Vec3f p0{0.1f, 0.2f, 0.3f}, p1{1.0f, 0.0f, 0.2f}, p2{0.0f, 1.5f, -0.4f};
  const Vec3f object_normal = cross(p1 - p0, p2 - p0);
  const Vec3f world_normal = cross(t.apply_point(p1) - t.apply_point(p0), t.apply_point(p2) - t.apply_point(p0));
  const Vec3f moved = t.apply_normal(object_normal);
  EXPECT_NEAR(length(moved - world_normal), 0.0f, 1e-4f * length(world_normal));
}

TEST(Transform, ValidityAndIdentity) {
  EXPECT_TRUE(Transform{}.is_identity());
  EXPECT_TRUE(Transform{}.is_valid());
  Transform t;
  t.scale = -1.0f;
  EXPECT_FALSE(t.is_valid());
  t.scale = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(t.is_valid());
  t = Transform{};
  t.rotation.rows[1].z = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(t.is_valid());
  t = Transform{};
  t.translation.y = 1e-30f;
  EXPECT_FALSE(t.is_identity());
}

TEST(TriangleSet, FlattenAppliesInstancesAndDropsDegenerates) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 1, 3}, {1, 1, 2}};  // the last two have zero area
  Scene scene = scene_from_mesh(mesh);
  Transform moved;
  moved.translation = {0, 0, 5};
  scene.add_instance(0, moved);
  const TriangleSet set = flatten(scene);
  ASSERT_EQ(set.size(), 2u);
  EXPECT_EQ(set.degenerate_count, 4u);
  EXPECT_EQ(set.prim[1], 0u);
  EXPECT_EQ(set.instance[1], 1u);
  EXPECT_FLOAT_EQ(set.triangles[1][0].z, 5.0f);
  EXPECT_FLOAT_EQ(set.bounds.hi.z, 5.0f);
}

TEST(Rng, SameKeysSameNumbersDifferentKeysDiffer) {
  Rng a(42, 7, 3), b(42, 7, 3), c(42, 7, 4);
  bool differs = false;
  for (int i = 0; i < 16; ++i) {
    const float x = a.uniform();
    EXPECT_EQ(x, b.uniform());
    differs |= x != c.uniform();
    EXPECT_GE(x, 0.0f);
    EXPECT_LT(x, 1.0f);
  }
  EXPECT_TRUE(differs);
}

// Jumping ahead n numbers lands where n draws do, whatever n (0, 1, odd, powers of two, large).
TEST(Rng, AdvancedLandsWhereDrawsDo) {
  for (const std::uint64_t n : {0ull, 1ull, 2ull, 31ull, 32ull, 33ull, 1000ull, 65537ull}) {
    Rng drawn(9, 4, n);
    const Rng jumped = drawn.advanced(n);
    for (std::uint64_t i = 0; i < n; ++i) drawn.next_u32();
    EXPECT_EQ(jumped.state(), drawn.state()) << n;
    EXPECT_EQ(jumped.increment(), drawn.increment()) << n;
  }
}

TEST(Sampling, CosineHemisphereHasMeanCosineTwoThirds) {
  Rng rng(1);
  double sum = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const Vec3f d = cosine_hemisphere(rng.uniform(), rng.uniform());
    ASSERT_NEAR(length(d), 1.0f, 1e-4f);
    ASSERT_GE(d.z, 0.0f);
    sum += d.z;
  }
  EXPECT_NEAR(sum / n, 2.0 / 3.0, 0.005);
}

TEST(Text, FormattedPrintsOneDoubleAsThePatternSays) {
  EXPECT_EQ(formatted("%.2f", 3.14159), "3.14");
  EXPECT_EQ(formatted("%g", 1e9), "1e+09");
  EXPECT_EQ(formatted("approx: %.1f%% differ", 12.345), "approx: 12.3% differ");
  EXPECT_EQ(formatted("%.3f", -0.0005), "-0.001");
}

TEST(Memory, RequestsBeyondTheAvailableMemoryAreRefusedWithTheEstimate) {
  clear_memory_limit();
  const double available = static_cast<double>(available_memory_bytes());
  ASSERT_GT(available, 0.0);
  ASSERT_LE(available, static_cast<double>(physical_memory_bytes()));
  EXPECT_NO_THROW(require_memory(1 << 20, "a small request"));
  try {
    require_memory(2.0 * available, "a grid of 10^12 cells");
    FAIL() << "twice the available memory was granted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find("a grid of 10^12 cells would need about " + format_bytes(2.0 * available)), 0u) << what;
    EXPECT_NE(what.find("more than the available memory ("), std::string::npos) << what;
  }
}

TEST(Memory, ASetLimitReplacesTheAvailableMemoryAndNamesItsSource) {
  set_memory_limit(1024.0 * 1024.0, "--max-memory 1.00 MiB");
  EXPECT_EQ(memory_limit().bytes, 1024.0 * 1024.0);
  EXPECT_NO_THROW(require_memory(1024.0 * 1024.0, "exactly the limit"));
  try {
    require_memory(1024.0 * 1024.0 + 1.0, "one byte more");
    FAIL() << "a request over the set limit was granted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "one byte more would need about 1.00 MiB, more than --max-memory 1.00 MiB");
  }
  clear_memory_limit();
  EXPECT_NE(memory_limit().source.find("available memory"), std::string::npos);
}

TEST(Memory, SizesAreReadAsPeopleWriteThem) {
  constexpr double kKiB = 1024.0, kMiB = kKiB * 1024.0, kGiB = kMiB * 1024.0;
  EXPECT_EQ(parse_byte_size("4G"), 4 * kGiB);
  EXPECT_EQ(parse_byte_size("4GiB"), 4 * kGiB);
  EXPECT_EQ(parse_byte_size("4 GB"), 4 * kGiB);
  EXPECT_EQ(parse_byte_size("512M"), 512 * kMiB);
  EXPECT_EQ(parse_byte_size("1.5g"), 1.5 * kGiB);
  EXPECT_EQ(parse_byte_size("64k"), 64 * kKiB);
  EXPECT_EQ(parse_byte_size("2T"), 2 * kGiB * 1024.0);
  EXPECT_EQ(parse_byte_size("1e9"), 1e9);
  EXPECT_EQ(parse_byte_size("100B"), 100.0);
  for (const char* bad : {"", "G", "0", "-1G", "4X", "4GiBs", "nan", "inf", "1e400"})
    EXPECT_FALSE(parse_byte_size(bad).has_value()) << bad;
}

TEST(Memory, SizesAreWrittenForPeople) {
  EXPECT_EQ(format_bytes(950), "950 B");
  EXPECT_EQ(format_bytes(12.5 * 1024), "12.5 KiB");
  EXPECT_EQ(format_bytes(4.4 * 1024 * 1024), "4.40 MiB");
  EXPECT_EQ(format_bytes(2.5 * 1024 * 1024 * 1024), "2.50 GiB");
}

TEST(Memory, LargeArraysStartOnHugePageBoundariesAndSmallOnesAsAsked) {
  for (const std::size_t bytes : {std::size_t{100}, kHugePageBytes - 1, kHugePageBytes, 3 * kHugePageBytes + 5}) {
    auto* storage = static_cast<unsigned char*>(allocate_aligned(bytes, 64));
    const auto address = reinterpret_cast<std::uintptr_t>(storage);
    EXPECT_EQ(address % (bytes < kHugePageBytes ? 64 : kHugePageBytes), 0u) << bytes;
    storage[0] = 1;  // the whole range is writable
    storage[bytes - 1] = 2;
    EXPECT_EQ(storage[0] + storage[bytes - 1], 3);
    free_aligned(storage, bytes, 64);
  }
}

TEST(Statistics, MedianOfOddAndEvenCounts) {
  EXPECT_EQ(median({}), 0.0);
  EXPECT_EQ(median({3.0}), 3.0);
  EXPECT_EQ(median({5.0, 1.0, 4.0}), 4.0);
  EXPECT_EQ(median({5.0, 1.0, 4.0, 2.0}), 3.0);
}

TEST(Stopwatch, MeasuresTheTimeThatPassedInMilliseconds) {
  // Bounded below by the sleep and above by the steady clock around the whole call: a wrong unit or
  // clock fails one side whatever the machine's load.
  const auto before = std::chrono::steady_clock::now();
  const double ms = time_ms([] { std::this_thread::sleep_for(std::chrono::milliseconds(20)); });
  const double outer_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - before).count();
  EXPECT_GE(ms, 20.0);
  EXPECT_LE(ms, outer_ms);
}

}  // namespace
}  // namespace vf
