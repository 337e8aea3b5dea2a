#include "visfield/core/parallel.hpp"

#include <tbb/global_control.h>
#include <tbb/info.h>

namespace vf {

struct ThreadLimit::Impl {
  tbb::global_control control;
  explicit Impl(int n) : control(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(n)) {}
};

ThreadLimit::ThreadLimit(int threads) {
  threads_ = threads > 0 ? threads : hardware_threads();
  impl_ = std::make_unique<Impl>(threads_);
}

ThreadLimit::~ThreadLimit() = default;

int hardware_threads() { return tbb::info::default_concurrency(); }

}  // namespace vf
