#include "visfield/gpu/roofline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "visfield/gpu/ray_generation.hpp"

namespace vf::gpu {
namespace {

// Float operations of trace_field() for one ray, counted in field/field_query.hpp and the headers
// it calls, an explicit fused multiply-add (hd::fma, hd::fused_dot: three a dot product) as one
// (nearest lookups; the bilinear and blend lookups repeat the direction part 4 and 3 times):
//   ray to unit direction, sphere roots, entry/exit point and its normalisation        34
//   heaviest_corner_position: octa::coordinates (sqrt, lookup_atan2's division and
//     degree-11 polynomial, lattice scaling) 23, containing_triangle 8                     31
//   read_direction: inward pole 3, orthonormal_basis 15, the local frame's 3 dot products 9,
//     disk_to_concentric (sqrt, division, atan_unit) 18, two cell indices 3               48
//   read_cell's decode and the hit distance, interval tests                                7
constexpr double kTraceFlops = 34 + 31 + 48 + 7;
constexpr double kTraceIntOps = 40;        // lattice indices, point_index, the cell address
constexpr double kDirectionFlops = 48;     // one more read_direction (bilinear, blend)
// sample_read() through the far end, per positional sample read: the exit point 3, the line 3, its
// length (dot product, sqrt) 4, the unit direction and the frame's reciprocal from one division
// (hd::reciprocals: 4, then 3 products) 7 less the frame's own division 1, the shift 3; from inside,
// the limit: the two directions apart 3, its length 4, the share, max, product, subtraction and the
// test against it 5.
constexpr double kThroughFlops = 31;
constexpr double kTransformFlops = 18;     // world-to-object ray (two 3x3 products, a subtraction)
// ao_ray(): the generator's two numbers (integer), concentric_disk 14, sincos_eighth 19,
// Malley's lift 5, the frame 15.
constexpr double kAoRayFlops = 53;
constexpr double kAoRayIntOps = 30;        // Rng's construction (two mix64) and two PCG steps
constexpr double kSector = 32.0;

}  // namespace

LookupCost field_lookup_cost(const field::FieldTables& t, bool device_rays, int rays_per_point, bool closest) {
  LookupCost c;
  const double cell_bytes = t.storage == field::CellStorage::u8    ? 1.0
                            : t.storage == field::CellStorage::u16 ? 2.0
                            : t.storage == field::CellStorage::f32 ? 4.0
                                                                   : 1.0 / 8.0;
  const double normal_bytes = t.normals == field::NormalStorage::none ? 0.0 : t.normals == field::NormalStorage::oct16 ? 2.0 : 4.0;
  const int directions = t.direction_lookup == field::DirectionLookup::bilinear ? 4 : 1;
  const int positions = t.position_lookup == field::PositionLookup::blend ? 3 : 1;
  const double reads = static_cast<double>(directions * positions);
  // Each positional sample's direction (12 bytes: one, the heaviest corner's, or the three blended),
  // then per read the cell and its normal; the 1-bit variant reads its sample's average distance too.
  c.table_bytes = positions * 12.0 + reads * (cell_bytes + normal_bytes + (t.storage == field::CellStorage::bit ? 4.0 : 0.0));
  c.sector_bytes = kSector * ((positions == 3 ? 2.0 : 1.0) + reads * (1.0 + (normal_bytes > 0.0 ? 1.0 : 0.0)));
  c.flops = kTraceFlops + kTransformFlops + (reads - 1.0) * kDirectionFlops +
            (t.sample_line == field::SampleLine::through ? positions * kThroughFlops : 0.0);
  c.int_ops = kTraceIntOps * reads;
  if (device_rays) {
    c.ray_bytes = (static_cast<double>(sizeof(SurfaceFrame)) + 4.0) / std::max(1, rays_per_point);
    c.flops += kAoRayFlops;
    c.int_ops += kAoRayIntOps;
  } else {
    c.ray_bytes = static_cast<double>(sizeof(Ray)) + (closest ? static_cast<double>(sizeof(Hit)) : 1.0);
  }
  return c;
}

Roofline roofline(const LookupCost& c, const DevicePeaks& p, double table_bytes) {
  Roofline r;
  r.tables_in_l2 = table_bytes <= 0.5 * p.l2_bytes;  // half: the rays and answers stream through L2 as well
  const double dram_bytes = c.ray_bytes + (r.tables_in_l2 ? 0.0 : c.sector_bytes);
  r.memory_rays_per_s = dram_bytes > 0.0 ? p.dram_bytes_per_s / dram_bytes : INFINITY;
  r.compute_rays_per_s = p.flops_per_s / c.flops;
  r.bound_rays_per_s = std::min(r.memory_rays_per_s, r.compute_rays_per_s);
  r.limiter = r.memory_rays_per_s < r.compute_rays_per_s ? "memory" : "compute";
  return r;
}

std::string describe(const LookupCost& c, const Roofline& r) {
  char line[256];
  std::snprintf(line, sizeof line,
                "%.0f flops + %.0f integer ops, %.1f B of tables (%.0f B in sectors, %s), %.1f B of rays per lookup; "
                "bound %.1f G lookups/s (%s; memory %.1f, compute %.1f)",
                c.flops, c.int_ops, c.table_bytes, c.sector_bytes, r.tables_in_l2 ? "L2-resident" : "from DRAM", c.ray_bytes,
                r.bound_rays_per_s * 1e-9, r.limiter.c_str(), r.memory_rays_per_s * 1e-9, r.compute_rays_per_s * 1e-9);
  return line;
}

// 132 SMs x 128 FP32 lanes x 1.98 GHz boost: 33.5e12 operations a second, a fused multiply-add
// counted as one (67 TFLOP/s counts it as two; the kernels fuse only where the shared query says so).
DevicePeaks h100_sxm_peaks() { return DevicePeaks{3.35e12, 50.0 * 1024 * 1024, 33.45e12}; }

}  // namespace vf::gpu
