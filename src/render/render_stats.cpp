#include "visfield/render/render_stats.hpp"

#include <cstdio>

namespace vf {
namespace {

// 950 -> "950", 12'300 -> "12.3k", 16'800'000 -> "16.8M", 2'500'000'000 -> "2.50G".
std::string short_count(std::uint64_t n) {
  char text[32];
  const auto x = static_cast<double>(n);
  if (n < 1000) std::snprintf(text, sizeof text, "%llu", static_cast<unsigned long long>(n));
  else if (n < 1000000) std::snprintf(text, sizeof text, "%.1fk", x * 1e-3);
  else if (n < 1000000000) std::snprintf(text, sizeof text, "%.1fM", x * 1e-6);
  else std::snprintf(text, sizeof text, "%.2fG", x * 1e-9);
  return text;
}

}  // namespace

std::string RenderStats::summary() const {
  char text[256];
  std::snprintf(text, sizeof text, "%dx%d, %s rays (camera %s, shadow %s, reflection %s, AO %s), %.2f s, %.1f Mrays/s", width,
                height, short_count(rays).c_str(), short_count(by_kind.camera).c_str(), short_count(by_kind.shadow).c_str(),
                short_count(by_kind.reflection).c_str(), short_count(by_kind.ao).c_str(), seconds, mrays_per_s());
  return text;
}

}  // namespace vf
