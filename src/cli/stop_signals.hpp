#pragma once

#include <atomic>
#include <functional>
#include <memory>

namespace asio {
class io_context;
}

// How every command hears SIGINT and SIGTERM. The first signal only asks: the command ends the
// step under way, writes its reports and exits. A second signal ends the program at once (the
// default action comes back after the first), so a stop that hangs can still be ended with
// another Ctrl-C. SIGPIPE is ignored: a peer that goes away is an error on the write, not the
// end of mblab.
namespace mblab::cli {

// For commands whose work polls a flag between steps (conform, fuzz, load, watch).
class StopSignals {
  public:
    // Installs the handlers. Interrupted reads and writes restart, so a step under way ends
    // as it would have without the signal.
    static void catch_them();
    static const std::atomic<bool>& flag();
    static bool requested() { return flag().load(); }
    // The signal that asked, 0 when none did.
    static int signal_number();
    // The exit status a shell gives a program that signal ended: 130 for SIGINT, 143 for
    // SIGTERM.
    static int exit_status();
};

// For commands that run an asio loop (serve): calls `on_stop` once, in the loop, on the first
// signal. The watch lasts as long as the returned holder.
std::shared_ptr<void> watch_stop_signals(asio::io_context& io, std::function<void()> on_stop);

}  // namespace mblab::cli
