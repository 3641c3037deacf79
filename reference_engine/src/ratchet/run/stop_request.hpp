// SIGINT and SIGTERM as a request to stop at the end of the current step (docs/cli.md,
// "Stopping and resuming"): the runner then writes a checkpoint (run/checkpoint.hpp),
// marks the run interrupted in run.json and throws RunInterrupted. A second signal of
// the same kind ends the process at once (the default action is restored).
#pragma once

#include <stdexcept>
#include <string>

namespace ratchet {

void install_stop_handlers();  // for SIGINT and SIGTERM; idempotent
int stop_signal();             // the signal received, 0 if none
void request_stop(int signal); // what the handler does (tests call it directly)
void clear_stop_request();

// "SIGINT", "SIGTERM" or "signal N".
std::string signal_name(int signal);

// Thrown by run_world after it has stopped cleanly on a request.
struct RunInterrupted : std::runtime_error {
  RunInterrupted(const std::string& what, int sig) : std::runtime_error(what), signal(sig) {}
  int signal;
};

}  // namespace ratchet
