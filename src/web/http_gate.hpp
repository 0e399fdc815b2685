#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "web/http_message.hpp"

// Who may talk to `serve --http` and `load --metrics`, decided on a request's head before its
// body is read: a Host that is not this server's own address is refused (a DNS-rebinding page
// would otherwise be same-origin), a change from a foreign Origin is refused (CSRF), a change must
// carry JSON (a form or text/plain POST is what a page may send without asking) and, with a
// token, "Authorization: Bearer TOKEN". Reads stay open to any client that names the server
// correctly: Prometheus needs no token.
namespace mblab::web {

struct GateOptions {
    std::string token;               // empty: changes need none
    std::string bound_host;          // the address listened on, an IP literal
    std::uint16_t port = 0;          // the port listened on (set once bound)
    std::vector<std::string> names;  // more host names taken (--http-allow-host)
    // Any Host: for a server that takes no change and shows nothing a rebound page could use
    // (load --metrics, scraped by host name).
    bool any_host = false;
};

class HttpGate {
  public:
    explicit HttpGate(GateOptions options);
    void set_port(std::uint16_t port) { options_.port = port; }

    // A refusal with its status and one line of JSON, or nullopt when the request may go on.
    std::optional<HttpReply> check(const HttpRequest& head) const;

  private:
    bool host_allowed(std::string_view host_and_port) const;
    bool origin_allowed(std::string_view origin) const;

    GateOptions options_;
};

// Compares in a time that depends only on `expected`'s length, so a client cannot learn the
// token a byte at a time.
bool same_secret(std::string_view given, std::string_view expected);

}  // namespace mblab::web
