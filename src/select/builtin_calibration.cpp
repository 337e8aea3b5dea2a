#include "visfield/select/calibration.hpp"

namespace vf {

// The "constants" of the calibration file written on the project's build machine (AMD EPYC VM, 2 TBB
// threads, Release build) over the 10 shared models and the 5 built-in scenes by
//   visfield report --models /work/shared/models --rays 200000 --build-repetitions 5 --threads 2
//       --splits 20 --save-measurements calibration.json
// (the same measurements as `visfield calibrate <those 15 scenes> --rays 200000 --build-repetitions 5
// --threads 2 -o calibration.json`). Per-ray constants are for 2 threads; select_structure rescales
// them to the threads in force. Re-measure with `visfield calibrate` on another machine.
const Calibration& builtin_calibration() {
  static const Calibration calibration = [] {
    Calibration c;
    c.machine = MachineInfo{"visfield build machine", 2, "AMD EPYC"};
    c.settings.rays = 200000;
    c.settings.sample_rays = 500;
    c.settings.build_repetitions = 5;
    c.constants.build_ms_per_n_log2_n = 4.802010045434388e-05;
    c.constants.ray_us_per_log2_n[calibrated_kind_index(RayKind::random)] = 0.0055662229810609235;
    c.constants.ray_us_per_log2_n[calibrated_kind_index(RayKind::path)] = 0.005091546079563168;
    return c;
  }();
  return calibration;
}

}  // namespace vf
