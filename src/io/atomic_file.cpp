#include "visfield/io/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"

namespace vf {
namespace {

// A name no other writer uses at the same time: process id plus a per-process counter.
std::filesystem::path temporary_sibling(const std::filesystem::path& folder, const std::filesystem::path& target) {
  static std::atomic<unsigned long> counter{0};
  std::string name(".");
  name += target.filename().string();
  name += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
  return folder / name;
}

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

std::filesystem::path folder_of(const std::filesystem::path& target) {
  return target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
}

void check_target(const std::filesystem::path& target) {
  const std::filesystem::path folder = folder_of(target);
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec))
    throw Error(target.string() + ": cannot write: " +
                (std::filesystem::exists(folder, ec) ? folder.string() + " is not a folder"
                                                     : "folder " + folder.string() + " does not exist"));
  if (target.filename().empty() || std::filesystem::is_directory(target, ec))
    throw Error(target.string() + ": cannot write: is a directory");
}

}  // namespace

void check_writable(const std::filesystem::path& target) {
  check_target(target);
  const std::filesystem::path probe = temporary_sibling(folder_of(target), target);
  std::FILE* file = std::fopen(probe.c_str(), "wx");
  if (file == nullptr)
    throw Error(target.string() + ": cannot write: cannot create a file in " + folder_of(target).string() + ": " +
                std::strerror(errno));
  std::fclose(file);
  std::error_code ec;
  std::filesystem::remove(probe, ec);
}

void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write) {
  check_target(target);
  std::error_code ec;
  const std::filesystem::path temp = temporary_sibling(folder_of(target), target);
  try {
    write(temp);
    check_interrupt();  // a signal during the write: the target keeps its old contents
  } catch (const Interrupted&) {
    std::filesystem::remove(temp, ec);
    throw;
  } catch (const Error& e) {
    std::filesystem::remove(temp, ec);
    // The user knows the target, not our temporary name.
    throw Error(replace_all(e.what(), temp.string(), target.string()));
  } catch (...) {
    std::filesystem::remove(temp, ec);
    throw;
  }
  std::filesystem::rename(temp, target, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw Error(target.string() + ": cannot write: " + ec.message());
  }
}

void write_file_bytes(const std::filesystem::path& path, std::string_view bytes) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) throw Error(path.string() + ": cannot write: " + std::strerror(errno));
  const std::size_t written = std::fwrite(bytes.data(), 1, bytes.size(), file);
  const int write_errno = errno;
  const bool closed = std::fclose(file) == 0;
  if (written != bytes.size()) throw Error(path.string() + ": cannot write: " + std::strerror(write_errno));
  if (!closed) throw Error(path.string() + ": cannot write: " + std::strerror(errno));
}

}  // namespace vf
