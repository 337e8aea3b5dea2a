#pragma once
/// \file The four ray sets visfield-bench measures and the query each one exercises.

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace vf::bench {

/// Which rays to trace. Primary and random rays ask for the closest hit; ao and shadow rays ask
/// only whether anything blocks them.
enum class RayKind { primary, ao, shadow, random };

/// Every kind, in the order the command line lists them.
inline constexpr std::array<RayKind, 4> kRayKinds{RayKind::primary, RayKind::ao, RayKind::shadow, RayKind::random};

/// The --rays spelling of `kind`.
constexpr std::string_view ray_kind_name(RayKind kind) {
  switch (kind) {
    case RayKind::primary: return "primary";
    case RayKind::ao: return "ao";
    case RayKind::shadow: return "shadow";
    case RayKind::random: return "random";
  }
  return "primary";
}

/// The kind spelled `name`, or nothing when no kind has that name.
inline std::optional<RayKind> parse_ray_kind(std::string_view name) {
  for (RayKind kind : kRayKinds) {
    if (ray_kind_name(kind) == name) return kind;
  }
  return std::nullopt;
}

/// True for the kinds answered with occluded() (any hit), false for intersect() (closest hit).
constexpr bool is_occlusion_kind(RayKind kind) { return kind == RayKind::ao || kind == RayKind::shadow; }

}  // namespace vf::bench
