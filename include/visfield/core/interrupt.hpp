#pragma once
/// \file Stopping long work on SIGINT or SIGTERM: the handler only records the signal; builds,
/// renders, ray batches and measurements poll it and throw vf::Interrupted, so the stack unwinds,
/// temporary files are removed and nothing partial is written.

#include <string>

#include "visfield/core/error.hpp"

namespace vf {

/// Thrown by check_interrupt() once SIGINT or SIGTERM has arrived. A vf::Error whose what() is
/// "interrupted by SIGINT" (or SIGTERM); `signal()` is the signal's number.
class Interrupted : public Error {
 public:
  explicit Interrupted(int signal);
  /// The signal that arrived (SIGINT or SIGTERM).
  int signal() const { return signal_; }

 private:
  int signal_;
};

/// Installs handlers for SIGINT and SIGTERM that record the signal for check_interrupt(). A second
/// signal while the first is being honoured kills the process as the default action would. Call
/// once, on the main thread, at program start.
void install_interrupt_handlers();

/// Throws vf::Interrupted when a signal has been recorded. One relaxed atomic load: cheap enough for
/// every node of a build or every tile of a render. Thread-safe.
void check_interrupt();

/// Records `signal` as the handler would (for tests and for callers with their own handlers).
void request_interrupt(int signal);

/// Forgets a recorded signal (for tests).
void clear_interrupt();

}  // namespace vf
