#include "visfield/select/calibration.hpp"

namespace vf {

// The "constants" of the calibration file written on the project's build machine (AMD EPYC VM, 2 TBB
// threads, Release build) over the 10 test meshes and the 5 built-in scenes by the command that also
// wrote docs/selection-report.md:
//   visfield report --models test-meshes --rays 200000 --sample-rays 500 --build-repetitions 5 --bounces 2
//       --seed 1 --threads 2 --save-measurements calibration.json --splits 20 --split-seed 1
//       --out docs/selection-report.md
// Per-ray constants are for 2 threads; select_structure rescales them to the threads in force.
// Re-measure with `visfield calibrate` on another machine.
const Calibration& builtin_calibration() {
  static const Calibration calibration = [] {
    Calibration c;
    c.machine = MachineInfo{"visfield build machine", 2, "AMD EPYC"};
    c.settings.rays = 200000;
    c.settings.sample_rays = 500;
    c.settings.build_repetitions = 5;
    c.constants.build_ms_per_n_log2_n = 4.3989598326806776e-05;
    c.constants.ray_us_per_log2_n[calibrated_kind_index(RayKind::random)] = 0.005148226376404635;
    c.constants.ray_us_per_log2_n[calibrated_kind_index(RayKind::path)] = 0.004292974696538104;
    return c;
  }();
  return calibration;
}

}  // namespace vf
