#include "cli/serve_stats_line.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <string>

namespace mblab::cli {

void StatsLine::print() {
    using server::ServerStats;
    std::uint64_t open = 0, requests = 0, exceptions = 0, busy = 0, refused = 0, evicted = 0,
                  slow = 0, handshakes = 0, resumed = 0, tls_refused = 0, denied = 0;
    for (const auto& s : servers_) {
        handshakes += ServerStats::read(s->stats().tls_handshakes);
        resumed += ServerStats::read(s->stats().tls_resumed);
        tls_refused += ServerStats::read(s->stats().tls_refused);
        denied += ServerStats::read(s->stats().denied);
        open += ServerStats::read(s->stats().connections_open);
        requests += ServerStats::read(s->stats().requests);
        exceptions += ServerStats::read(s->stats().exceptions);
        busy += ServerStats::read(s->stats().busy);
        slow += ServerStats::read(s->stats().closed_slow_frame);
        refused += s->listener_counters().refused_address.load() +
                   s->listener_counters().refused_full.load();
        evicted += s->listener_counters().evicted();
    }
    const auto tls = handshakes + tls_refused == 0
                         ? std::string()
                         : fmt::format(
                               "; TLS {} handshakes ({} resumed), {} refused, {} "
                               "requests denied by role",
                               handshakes, resumed, tls_refused, denied);
    fmt::print(stderr,
               "{}mblab serve: {} connections, {} req/s, {} exc/s; total {} requests, {} "
               "exceptions, {} busy, {} refused, {} evicted, {} closed for a slow frame{}{}",
               live_ ? "\r\033[K" : "", open, requests - last_requests_,
               exceptions - last_exceptions_, requests, exceptions, busy, refused, evicted, slow,
               tls, live_ ? "" : "\n");
    std::fflush(stderr);
    last_requests_ = requests;
    last_exceptions_ = exceptions;
}

}  // namespace mblab::cli
