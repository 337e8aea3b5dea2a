#pragma once
// Shared helpers of the io tests: a scratch folder per test and checks on error messages.

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>

#include "visfield/core/error.hpp"

namespace vf::test {

/// A fresh empty folder under the system temp folder, removed with everything in it on destruction.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("visfield-io-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

/// Writes `bytes` to `path` exactly as given (binary mode: CRLF stays CRLF).
inline std::filesystem::path write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
  return path;
}

/// Runs `action`, requires a vf::Error whose message is one line mentioning `must_contain`, and
/// returns the message for further checks.
template <typename Action>
std::string expect_one_line_error(Action&& action, const std::string& must_contain) {
  try {
    action();
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.find('\r'), std::string::npos) << message;
    EXPECT_NE(message.find(must_contain), std::string::npos) << "message \"" << message << "\" lacks \"" << must_contain << "\"";
    return message;
  }
  ADD_FAILURE() << "expected a vf::Error mentioning \"" << must_contain << "\"";
  return {};
}

}  // namespace vf::test
