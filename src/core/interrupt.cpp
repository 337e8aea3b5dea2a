#include "visfield/core/interrupt.hpp"

#include <atomic>
#include <csignal>

namespace vf {
namespace {

// Written by the signal handler: a lock-free atomic is async-signal-safe.
std::atomic<int> recorded_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);

extern "C" void record_signal(int signal) {
  if (recorded_signal.exchange(signal) != 0) {
    // Asked twice: the user wants out now.
    std::signal(signal, SIG_DFL);
    std::raise(signal);
  }
}

std::string signal_name(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(signal);
}

}  // namespace

Interrupted::Interrupted(int signal) : Error("interrupted by " + signal_name(signal)), signal_(signal) {}

void install_interrupt_handlers() {
  std::signal(SIGINT, record_signal);
  std::signal(SIGTERM, record_signal);
}

void check_interrupt() {
  const int signal = recorded_signal.load(std::memory_order_relaxed);
  if (signal != 0) throw Interrupted(signal);
}

void request_interrupt(int signal) { recorded_signal.store(signal); }

void clear_interrupt() { recorded_signal.store(0); }

}  // namespace vf
