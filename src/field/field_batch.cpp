// ObjectField's batch queries: the lanes kernel of field_kernel.hpp at 32, 16 or 8 lanes (two or
// one AVX-512 packets, two or one AVX2 packets), trace_field() for the remainder, for width 1 and
// where the kernel does not apply. All give the same bits. A kernel file: compiled once per
// instruction set (src/core/isa_dispatch.hpp).

// GCC 12 reports the undefined-value operands of its own avx512fintrin.h (`__Y = __Y` in _mm512_undefined_*) as
// uninitialised once the kernel is inlined: a false positive of the compiler's headers.
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <algorithm>
#include <numeric>
#include <vector>

#include <tbb/blocked_range.h>

#include "core/isa_dispatch.hpp"
#include "field_kernel.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/field/object_field.hpp"

namespace vf::isa_avx512 {
void field_trace_batch(const field::ObjectField& f, const field::ObjectRays& rays, field::FieldAnswer* out, int width);
void field_trace_rays(const field::ObjectField& f, const Ray* rays, const std::uint32_t* index, std::size_t count,
                      const InverseTransform& to_object, const float* limit, field::FieldAnswer* out, int width);
void field_mark_occluded(const field::ObjectField& f, const Ray* rays, const std::uint32_t* index, std::size_t count,
                         const InverseTransform& to_object, std::uint8_t* occluded, int width);
void field_mark_occluded(const field::ObjectField& f, const field::ObjectRays& rays, std::uint8_t* occluded, int width);
int field_batch_width(int width);
}  // namespace vf::isa_avx512

