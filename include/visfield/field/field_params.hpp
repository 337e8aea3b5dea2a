#pragma once
/// \file The parameters that define an ObjectField's tables, in the `key=value` syntax of every
/// spec (core/spec.hpp): what `field:...` structure specs and a scene JSON mesh's "field" object
/// both accept, declared once.

#include <array>
#include <string_view>

#include "visfield/core/spec.hpp"
#include "visfield/field/object_field.hpp"

namespace vf::field {

/// positions, directions, mapping, storage and normals, with the papers' defaults.
inline constexpr std::array<ParamSpec, 5> kTableParams{{
    {"positions", ParamType::choice, "4226", "positional samples on each mesh's bounding sphere", 0, 0, "290|1090|4226|16642"},
    {"directions", ParamType::whole, "32", "N: each positional sample holds an NxN table of directions", 8, 256},
    {"mapping", ParamType::choice, "concentric", "how a table covers the hemisphere (concentric: + Malley, the paper's)", 0, 0,
     "polar|rejection|concentric|equal-area"},
    {"storage", ParamType::choice, "u8", "bits of a distance: u8, u16, f32, or bit (visibility + mean distance)", 0, 0,
     "u8|u16|f32|bit"},
    {"normals", ParamType::choice, "none", "normal field beside the distances: none, oct16 or oct32 (octahedral, 8 or 16 bits per coordinate)",
     0, 0, "none|oct16|oct32"},
}};

/// `base` with the table parameters `p` gives (read against kTableParams or a table that begins
/// with them) written over it; with `given_only`, only those the user wrote.
ObjectFieldConfig with_table_params(ObjectFieldConfig base, const ParamValues& p, bool given_only = false);

/// `base` with the table parameters of `params` ("directions=64,storage=u16", as a scene JSON mesh
/// gives them) written over it. Throws a one-line vf::Error starting with `where` on an unknown key
/// or a bad value.
ObjectFieldConfig with_table_params(const ObjectFieldConfig& base, std::string_view params, const std::string& where);

}  // namespace vf::field
