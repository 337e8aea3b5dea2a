#pragma once
/// \file No partial output: write to a temporary sibling, rename on success.

#include <filesystem>
#include <functional>

namespace vf {

/// Calls `write(tmp)` with a temporary path next to `target`, then renames it over `target`. If
/// `write` throws, the temporary is removed and the exception propagates; `target` is untouched.
void write_atomically(const std::filesystem::path& target, const std::function<void(const std::filesystem::path&)>& write);

}  // namespace vf
