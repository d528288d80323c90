#include "InterruptHint.h"

#include <unistd.h>

#include <csignal>
#include <cstring>

namespace rangefuse::cli {
namespace {

// Written once before the work starts and read by the handler, which may only call
// async-signal-safe functions: a fixed buffer, not a std::string.
char hint[1024] = "";
volatile sig_atomic_t printing = 0;

extern "C" void onInterrupt(int signal) {
  if (printing && hint[0] != '\0') {
    const ssize_t written = ::write(STDERR_FILENO, hint, std::strlen(hint));
    (void)written;
  }
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace

void installInterruptHint(bool print) {
  printing = print ? 1 : 0;
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
}

void setInterruptHint(const std::string& text) {
  const std::string line = text.empty() ? "" : "\nrangefuse: interrupted; " + text + "\n";
  std::strncpy(hint, line.c_str(), sizeof hint - 1);
  hint[sizeof hint - 1] = '\0';
}

std::string fuseInterruptHint(const std::string& checkpoint, bool resumesIt) {
  if (checkpoint.empty())
    return "nothing was saved: give --checkpoint FILE.h5 to make a long run resumable";
  if (resumesIt)
    return "run the same command again: it goes on from the last checkpoint in " + checkpoint;
  return "to go on from the last checkpoint, run the same command with --resume " + checkpoint +
         " (if none was written yet, run it again as it was)";
}

}  // namespace rangefuse::cli
