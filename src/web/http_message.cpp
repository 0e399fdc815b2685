#include "web/http_message.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>

#include "support/hex_digits.hpp"

namespace mblab::web {

namespace {

constexpr std::size_t kMaxHeaders = 100;

// Sent with every answer: the dashboard is never framed (clickjacking), runs only its own
// script and style, and the token a URL may carry never leaves in a Referer.
constexpr std::string_view kSecurityHeaders =
    "X-Content-Type-Options: nosniff\r\n"
    "X-Frame-Options: DENY\r\n"
    "Content-Security-Policy: default-src 'none'; script-src 'self'; style-src 'self'; "
    "connect-src 'self'; img-src 'self' data:; base-uri 'none'; form-action 'none'; "
    "frame-ancestors 'none'\r\n"
    "Referrer-Policy: no-referrer\r\n"
    "Cache-Control: no-store\r\n";

bool is_tchar(char c) {
    if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9')) return true;
    return std::string_view("!#$%&'*+-.^_`|~").find(c) != std::string_view::npos;
}

bool is_token(std::string_view text) {
    return !text.empty() && std::all_of(text.begin(), text.end(), is_tchar);
}

std::string lower(std::string_view text) {
    std::string out(text);
    for (auto& c : out)
        if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    return out;
}

std::string_view trim(std::string_view text) {
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t'))
        text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t'))
        text.remove_suffix(1);
    return text;
}

HeadResult refuse(int status, std::string reason) {
    HeadResult out;
    out.kind = HeadResult::Kind::Refused;
    out.status = status;
    out.reason = std::move(reason);
    return out;
}

// The query's key=value pairs; '+' is a space, as forms send it.
bool parse_query(std::string_view text, std::map<std::string, std::string>& query) {
    while (!text.empty()) {
        const auto amp = text.find('&');
        const auto pair = text.substr(0, amp);
        text = amp == std::string_view::npos ? std::string_view() : text.substr(amp + 1);
        if (pair.empty()) continue;
        const auto eq = pair.find('=');
        std::string key(pair.substr(0, eq));
        std::string value(eq == std::string_view::npos ? std::string_view() : pair.substr(eq + 1));
        std::replace(key.begin(), key.end(), '+', ' ');
        std::replace(value.begin(), value.end(), '+', ' ');
        auto k = percent_decode(key);
        auto v = percent_decode(value);
        if (!k || !v) return false;
        query[*k] = *v;
    }
    return true;
}

// Content-Length, Transfer-Encoding, Connection and Expect: what the framing of this request
// and the next depends on. A refusal leaves `result` Refused.
void read_framing(HeadResult& result, bool http10) {
    auto& request = result.request;
    std::optional<std::size_t> length;
    bool close = http10;
    for (const auto& [name, value] : request.headers) {
        if (name == "content-length") {
            std::size_t n = 0;
            auto [at, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
            if (value.empty() || ec == std::errc::result_out_of_range ||
                (ec == std::errc() && at == value.data() + value.size() && n > kMaxBody)) {
                result = refuse(413, fmt::format("a body of at most {} bytes is taken", kMaxBody));
                return;
            }
            if (ec != std::errc() || at != value.data() + value.size() ||
                (length && *length != n)) {
                result = refuse(400, "Content-Length is not one decimal number");
                return;
            }
            length = n;
        } else if (name == "transfer-encoding") {
            // Chunked bodies have no length to check before they are read.
            result = refuse(411, "a body needs Content-Length (chunked bodies are not taken)");
            return;
        } else if (name == "connection") {
            const auto token = lower(value);
            if (token.find("close") != std::string::npos) close = true;
            if (http10 && token.find("keep-alive") != std::string::npos) close = false;
        } else if (name == "expect") {
            if (lower(value) != "100-continue") {
                result = refuse(417, "only Expect: 100-continue is understood");
                return;
            }
            request.expects_continue = true;
        }
    }
    request.body_length = length.value_or(0);
    request.keep_alive = !close;
}

}  // namespace

const std::string* HttpRequest::header(std::string_view name) const {
    for (const auto& [key, value] : headers)
        if (key == name) return &value;
    return nullptr;
}

std::optional<std::string> percent_decode(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '%') {
            out += text[i];
            continue;
        }
        if (i + 2 >= text.size()) return std::nullopt;
        const int high = hex_value(text[i + 1]);
        const int low = hex_value(text[i + 2]);
        if (high < 0 || low < 0 || (high == 0 && low == 0)) return std::nullopt;
        out += static_cast<char>(high * 16 + low);
        i += 2;
    }
    return out;
}

