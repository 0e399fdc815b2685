#include "cli/stop_signals.hpp"

#include <signal.h>

#include <asio/io_context.hpp>
#include <asio/signal_set.hpp>
#include <csignal>

namespace mblab::cli {

namespace {

std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};

extern "C" void on_stop_signal(int signal_number) {
    g_signal.store(signal_number);
    g_stop.store(true);
}

}  // namespace

void StopSignals::catch_them() {
    g_stop.store(false);
    g_signal.store(0);
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    action.sa_flags = SA_RESETHAND | SA_RESTART;
    sigemptyset(&action.sa_mask);
    ::sigaction(SIGINT, &action, nullptr);
    ::sigaction(SIGTERM, &action, nullptr);
    std::signal(SIGPIPE, SIG_IGN);
}

const std::atomic<bool>& StopSignals::flag() {
    return g_stop;
}

int StopSignals::signal_number() {
    return g_signal.load();
}

int StopSignals::exit_status() {
    return 128 + g_signal.load();
}

std::shared_ptr<void> watch_stop_signals(asio::io_context& io, std::function<void()> on_stop) {
    std::signal(SIGPIPE, SIG_IGN);
    auto signals = std::make_shared<asio::signal_set>(io, SIGINT, SIGTERM);
    signals->async_wait([watched = std::weak_ptr<asio::signal_set>(signals),
                         on_stop = std::move(on_stop)](const asio::error_code& ec, int) {
        if (ec) return;
        // Giving the signals back to their default action lets a second one end the program.
        if (auto set = watched.lock()) {
            asio::error_code ignored;
            set->clear(ignored);
        }
        on_stop();
    });
    return signals;
}

}  // namespace mblab::cli
