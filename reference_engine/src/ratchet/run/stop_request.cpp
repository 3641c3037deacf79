#include "ratchet/run/stop_request.hpp"

#include <atomic>
#include <csignal>

namespace ratchet {

namespace {

// Lock-free, so safe in a signal handler, and read by the runs of a sweep's threads.
std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);

extern "C" void on_stop_signal(int sig) {
  g_stop_signal = sig;
  std::signal(sig, SIG_DFL);  // a second one ends the process: the user insists
}

}  // namespace

void install_stop_handlers() {
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}

int stop_signal() { return g_stop_signal.load(); }

void request_stop(int signal) { g_stop_signal = signal; }

void clear_stop_request() { g_stop_signal = 0; }

std::string signal_name(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(signal);
}

}  // namespace ratchet