namespace vf::field {
namespace {

/// The lanes a build can run for a requested width (0: the widest): 32, 16, 8 or 1.
int resolved_width(int width) {
#if defined(__AVX512F__)
  constexpr int widest = 32;
#elif defined(__AVX2__) && defined(__FMA__)
  constexpr int widest = 16;
#else
  constexpr int widest = 1;
#endif
  if (width <= 0 || width > widest) return widest;
  return width >= 32 ? 32 : width >= 16 ? 16 : width >= 8 ? 8 : 1;
}

/// Calls run(L{}) with the lanes of `width` where this build has them, nothing otherwise: 32 is two
/// AVX-512 packets side by side, 16 one (or two AVX2 packets without AVX-512), 8 one AVX2 packet.
/// Two packets side by side run faster than one of the same width: the query's steps are long
/// dependency chains, and the second packet's fill the cycles the first waits on (AMD EPYC, intra AO
/// on the bunny: 16 -> 32 lanes 186-189 -> 233-239 Mrays/s; AVX2 8 -> 16 lanes 99 -> 139-147).
template <class Run>
void at_width(int width, const Run& run) {
#if defined(__AVX512F__)
  if (width == 32) run(lanes::Pair<lanes::Avx512>{});
  if (width == 16) run(lanes::Avx512{});
#elif defined(__AVX2__) && defined(__FMA__)
  if (width == 16) run(lanes::Pair<lanes::Avx2>{});
#endif
#if defined(__AVX2__) && defined(__FMA__)
  if (width == 8) run(lanes::Avx2{});
#endif
  (void)width, (void)run;
}

/// Streams the first count − count % width rays through FieldKernel<L> for the width (32, 16 or 8):
/// `load(kernel, k)` gives packet k's rays and `emit(kernel, k, answer)` takes its answers. Returns
/// how many rays it took (0 when the width is 1 or the kernel cannot read the tables).
template <class Load, class Emit>
std::size_t run_lanes(const FieldTables& f, int width, std::size_t count, std::size_t cell_bytes, std::size_t normal_bytes,
                      const Load& load, const Emit& emit) {
  std::size_t done = 0;
  const auto run = [&]<class L>(L) {
    using Kernel = FieldKernel<L>;
    if (!Kernel::reads(cell_bytes, normal_bytes) || f.position_lookup == PositionLookup::lines) return;
    const std::size_t packets = count / Kernel::kWidth;
    Kernel::stream(
        f, packets, [&](std::size_t k) { return load(Kernel{}, k * Kernel::kWidth); },
        [&](std::size_t k, const typename Kernel::Answer& a) { emit(Kernel{}, k * Kernel::kWidth, a); });
    done = packets * Kernel::kWidth;
  };
  at_width(width, run);
  return done;
}

/// Runs FieldKernel<L>::stream_culled for the width (32, 16 or 8) over the world-space candidates, then
/// the candidates it leaves (the last partial packets) as packets whose spare lanes repeat their last
/// ray (among many objects, most of an object's few rays are such); everything at width 1, or when
/// the kernel cannot read the tables, one at a time through `one(k)`.
template <class Emit, class One>
void run_culled(const FieldTables& f, int width, const Ray* rays, const std::uint32_t* index, std::size_t count, const float* limit,
                const InverseTransform& to_object, std::size_t cell_bytes, std::size_t normal_bytes, const Emit& emit, const One& one) {
  bool ran = false;
  const auto run = [&]<class L>(L) {
    using Kernel = FieldKernel<L>;
    if (!Kernel::reads(cell_bytes, normal_bytes) || f.position_lookup == PositionLookup::lines) return;
    std::uint32_t rest_index[2 * Kernel::kWidth + 16], rest_position[2 * Kernel::kWidth + 16];
    std::size_t rest = 0;
    Kernel::stream_culled(f, rays, index, count, limit, to_object, rest_index, rest_position, rest,
                          [&](const std::uint32_t* packet_index, const std::uint32_t* packet_position, const typename Kernel::Answer& a) {
                            emit(Kernel{}, packet_index, packet_position, a);
                          });
    for (std::size_t first = 0; first < rest; first += Kernel::kWidth) {
      alignas(64) std::uint32_t packet_index[Kernel::kWidth], packet_position[Kernel::kWidth];
      for (std::size_t lane = 0; lane < Kernel::kWidth; ++lane) {
        const std::size_t k = std::min(first + lane, rest - 1);
        packet_index[lane] = rest_index[k];
        packet_position[lane] = rest_position[k];
      }
      emit(Kernel{}, packet_index, packet_position, Kernel::trace_indexed(f, rays, packet_index, limit, to_object));
    }
    ran = true;
  };
  at_width(width, run);
  if (!ran)
    for (std::size_t k = 0; k < count; ++k) one(k);
}

}  // namespace

void ObjectField::trace_batch(const ObjectRays& rays, FieldAnswer* out, int width) const {
  VF_USE_WIDER(field_trace_batch, *this, rays, out, width);
  const FieldTables f = tables();
  const float* const rows[8] = {rays.ox, rays.oy, rays.oz, rays.dx, rays.dy, rays.dz, rays.tmin, rays.tmax};
  std::size_t done = run_lanes(
      f, resolved_width(width), rays.count, cells_.size(), normals_.size(), [&]<class K>(K, std::size_t at) { return K::load(rows, at); },
      [&]<class K>(K, std::size_t at, const typename K::Answer& a) { K::store(f, a, out + at); });
  for (; done < rays.count; ++done)
    out[done] = trace_field(f, {rays.ox[done], rays.oy[done], rays.oz[done]}, {rays.dx[done], rays.dy[done], rays.dz[done]},
                            rays.tmin[done], rays.tmax[done]);
}

void ObjectField::trace_rays(const Ray* rays, const std::uint32_t* index, std::size_t count, const InverseTransform& to_object,
                             const float* limit, FieldAnswer* out, int width) const {
  VF_USE_WIDER(field_trace_rays, *this, rays, index, count, to_object, limit, out, width);
  const FieldTables f = tables();
  // Rays culled by the sphere are misses; the kernel writes the answers of the others.
  std::fill(out, out + count, FieldAnswer{});
  run_culled(
      f, resolved_width(width), rays, index, count, limit, to_object, cells_.size(), normals_.size(),
      [&]<class K>(K, const std::uint32_t*, const std::uint32_t* position, const typename K::Answer& a) { K::store_at(f, a, out, position); },
      [&](std::size_t k) {
        Ray ray = rays[index[k]];
        if (limit) ray.tmax = limit[index[k]];
        const Ray local = to_object.apply(ray);
        out[k] = trace_field(f, {local.org.x, local.org.y, local.org.z}, {local.dir.x, local.dir.y, local.dir.z}, local.tmin, local.tmax);
      });
}

void ObjectField::trace_rays(std::span<const Ray> rays, std::span<FieldAnswer> out) const {
  if (rays.size() != out.size()) throw Error("trace_rays: " + std::to_string(rays.size()) + " rays but room for " + std::to_string(out.size()) + " answers");
  const InverseTransform identity;  // object space already: the rays pass bit for bit
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 4096), [&](const auto& range) {
    check_interrupt();
    std::vector<std::uint32_t> index(range.size());
    std::iota(index.begin(), index.end(), static_cast<std::uint32_t>(range.begin()));
    trace_rays(rays.data(), index.data(), index.size(), identity, nullptr, out.data() + range.begin());
  });
}

