#pragma once
/// \file The --figure names `visfield-experiments --device cuda` runs, known in every build so that the
/// command line can refuse them with the right message where CUDA is absent.

#include <string>
#include <vector>

namespace vf::experiments {

/// The figures --device cuda reproduces on the GPU: gpu3, gpu5, gpu7.
inline std::vector<std::string> cuda_figure_names() { return {"gpu3", "gpu5", "gpu7"}; }
/// The figures that exist only on the GPU: gpu5 (the GPU paper's Figure 5 timing).
inline std::vector<std::string> cuda_only_figure_names() { return {"gpu5"}; }

}  // namespace vf::experiments
