#pragma once
/// \file The ray distributions visfield generates, measures and calibrates for: one enum for the
/// benchmark's ray sets and the selection's workloads.

#include <array>
#include <optional>
#include <string_view>

namespace vf {

/// Which rays: camera rays through pixel centres (primary), ambient-occlusion rays from the primary
/// hits (ao), shadow rays from them to the lights (shadow), segments between random points of the
/// bounding sphere (random, Havran's "random rays"), or path-tracing rays: camera rays, diffuse
/// bounces and a shadow ray per hit (path).
enum class RayKind { primary, ao, shadow, random, path };

/// Every kind, in the order help texts list them.
inline constexpr std::array<RayKind, 5> kRayKinds{RayKind::primary, RayKind::ao, RayKind::shadow, RayKind::random,
                                                  RayKind::path};

/// The command-line and file spelling of `kind`.
constexpr std::string_view ray_kind_name(RayKind kind) {
  switch (kind) {
    case RayKind::primary: return "primary";
    case RayKind::ao: return "ao";
    case RayKind::shadow: return "shadow";
    case RayKind::random: return "random";
    case RayKind::path: return "path";
  }
  return "primary";
}

/// The kind spelled `name` ("camera" also names primary rays), or nothing when no kind has that name.
constexpr std::optional<RayKind> parse_ray_kind(std::string_view name) {
  if (name == "camera") return RayKind::primary;
  for (RayKind kind : kRayKinds)
    if (ray_kind_name(kind) == name) return kind;
  return std::nullopt;
}

/// True for the kinds whose rays only ask whether anything blocks them (ao, shadow).
constexpr bool is_occlusion_kind(RayKind kind) { return kind == RayKind::ao || kind == RayKind::shadow; }

}  // namespace vf