void ObjectField::mark_occluded(const Ray* rays, const std::uint32_t* index, std::size_t count, const InverseTransform& to_object,
                                std::uint8_t* occluded, int width) const {
  VF_USE_WIDER(field_mark_occluded, *this, rays, index, count, to_object, occluded, width);
  const FieldTables f = tables();
  run_culled(
      f, resolved_width(width), rays, index, count, nullptr, to_object, cells_.size(), normals_.size(),
      [&]<class K>(K, const std::uint32_t* packet_index, const std::uint32_t*, const typename K::Answer& a) {
        K::mark(a, packet_index, occluded);
      },
      [&](std::size_t k) {
        const Ray local = to_object.apply(rays[index[k]]);
        if (trace_field(f, {local.org.x, local.org.y, local.org.z}, {local.dir.x, local.dir.y, local.dir.z}, local.tmin, local.tmax).hit)
          occluded[index[k]] = 1;
      });
}

void ObjectField::mark_occluded(const ObjectRays& rays, std::uint8_t* occluded, int width) const {
  VF_USE_WIDER(field_mark_occluded, *this, rays, occluded, width);
  const FieldTables f = tables();
  const float* const rows[8] = {rays.ox, rays.oy, rays.oz, rays.dx, rays.dy, rays.dz, rays.tmin, rays.tmax};
  std::size_t done = run_lanes(
      f, resolved_width(width), rays.count, cells_.size(), normals_.size(), [&]<class K>(K, std::size_t at) { return K::load(rows, at); },
      [&]<class K>(K, std::size_t at, const typename K::Answer& a) { K::mark_run(a, occluded + at); });
  for (; done < rays.count; ++done)
    if (trace_field(f, {rays.ox[done], rays.oy[done], rays.oz[done]}, {rays.dx[done], rays.dy[done], rays.dz[done]}, rays.tmin[done],
                    rays.tmax[done])
            .hit)
      occluded[done] = 1;
}

int ObjectField::batch_width(int width) {
  VF_USE_WIDER(field_batch_width, width);
  return resolved_width(width);
}

const char* ObjectField::timing_bound() {
  constexpr const char* names[] = {"", "no-lookups", "read-and-map", "read-only", "cached-cells", "no-map", "no-map-line", "no-map-line-lattice", "sphere-only"};
  return names[static_cast<int>(kTimingBound)];
}

}  // namespace vf::field

#if VF_IN_WIDER_COPY
namespace vf::isa_avx512 {
VF_WIDER_ENTRY void field_trace_batch(const field::ObjectField& f, const field::ObjectRays& rays, field::FieldAnswer* out, int width) {
  f.trace_batch(rays, out, width);
}
VF_WIDER_ENTRY void field_trace_rays(const field::ObjectField& f, const Ray* rays, const std::uint32_t* index, std::size_t count,
                                     const InverseTransform& to_object, const float* limit, field::FieldAnswer* out, int width) {
  f.trace_rays(rays, index, count, to_object, limit, out, width);
}
VF_WIDER_ENTRY void field_mark_occluded(const field::ObjectField& f, const Ray* rays, const std::uint32_t* index, std::size_t count,
                                        const InverseTransform& to_object, std::uint8_t* occluded, int width) {
  f.mark_occluded(rays, index, count, to_object, occluded, width);
}
VF_WIDER_ENTRY void field_mark_occluded(const field::ObjectField& f, const field::ObjectRays& rays, std::uint8_t* occluded, int width) {
  f.mark_occluded(rays, occluded, width);
}
VF_WIDER_ENTRY int field_batch_width(int width) { return field::ObjectField::batch_width(width); }
}  // namespace vf::isa_avx512
#endif
