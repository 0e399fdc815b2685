#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "web/device_api.hpp"

namespace httplib {
class Server;
}

// The HTTP side of `serve --http` and `load --metrics`: cpp-httplib's threaded server on threads
// of its own, never the Modbus event loop's. It carries requests to handlers and back; what the
// answers say is the handlers' (device_api.hpp, serve_metrics.hpp, load_metrics.hpp).
namespace mblab::web {

struct HttpReply {
    int status = 200;
    std::string body;
    std::string content_type = "application/json";
};
using HttpHandler = std::function<HttpReply(const ApiRequest&)>;
// The data of one server-sent event, from the query the stream was opened with.
using EventSource = std::function<std::string(const std::map<std::string, std::string>& query)>;

// HOST:PORT as --http and --metrics take it: an IPv4 address, [IPv6], or localhost.
struct HttpAddress {
    std::string host;
    std::uint16_t port = 0;
};
std::optional<HttpAddress> parse_http_address(const std::string& text, std::string& error);
bool is_loopback(const std::string& host);

class HttpServer {
  public:
    // With a token, every request but GET must carry "Authorization: Bearer TOKEN".
    explicit HttpServer(std::string token = {});
    ~HttpServer();
    HttpServer(const HttpServer&) = delete;
    HttpServer& operator=(const HttpServer&) = delete;

    // Before start(): GET of exactly `path`, or every method under `prefix`.
    void get(const std::string& path, HttpHandler handler);
    void under(const std::string& prefix, HttpHandler handler);
    // GET `path` is a text/event-stream sending source's data every `period`.
    void events(const std::string& path, EventSource source, std::chrono::milliseconds period);

    // Binds (port 0: any free port) and serves on its own threads; the port, or nullopt and
    // `error`.
    std::optional<std::uint16_t> start(const HttpAddress& address, std::string& error);
    // Ends open event streams and the threads; called by the destructor too.
    void stop();

  private:
    bool authorized(const std::string& method, const std::string& header) const;

    std::unique_ptr<httplib::Server> server_;
    std::string token_;
    std::thread thread_;
    std::mutex stop_mutex_;
    std::condition_variable stop_changed_;
    bool stopping_ = false;
    std::atomic<int> streams_{0};
};

}  // namespace mblab::web
