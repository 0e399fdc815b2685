#include "cli/serve_line.hpp"

#include <fmt/format.h>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/io_context.hpp>
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/serve_state.hpp"
#include "cli/stop_signals.hpp"
#include "server/behaviour_timer.hpp"
#include "server/serial_server.hpp"

namespace mblab::cli {

int run_serial_line(const transport::SerialUrl& url, server::KeptDevices& kept,
                    device::RequestHandler& handler, std::chrono::milliseconds save_period,
                    LiveDevice* live, const std::optional<HttpPlan>& http) {
    auto& device = kept.device(0);
    asio::io_context io(1);
    auto line = server::start_serial_server(io, handler, url, server::device_line_hooks(device));
    if (!line) {
        report(line.error());
        return kExitUsage;
    }
    int status = kExitOk;
    (*line)->on_failure([&](const std::string& why) {
        fmt::print(stderr, "mblab serve: {}\n", why);
        status = kExitFailed;
        io.stop();
    });
    fmt::print("mblab serve: {} profile on {}, {}; stop with Ctrl-C\n",
               device.declarations().profile().name, transport::format_serial_url(url),
               device.declarations().addressing(device::Link::Serial));
    std::fflush(stdout);
    std::string error;
    if (live &&
        !live->start(
            *http, [] { return std::uint64_t{0}; }, state_saver_for_http(kept.keeper(0)), error)) {
        (*line)->stop();
        report(error);
        return kExitUsage;
    }
    asio::steady_timer save_timer(io);
    server::BehaviourTimer behaviours(io, device);
    behaviours.start();
    bool stopping = false;
    if (kept.keeps_state() && save_period.count() > 0) {
        asio::co_spawn(io, every(save_timer, save_period, stopping, [&] { kept.save_soon(); }),
                       asio::detached);
    }
    const auto signals = watch_stop_signals(io, [&] {
        stopping = true;
        (*line)->stop();
        save_timer.cancel();
        behaviours.stop();
    });
    io.run();
    if (live) live->stop();
    // The line is closed, so every write the device acknowledged is in it now.
    if (!kept.save_all()) return kExitFailed;
    return status;
}

}  // namespace mblab::cli
