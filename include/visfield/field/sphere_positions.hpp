#pragma once
/// \file The positional sample set of an ObjectField (levels 3–6: 290, 1090, 4226, 16642 samples)
/// as a host object: the sample directions and the O(1) lookups of position_lookup.hpp over them.

#include <cstddef>
#include <vector>

#include "visfield/core/vec.hpp"
#include "visfield/field/position_lookup.hpp"

namespace vf::field {

/// Positional samples of one level. Immutable after construction; thread-safe; 24 + 12 bytes per
/// upper-hemisphere sample.
class SpherePositions {
 public:
  static constexpr int kMinLevel = 3;  ///< 290 samples
  static constexpr int kMaxLevel = 6;  ///< 16642 samples

  /// The set of `level`; throws vf::Error outside [kMinLevel, kMaxLevel]. O(4^level).
  explicit SpherePositions(int level);

  /// The level given at construction.
  int level() const { return level_; }
  /// The lattice half-width n = 2^level.
  int lattice_size() const { return n_; }
  /// Number of samples, 2(2n² + 2n + 1).
  std::size_t size() const { return 2 * upper_.size(); }
  /// Unit direction from the sphere's centre to sample `index` (double precision).
  hd::Vec3<double> direction(std::size_t index) const;
  /// The upper hemisphere's directions computed in float (octa::point_direction<float>, within 2e-7
  /// of the double ones), as the device-neutral lookups read them and the SIMD lookup computes them.
  const hd::Vec3<float>* upper_table() const { return upper_float_.data(); }

  /// The sample nearest to unit direction `d`. O(1).
  std::size_t nearest(const hd::Vec3<double>& d) const {
    return static_cast<std::size_t>(nearest_position(d, n_, upper_.data()));
  }
  /// The three samples around unit direction `d` with blending weights. O(1).
  PositionBlend<double> blend(const hd::Vec3<double>& d) const { return blend_positions(d, n_); }

  /// Number of samples of `level` without building the set.
  static std::size_t count(int level);

 private:
  int level_ = 0;
  int n_ = 0;
  std::vector<hd::Vec3<double>> upper_;
  std::vector<hd::Vec3<float>> upper_float_;
};

}  // namespace vf::field
