#pragma once
/// \file No partial output: write to a temporary sibling, rename on success.

#include <filesystem>
#include <functional>
#include <string_view>

namespace vf {

/// Checks, before any work, that write_atomically(target, ...) can succeed as far as the file system
/// goes: the folder exists, `target` is not a directory, and a file can be created in the folder (a
/// probe is created and removed). Throws vf::Error "<target>: cannot write: <reason>".
void check_writable(const std::filesystem::path& target);

/// Calls `write(tmp)` with a temporary path next to `target`, then renames it over `target`. If
/// `write` throws, the temporary is removed and the exception propagates (a vf::Error reworded to
/// name `target` instead of the temporary); `target` is untouched.
/// Throws vf::Error naming `target` when its folder does not exist, `target` is a directory, or the
/// rename fails. Safe to call from several threads for different targets.
void write_atomically(const std::filesystem::path& target, const std::function<void(const std::filesystem::path&)>& write);

/// Writes `bytes` to `path` (created or truncated), not atomically: meant as the `write` step of
/// write_atomically. Throws vf::Error naming `path` and the system's reason on any failure.
void write_file_bytes(const std::filesystem::path& path, std::string_view bytes);

}  // namespace vf
