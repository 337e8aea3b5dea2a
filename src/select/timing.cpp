#include "visfield/select/timing.hpp"

namespace vf {

void do_not_optimize(std::uint64_t value) {
  static volatile std::uint64_t sink = 0;
  sink = sink + value;
}

QuerySet query_parts(const QuerySet& queries, std::size_t first, std::size_t last, std::size_t parts) {
  const auto slice = [&](const std::vector<Ray>& rays) {
    const std::size_t begin = rays.size() * first / parts, end = rays.size() * last / parts;
    return std::vector<Ray>(rays.begin() + static_cast<std::ptrdiff_t>(begin), rays.begin() + static_cast<std::ptrdiff_t>(end));
  };
  return QuerySet{slice(queries.closest), slice(queries.shadow)};
}

}  // namespace vf
