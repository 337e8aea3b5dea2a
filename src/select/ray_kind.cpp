#include "visfield/select/ray_kind.hpp"

namespace vf {

std::string ray_kind_name(RayKind kind) { return kind == RayKind::random ? "random" : "path"; }

std::optional<RayKind> parse_ray_kind(std::string_view name) {
  for (RayKind kind : kRayKinds)
    if (name == ray_kind_name(kind)) return kind;
  return std::nullopt;
}

}  // namespace vf
