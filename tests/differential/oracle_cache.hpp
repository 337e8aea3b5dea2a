#pragma once
/// \file The oracle's answers kept on disk, so that the many test processes that compare structures
/// against one scene's oracle (ctest runs each test in a process of its own) compute them once. An
/// entry is named by a hash of what decides the answers: the oracle's kind, the configure-time hash
/// of the oracle's sources (VISFIELD_ORACLE_SOURCES_HASH: brute force, the triangle test, this
/// harness), the scene's triangles, objects and transforms, the rays and whether occluded() was
/// queried. The folder is VISFIELD_ORACLE_CACHE from the environment, else the build's oracle-cache/.
/// Concurrent processes computing one entry take a file lock: one computes, the others read.

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "differential/harness.hpp"

namespace vf::test {

/// FNV-1a, 64 bits, over bytes appended one span at a time.
class Fnv1a {
 public:
  /// Adds the bytes of `values` (trivially copyable, padding included only where the caller's type has none).
  template <class T>
  Fnv1a& add(std::span<const T> values) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
    for (std::size_t i = 0; i < values.size_bytes(); ++i) hash_ = (hash_ ^ bytes[i]) * 0x100000001b3ull;
    return *this;
  }
  /// Adds the characters of `text` and its length.
  Fnv1a& add(std::string_view text) {
    const std::uint64_t n = text.size();
    add(std::span<const std::uint64_t>(&n, 1));
    return add(std::span<const char>(text.data(), text.size()));
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

/// Adds a ray set to `h` field by field (Ray has no padding, but say so rather than rely on it).
inline void hash_rays(Fnv1a& h, std::span<const Ray> rays) {
  for (const Ray& r : rays) {
    const float f[8] = {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax};
    h.add(std::span<const float>(f, 8));
  }
}

/// A scene's identity for the cache: its world-space triangles with their triangle and object ids,
/// and each object's mesh and transform (the instanced oracle answers in object space).
inline std::uint64_t scene_hash(const Scene& scene, const TriangleSet& flattened) {
  Fnv1a h;
  for (const auto& t : flattened.triangles)
    for (const Vec3f& p : t) {
      const float f[3] = {p.x, p.y, p.z};
      h.add(std::span<const float>(f, 3));
    }
  h.add(std::span<const std::uint32_t>(flattened.prim)).add(std::span<const std::uint32_t>(flattened.instance));
  for (const Instance& o : scene.instances()) {
    const std::uint32_t ids[2] = {o.id, o.mesh};
    h.add(std::span<const std::uint32_t>(ids, 2));
    const Mat3& m = o.transform.rotation;
    const Vec3f& t = o.transform.translation;
    const float f[13] = {m.rows[0].x, m.rows[0].y, m.rows[0].z, m.rows[1].x, m.rows[1].y, m.rows[1].z,
                         m.rows[2].x, m.rows[2].y, m.rows[2].z, o.transform.scale,   t.x,         t.y, t.z};
    h.add(std::span<const float>(f, 13));
  }
  return h.value();
}

/// The cache folder (created on first use).
inline std::filesystem::path oracle_cache_dir() {
  const char* env = std::getenv("VISFIELD_ORACLE_CACHE");
  return env && *env ? std::filesystem::path(env) : std::filesystem::path(VISFIELD_ORACLE_CACHE_DIR);
}

namespace detail {

inline bool read_answers(const std::filesystem::path& file, std::size_t n, OracleAnswers& out) {
  std::ifstream in(file, std::ios::binary);
  std::uint64_t count = 0;
  if (!in.read(reinterpret_cast<char*>(&count), sizeof count) || count != n) return false;
  out.closest.resize(n);
  out.occluded.resize(n);
  in.read(reinterpret_cast<char*>(out.closest.data()), static_cast<std::streamsize>(n * sizeof(Hit)));
  in.read(reinterpret_cast<char*>(out.occluded.data()), static_cast<std::streamsize>(n));
  return static_cast<bool>(in) && in.peek() == std::char_traits<char>::eof();
}

inline void write_answers(const std::filesystem::path& file, const OracleAnswers& a) {
  const std::filesystem::path tmp = file.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    const std::uint64_t count = a.closest.size();
    out.write(reinterpret_cast<const char*>(&count), sizeof count);
    out.write(reinterpret_cast<const char*>(a.closest.data()), static_cast<std::streamsize>(a.closest.size() * sizeof(Hit)));
    out.write(reinterpret_cast<const char*>(a.occluded.data()), static_cast<std::streamsize>(a.occluded.size()));
  }
  std::filesystem::rename(tmp, file);
}

}  // namespace detail

/// oracle_answers(oracle, rays, query_occluded) for the scene named by `scene` (scene_hash), read
/// from the cache when a process computed them before, else computed and stored. With
/// `query_occluded`, the oracle's own occluded() must agree with its closest hits: a disagreement
/// fails the calling test (and is not stored).
template <Accelerator O>
OracleAnswers cached_oracle_answers(const O& oracle, std::uint64_t scene, std::span<const Ray> rays, bool query_occluded) {
  Fnv1a h;
  h.add(O::name()).add(VISFIELD_ORACLE_SOURCES_HASH).add(std::span<const std::uint64_t>(&scene, 1));
  hash_rays(h, rays);
  const std::uint8_t occluded_too = query_occluded ? 1 : 0;
  h.add(std::span<const std::uint8_t>(&occluded_too, 1));
  const std::filesystem::path dir = oracle_cache_dir();
  std::filesystem::create_directories(dir);
  char name[40];
  std::snprintf(name, sizeof name, "%016llx.oracle", static_cast<unsigned long long>(h.value()));
  const std::filesystem::path file = dir / name;

  // One process computes an entry; the others wait on the lock, then read it.
  const std::string lock_path = file.string() + ".lock";
  const int lock = ::open(lock_path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (lock >= 0) ::flock(lock, LOCK_EX);
  OracleAnswers answers;
  if (!detail::read_answers(file, rays.size(), answers)) {
    std::size_t inconsistent = 0;
    answers = oracle_answers(oracle, rays, query_occluded, &inconsistent);
    EXPECT_EQ(inconsistent, 0u) << O::name() << ": the oracle's occluded() disagrees with its intersect()";
    if (inconsistent == 0) detail::write_answers(file, answers);
  }
  if (lock >= 0) ::close(lock);  // releases the lock
  return answers;
}

}  // namespace vf::test
