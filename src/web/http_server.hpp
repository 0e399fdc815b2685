#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "web/http_gate.hpp"
#include "web/http_routes.hpp"

// The HTTP side of `serve --http` and `load --metrics`, on threads of its own, never the Modbus
// event loop's. One thread owns every socket and moves bytes without blocking, so a client that
// sends or reads slowly holds a connection slot, never a thread: a whole request head must come
// within a deadline, a full table lets go of the oldest unfinished request first, and a
// Prometheus scrape is answered while slow clients wait. Handlers run on a few worker threads.
namespace mblab::web {

// HOST:PORT as --http and --metrics take it: an IPv4 address, [IPv6], or localhost.
struct HttpAddress {
    std::string host;
    std::uint16_t port = 0;
};
std::optional<HttpAddress> parse_http_address(const std::string& text, std::string& error);
bool is_loopback(const std::string& host);

class HttpServer {
  public:
    explicit HttpServer(GateOptions gate = {});
    ~HttpServer();
    HttpServer(const HttpServer&) = delete;
    HttpServer& operator=(const HttpServer&) = delete;

    // Before start().
    HttpRoutes& routes() { return routes_; }

    // Binds (port 0: any free port) and serves on its own threads; the port, or nullopt and
    // `error`.
    std::optional<std::uint16_t> start(const HttpAddress& address, std::string& error);
    // Closes every connection and ends the threads; called by the destructor too.
    void stop();

  private:
    struct Loop;
    struct Job {
        std::uint64_t connection = 0;
        HttpRequest request;
    };
    struct Done {
        std::uint64_t connection = 0;
        HttpRoutes::Outcome outcome;
    };

    void work();

    GateOptions gate_options_;
    HttpRoutes routes_;
    std::unique_ptr<Loop> loop_;
    std::thread io_thread_;
    std::vector<std::thread> workers_;
    std::mutex jobs_mutex_;
    std::condition_variable jobs_changed_;
    std::deque<Job> jobs_;
    std::vector<Done> done_;
    bool stopping_ = false;
    int wake_fd_ = -1;
};

}  // namespace mblab::web
