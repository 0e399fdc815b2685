#pragma once

#include <asio/experimental/as_tuple.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>
#include <chrono>
#include <optional>

#include "cli/serve_http.hpp"
#include "server/kept_devices.hpp"
#include "transport/serial_url.hpp"

// `mblab serve --listen rtu://` or `ascii://`, and the timer loop serve's periodic work runs on.
namespace mblab::cli {

// Runs `action` every `period` until `stopping` is set. Cancelling the timer alone cannot stop
// it: a cancel that comes while the timer's completion is already queued (the period ran out as
// the action ran) finds nothing to cancel, and the loop would wait again, keeping the server
// running after SIGTERM.
template <class Action>
asio::awaitable<void> every(asio::steady_timer& timer, std::chrono::milliseconds period,
                            const bool& stopping, Action action) {
    while (!stopping) {
        timer.expires_after(period);
        auto [ec] = co_await timer.async_wait(asio::experimental::as_tuple(asio::use_awaitable));
        if (ec || stopping) co_return;
        action();
    }
}

// --listen rtu:// or ascii://: the device on a serial line until SIGINT or SIGTERM, or until the
// line fails (exit status 1).
int run_serial_line(const transport::SerialUrl& url, server::KeptDevices& kept,
                    device::RequestHandler& handler, std::chrono::milliseconds save_period,
                    LiveDevice* live, const std::optional<HttpPlan>& http);

}  // namespace mblab::cli
