#include "visfield/accel/any_accel.hpp"

#include <utility>

#include "visfield/core/error.hpp"

namespace vf {

namespace {

template <class... Structures>
std::vector<std::string> names_of(std::variant<Structures...>*) {
  static_assert((Accelerator<Structures> && ...));
  return {Structures::name()...};
}

// Builds the alternative whose name() matches; false when none does. Each build() records its build_ms.
template <class... Structures>
bool build_named(const std::string& name, const TriangleSet& set, std::optional<AnyAccel>& out,
                 std::variant<Structures...>*) {
  return ((name == Structures::name() ? (out.emplace(Structures::build(set)), true) : false) || ...);
}

}  // namespace

std::vector<std::string> accel_names() { return names_of(static_cast<AnyAccel*>(nullptr)); }

AnyAccel build_accel(const std::string& name, const TriangleSet& set) {
  std::optional<AnyAccel> accel;
  if (build_named(name, set, accel, static_cast<AnyAccel*>(nullptr))) return std::move(*accel);
  std::string valid;
  for (const std::string& n : accel_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw Error("--accel: unknown structure '" + name + "' (valid: " + valid + ")");
}

AccelStats accel_stats(const AnyAccel& accel) {
  return std::visit([](const auto& a) -> AccelStats { return a.stats(); }, accel);
}

}  // namespace vf
