#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

// HTTP/1.1 messages as bytes in, values out and back, with no socket: the request head cut and
// checked, the body's length decided, a reply written with the headers every answer carries.
// Everything a client sends is bounded here, before any handler sees it (RFC 9112).
namespace mblab::web {

// A request head of more than this is answered 431; a body of more, 413.
constexpr std::size_t kMaxHead = 16 * 1024;
constexpr std::size_t kMaxBody = 1 << 20;

struct HttpRequest {
    std::string method;                        // as sent: GET, HEAD, POST, PUT, DELETE, PATCH, ...
    std::string target;                        // as sent, for messages
    std::string path;                          // percent-decoded, without the query
    std::map<std::string, std::string> query;  // percent-decoded; the last of a repeated key
    std::vector<std::pair<std::string, std::string>> headers;  // names lower-cased
    std::string body;
    std::size_t body_length = 0;  // from Content-Length (0 without one)
    bool keep_alive = true;
    bool expects_continue = false;  // Expect: 100-continue

    // The value of the header `name` (lower case); nullptr when absent.
    const std::string* header(std::string_view name) const;
};

// What parse_head found: a request whose body (body_length bytes) follows at `used`, more bytes
// needed, or a refusal with its status and one line of reason.
struct HeadResult {
    enum class Kind { NeedMore, Request, Refused } kind = Kind::NeedMore;
    HttpRequest request;
    std::size_t used = 0;  // bytes of the head, blank line included
    int status = 0;
    std::string reason;
};
HeadResult parse_head(std::string_view bytes);

std::optional<std::string> percent_decode(std::string_view text);

struct HttpReply {
    int status = 200;
    std::string body;
    std::string content_type = "application/json";
};

// Status line, headers (length, type, keep-alive or close, and the security headers every
// answer carries) and the body; HEAD gets the same head with no body.
std::string write_reply(const HttpReply& reply, bool keep_alive, bool head_only);
// The head of a text/event-stream answer; its events follow as they come, and it ends with the
// connection.
std::string write_stream_head();
const char* status_text(int status);

}  // namespace mblab::web
