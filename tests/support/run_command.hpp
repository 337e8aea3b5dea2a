#pragma once
// Test support: run a program through the shell and capture its exit code, stdout and stderr.

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace vf::test {

struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline std::string read_text_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs `command` (a shell command line) in `workdir`; stdout/stderr are captured through files there.
inline CommandResult run_command(const std::string& command, const std::filesystem::path& workdir) {
  std::filesystem::create_directories(workdir);
  const auto out_path = workdir / "stdout.txt", err_path = workdir / "stderr.txt";
  const std::string full =
      "cd '" + workdir.string() + "' && " + command + " >'" + out_path.string() + "' 2>'" + err_path.string() + "'";
  const int status = std::system(full.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text_file(out_path);
  r.err = read_text_file(err_path);
  std::filesystem::remove(out_path);
  std::filesystem::remove(err_path);
  return r;
}

// Number of lines in `text` (a final line without '\n' counts).
inline int line_count(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n';
  if (!text.empty() && text.back() != '\n') ++n;
  return n;
}

}  // namespace vf::test
