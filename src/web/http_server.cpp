#include "web/http_server.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <httplib.h>

#include <charconv>
#include <nlohmann/json.hpp>

namespace mblab::web {

namespace {

// Each event stream holds one of the server's threads while open; the rest stay for the API.
constexpr int kThreads = 8;
constexpr int kMaxStreams = 4;
constexpr std::size_t kMaxBody = 1 << 20;

std::string error_body(const std::string& reason) {
    return nlohmann::json{{"error", reason}}.dump();
}

ApiRequest api_request(const httplib::Request& request) {
    ApiRequest out{request.method, request.path, {}, request.body};
    for (const auto& [key, value] : request.params)
        out.query[key] = value;
    return out;
}

void send(httplib::Response& response, const HttpReply& reply) {
    response.status = reply.status;
    response.set_content(reply.body, reply.content_type.c_str());
}

}  // namespace

std::optional<HttpAddress> parse_http_address(const std::string& text, std::string& error) {
    const auto colon = text.rfind(':');
    std::string host = colon == std::string::npos ? std::string() : text.substr(0, colon);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
        host = host.substr(1, host.size() - 2);
    }
    const std::string port_text = colon == std::string::npos ? text : text.substr(colon + 1);
    unsigned port = 0;
    const auto* end = port_text.data() + port_text.size();
    auto [at, ec] = std::from_chars(port_text.data(), end, port);
    in6_addr any{};
    const bool host_ok = host == "localhost" || ::inet_pton(AF_INET, host.c_str(), &any) == 1 ||
                         ::inet_pton(AF_INET6, host.c_str(), &any) == 1;
    if (colon == std::string::npos || !host_ok || port_text.empty() || ec != std::errc() ||
        at != end || port > 65535) {
        error = fmt::format("'{}': expected HOST:PORT, e.g. 127.0.0.1:8080 (port 0: any free port)",
                            text);
        return std::nullopt;
    }
    return HttpAddress{host == "localhost" ? "127.0.0.1" : host, static_cast<std::uint16_t>(port)};
}

bool is_loopback(const std::string& host) {
    in_addr v4{};
    if (::inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
    return host == "::1";
}

HttpServer::HttpServer(std::string token)
    : server_(std::make_unique<httplib::Server>()), token_(std::move(token)) {
    server_->new_task_queue = [] { return new httplib::ThreadPool(kThreads); };
    server_->set_payload_max_length(kMaxBody);
    // What cpp-httplib refuses before a handler runs (a POST without Content-Length, an
    // unknown path, a body over the limit) still gets one line of JSON.
    server_->set_error_handler([](const httplib::Request& request, httplib::Response& response) {
        if (!response.body.empty()) return;
        std::string reason = fmt::format("{} {}: refused with status {}", request.method,
                                         request.path, response.status);
        if (response.status == 400 && !request.has_header("Content-Length")) {
            reason += " (a POST or PUT needs Content-Length; with curl, -d '' sends an empty body)";
        }
        response.set_content(error_body(reason), "application/json");
    });
    server_->set_exception_handler(
        [](const httplib::Request&, httplib::Response& response, std::exception_ptr) {
            response.status = 500;
            response.set_content(error_body("internal error"), "application/json");
        });
}

HttpServer::~HttpServer() {
    stop();
}

bool HttpServer::authorized(const std::string& method, const std::string& header) const {
    return token_.empty() || method == "GET" || header == "Bearer " + token_;
}

void HttpServer::get(const std::string& path, HttpHandler handler) {
    server_->Get(path, [handler = std::move(handler)](const httplib::Request& request,
                                                      httplib::Response& response) {
        send(response, handler(api_request(request)));
    });
}

void HttpServer::under(const std::string& prefix, HttpHandler handler) {
    const auto serve = [this, handler = std::move(handler)](const httplib::Request& request,
                                                            httplib::Response& response) {
        if (!authorized(request.method, request.get_header_value("Authorization"))) {
            send(response, {401, error_body("this server takes writes with "
                                            "\"Authorization: Bearer TOKEN\" (--http-token)")});
            return;
        }
        send(response, handler(api_request(request)));
    };
    const std::string pattern = prefix + "(/.*)?";
    server_->Get(pattern, serve);
    server_->Post(pattern, serve);
    server_->Put(pattern, serve);
    server_->Delete(pattern, serve);
    server_->Patch(pattern, serve);
}

void HttpServer::events(const std::string& path, EventSource source,
                        std::chrono::milliseconds period) {
    server_->Get(path, [this, source = std::move(source), period](const httplib::Request& request,
                                                                  httplib::Response& response) {
        if (streams_.fetch_add(1) >= kMaxStreams) {
            streams_.fetch_sub(1);
            send(response,
                 {503, error_body(fmt::format("at most {} event streams at once", kMaxStreams))});
            return;
        }
        const auto query = api_request(request).query;
        response.set_header("Cache-Control", "no-cache");
        response.set_chunked_content_provider(
            "text/event-stream",
            [this, source, period, query](std::size_t, httplib::DataSink& sink) {
                const std::string event = "data: " + source(query) + "\n\n";
                if (!sink.is_writable() || !sink.write(event.data(), event.size())) return false;
                std::unique_lock lock(stop_mutex_);
                return !stop_changed_.wait_for(lock, period, [this] { return stopping_; });
            },
            [this](bool) { streams_.fetch_sub(1); });
    });
}

std::optional<std::uint16_t> HttpServer::start(const HttpAddress& address, std::string& error) {
    const int port = address.port == 0 ? server_->bind_to_any_port(address.host)
                     : server_->bind_to_port(address.host, address.port) ? address.port
                                                                         : -1;
    if (port <= 0) {
        error = fmt::format("cannot listen for HTTP on {}:{}: {}", address.host, address.port,
                            std::strerror(errno));
        return std::nullopt;
    }
    thread_ = std::thread([this] { server_->listen_after_bind(); });
    return static_cast<std::uint16_t>(port);
}

void HttpServer::stop() {
    {
        std::lock_guard lock(stop_mutex_);
        stopping_ = true;
    }
    stop_changed_.notify_all();
    server_->stop();
    if (thread_.joinable()) thread_.join();
}

}  // namespace mblab::web
