#pragma once
/// \file The roofline of a field lookup: bytes it reads and float operations it executes, from the
/// packed layout (packed_scene.hpp) and the query (field/field_query.hpp), against a device's peak
/// bandwidth and arithmetic rate. The bench prints it beside the measured rate; docs/cuda.md
/// explains the figures.

#include <string>

#include "visfield/field/field_query.hpp"

namespace vf::gpu {

/// What one lookup of a field costs, for a kind of kernel.
struct LookupCost {
  double table_bytes = 0.0;   ///< Bytes of the tables it reads: up to 3 sample directions, the cell(s), the normal(s).
  double sector_bytes = 0.0;  ///< The same in the 32-byte sectors the memory system moves (every read touches its own sector).
  double ray_bytes = 0.0;     ///< Bytes of rays in and answers out per lookup (0 when the kernel makes its own rays).
  double flops = 0.0;         ///< Float operations (add, multiply, divide, square root, compare-select), counted from the code.
  double int_ops = 0.0;       ///< Integer operations (indices, the generator, conversions).
};

/// A device's peaks.
struct DevicePeaks {
  double dram_bytes_per_s = 0.0;  ///< Memory bandwidth.
  double l2_bytes = 0.0;          ///< L2 cache size.
  double flops_per_s = 0.0;       ///< FP32 operations a second, unfused (the kernels run --fmad=false): lanes × clock.
};

/// The bound a kernel cannot pass.
struct Roofline {
  double memory_rays_per_s = 0.0;   ///< Lookups a second the memory system allows (L2-resident tables: only rays and answers from DRAM).
  double compute_rays_per_s = 0.0;  ///< Lookups a second the arithmetic allows.
  double bound_rays_per_s = 0.0;    ///< The smaller of the two.
  bool tables_in_l2 = false;        ///< The packed tables fit in L2, so table sectors come from there, not DRAM.
  std::string limiter;              ///< "memory" or "compute".
};

/// The cost of one lookup of the field `tables` describes (parameters only; no pointer is read):
/// `device_rays` true for kernels that generate their AO rays (a surface frame per point and a
/// count out, amortised over `rays_per_point`), false for the batch API (a 32-byte Ray in, one byte
/// or a 36-byte Hit out: `closest`).
LookupCost field_lookup_cost(const field::FieldTables& tables, bool device_rays, int rays_per_point, bool closest);

/// The roofline of `cost` on `peaks` for a working set of `table_bytes` packed bytes.
Roofline roofline(const LookupCost& cost, const DevicePeaks& peaks, double table_bytes);

/// "180 flops, 41 B of tables (4 sectors), 0.8 B of rays per lookup; bound 95 G lookups/s (compute)".
std::string describe(const LookupCost& cost, const Roofline& bound);

/// The H100's published peaks (SXM5: 3.35 TB/s HBM3, 50 MiB L2, 67 TFLOP/s FP32 counting a fused
/// multiply-add as two, so 33.5e12 unfused operations a second), for docs/cuda.md when no device is
/// at hand; a device's own figures replace them in the bench.
DevicePeaks h100_sxm_peaks();

}  // namespace vf::gpu