HeadResult parse_head(std::string_view bytes) {
    std::size_t start = 0;
    while (start < bytes.size() && (bytes[start] == '\r' || bytes[start] == '\n'))
        ++start;
    const auto crlf = bytes.find("\r\n\r\n", start);
    const auto lf = bytes.find("\n\n", start);
    const auto end = std::min(crlf == std::string_view::npos ? crlf : crlf + 4,
                              lf == std::string_view::npos ? lf : lf + 2);
    if (end == std::string_view::npos || end > kMaxHead) {
        if (bytes.size() > kMaxHead) {
            return refuse(431,
                          fmt::format("a request head of at most {} bytes is taken", kMaxHead));
        }
        return {};
    }
    HeadResult result;
    result.kind = HeadResult::Kind::Request;
    result.used = end;
    auto& request = result.request;
    std::vector<std::string_view> lines;
    std::string_view head = bytes.substr(start, end - start);
    while (!head.empty()) {
        const auto nl = head.find('\n');
        auto line = head.substr(0, nl);
        head = nl == std::string_view::npos ? std::string_view() : head.substr(nl + 1);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (!line.empty()) lines.push_back(line);
    }
    if (lines.empty()) return refuse(400, "an empty request");
    const auto& first = lines.front();
    const auto sp1 = first.find(' ');
    const auto sp2 = sp1 == std::string_view::npos ? sp1 : first.find(' ', sp1 + 1);
    if (sp2 == std::string_view::npos || first.find(' ', sp2 + 1) != std::string_view::npos) {
        return refuse(400, "the request line is not METHOD TARGET HTTP/1.1");
    }
    request.method = std::string(first.substr(0, sp1));
    request.target = std::string(first.substr(sp1 + 1, sp2 - sp1 - 1));
    const auto version = first.substr(sp2 + 1);
    if (!is_token(request.method)) return refuse(400, "the method is not a token");
    if (version != "HTTP/1.1" && version != "HTTP/1.0") {
        if (version.substr(0, 5) == "HTTP/") return refuse(505, "only HTTP/1.1 and 1.0 are spoken");
        return refuse(400, "the request line is not METHOD TARGET HTTP/1.1");
    }
    if (request.target.empty() || request.target.front() != '/') {
        return refuse(400, "the target must be a path from / (origin form)");
    }
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const auto line = lines[i];
        if (line.front() == ' ' || line.front() == '\t')
            return refuse(400, "folded header lines are not taken");
        const auto colon = line.find(':');
        if (colon == std::string_view::npos || !is_token(line.substr(0, colon)))
            return refuse(400, "a header line is not NAME: VALUE");
        const auto value = trim(line.substr(colon + 1));
        for (const char c : value)
            if ((static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7f)
                return refuse(400, "a header value holds a control character");
        if (request.headers.size() == kMaxHeaders)
            return refuse(431, fmt::format("at most {} header lines are taken", kMaxHeaders));
        request.headers.emplace_back(lower(line.substr(0, colon)), std::string(value));
    }
    const std::string_view target = request.target;
    const auto question = target.find('?');
    auto path = percent_decode(target.substr(0, question));
    if (!path) return refuse(400, "the path holds a bad %-escape or %00");
    request.path = std::move(*path);
    if (question != std::string_view::npos &&
        !parse_query(target.substr(question + 1), request.query)) {
        return refuse(400, "the query holds a bad %-escape or %00");
    }
    read_framing(result, version == "HTTP/1.0");
    return result;
}

const char* status_text(int status) {
    switch (status) {
        case 100:
            return "Continue";
        case 200:
            return "OK";
        case 201:
            return "Created";
        case 204:
            return "No Content";
        case 400:
            return "Bad Request";
        case 401:
            return "Unauthorized";
        case 403:
            return "Forbidden";
        case 404:
            return "Not Found";
        case 405:
            return "Method Not Allowed";
        case 408:
            return "Request Timeout";
        case 409:
            return "Conflict";
        case 411:
            return "Length Required";
        case 413:
            return "Content Too Large";
        case 415:
            return "Unsupported Media Type";
        case 417:
            return "Expectation Failed";
        case 421:
            return "Misdirected Request";
        case 431:
            return "Request Header Fields Too Large";
        case 500:
            return "Internal Server Error";
        case 501:
            return "Not Implemented";
        case 503:
            return "Service Unavailable";
        case 505:
            return "HTTP Version Not Supported";
        default:
            return "Unknown";
    }
}

std::string write_reply(const HttpReply& reply, bool keep_alive, bool head_only) {
    std::string out = fmt::format(
        "HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\nConnection: {}\r\n{}\r\n",
        reply.status, status_text(reply.status), reply.content_type, reply.body.size(),
        keep_alive ? "keep-alive" : "close", kSecurityHeaders);
    if (!head_only) out += reply.body;
    return out;
}

std::string write_stream_head() {
    return fmt::format(
        "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nConnection: close\r\n{}\r\n",
        kSecurityHeaders);
}

}  // namespace mblab::web
