// SIGINT and SIGTERM during long renders, builds and measurements: the command stops promptly with
// exit status 128 + signal, one line on stderr, and no output file (partial or temporary) left.

#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "support/run_command.hpp"

namespace vf {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Outcome {
  int exit_code = -1;          ///< -1 when it did not exit normally
  double seconds_after = 0.0;  ///< From the signal to the exit.
  std::string err;
};

// Starts visfield with `args` in `dir`, sends `signal` after `delay_s`, and waits (at most 60 s).
Outcome interrupt_visfield(const std::vector<std::string>& args, const fs::path& dir, int signal, double delay_s) {
  const fs::path err_path = dir / "stderr.txt";
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (::chdir(dir.c_str()) != 0) ::_exit(127);
    const int out = ::open("stdout.txt", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open("stderr.txt", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out, 1);
    ::dup2(err, 2);
    std::vector<char*> argv{const_cast<char*>(VISFIELD_EXE)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(VISFIELD_EXE, argv.data());
    ::_exit(127);
  }
  std::this_thread::sleep_for(std::chrono::duration<double>(delay_s));
  ::kill(pid, signal);
  const auto sent = Clock::now();
  Outcome outcome;
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (Clock::now() - sent > std::chrono::seconds(60)) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  outcome.seconds_after = std::chrono::duration<double>(Clock::now() - sent).count();
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  outcome.err = test::read_text_file(err_path);
  fs::remove(err_path);
  fs::remove(dir / "stdout.txt");
  return outcome;
}

class Interrupt : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(VISFIELD_TEST_BINARY_DIR) / "interrupt-work" / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  // The one-line message, the exit status, promptness, and an empty folder.
  void expect_stopped(const Outcome& o, int signal, const char* name) {
    EXPECT_EQ(o.exit_code, 128 + signal) << o.err;
    EXPECT_LT(o.seconds_after, 3.0) << "took " << o.seconds_after << " s to stop";
    const std::string last_line = o.err.substr(o.err.rfind('\n', o.err.size() - 2) + 1);
    EXPECT_EQ(last_line, std::string("visfield: interrupted by ") + name + "; nothing was written\n") << o.err;
    for (const auto& entry : fs::directory_iterator(dir_)) ADD_FAILURE() << "left behind: " << entry.path().filename();
  }
  fs::path dir_;
};

TEST_F(Interrupt, SigintStopsARenderAndLeavesNoImage) {
  // About 540M rays: tens of seconds, interrupted after one.
  const Outcome o = interrupt_visfield({"render", "builtin:cornell", "--width", "1024", "--height", "1024", "--ao-rays", "512",
                                        "--out", "ao.png"},
                                       dir_, SIGINT, 1.0);
  expect_stopped(o, SIGINT, "SIGINT");
}

TEST_F(Interrupt, SigtermStopsABuild) {
  // A kd-tree over 3M soup triangles: several seconds of build.
  const Outcome o = interrupt_visfield({"info", "builtin:soup:size=3000000", "--accel", "kdtree"}, dir_, SIGTERM, 1.0);
  expect_stopped(o, SIGTERM, "SIGTERM");
}

TEST_F(Interrupt, SigintStopsACalibrationAndLeavesNoJson) {
  const Outcome o = interrupt_visfield({"calibrate", "builtin:soup:size=200000", "builtin:sphere", "--rays", "2e6", "-o", "c.json"},
                                       dir_, SIGINT, 1.0);
  expect_stopped(o, SIGINT, "SIGINT");
}

TEST_F(Interrupt, SigintStopsAFieldPrecomputeAndLeavesNoFile) {
  // 68M rays into 200,000 triangles: tens of seconds, interrupted after one.
  const Outcome o = interrupt_visfield({"field", "build", "builtin:soup:size=200000", "--positions", "16642", "--directions", "64",
                                        "--no-progress", "-o", "soup.vfield"},
                                       dir_, SIGINT, 1.0);
  expect_stopped(o, SIGINT, "SIGINT");
}

}  // namespace
}  // namespace vf
