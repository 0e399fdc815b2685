#include "cli/serve_http.hpp"

#include <fmt/core.h>

#include <fstream>

#include "web/dashboard_page.hpp"
#include "web/metrics_text.hpp"
#include "web/serve_metrics.hpp"

namespace mblab::cli {

namespace {

// How often the dashboard's event stream sends the counters and the page it shows.
constexpr std::chrono::milliseconds kEventPeriod{500};

bool read_token_file(const std::string& path, std::string& token, std::string& error) {
    std::ifstream in(path);
    if (!in || !std::getline(in, token)) {
        error = fmt::format("--http-token-file {}: cannot read a token from it", path);
        return false;
    }
    while (!token.empty() && (token.back() == '\r' || token.back() == ' '))
        token.pop_back();
    if (token.empty()) {
        error = fmt::format("--http-token-file {}: the first line is empty", path);
        return false;
    }
    return true;
}

}  // namespace

void add_http_options(CLI::App& command, HttpOptions& options) {
    command.add_option("--http", options.address,
                       "serve a dashboard, a REST API under /api and Prometheus metrics at "
                       "/metrics on HOST:PORT, e.g. 127.0.0.1:8080 (docs/http.md)");
    command.add_option("--http-token", options.token,
                       "require \"Authorization: Bearer TOKEN\" on --http writes (needed when "
                       "--http is not a loopback address)");
    command.add_option("--http-token-file", options.token_file,
                       "as --http-token, the token being the first line of FILE");
}

std::optional<HttpPlan> plan_http(const HttpOptions& options, std::string& error) {
    if (options.address.empty()) {
        if (!options.token.empty() || !options.token_file.empty()) {
            error = "--http-token and --http-token-file need --http";
        }
        return std::nullopt;
    }
    auto address = web::parse_http_address(options.address, error);
    if (!address) {
        error = "--http " + error;
        return std::nullopt;
    }
    HttpPlan plan{*address, options.token};
    if (!options.token.empty() && !options.token_file.empty()) {
        error = "give --http-token or --http-token-file, not both";
        return std::nullopt;
    }
    if (!options.token_file.empty() && !read_token_file(options.token_file, plan.token, error)) {
        return std::nullopt;
    }
    if (plan.token.empty() && !web::is_loopback(plan.address.host)) {
        error = fmt::format(
            "--http {}: not a loopback address, so writes need --http-token or "
            "--http-token-file",
            options.address);
        return std::nullopt;
    }
    return plan;
}

bool LiveDevice::start(const HttpPlan& plan, std::function<std::uint64_t()> connections,
                       std::function<bool(std::string&)> save_state, std::string& error) {
    api_ = std::make_unique<web::DeviceApi>(web::ServeView{device_, meter_, std::move(connections),
                                                           std::move(save_state), write_values_});
    server_ = std::make_unique<web::HttpServer>(plan.token);
    auto* api = api_.get();
    server_->get("/", [](const web::ApiRequest&) {
        return web::HttpReply{200, std::string(web::dashboard_page()), "text/html; charset=utf-8"};
    });
    server_->get("/metrics", [api](const web::ApiRequest&) {
        return web::HttpReply{200, web::serve_metrics(api->view()), web::kMetricsContentType};
    });
    // Before /api's catch-all, which would take it.
    server_->events(
        "/api/events", [api](const auto& query) { return api->live_event(query).dump(); },
        kEventPeriod);
    server_->under("/api", [api](const web::ApiRequest& request) {
        auto reply = api->handle(request);
        return web::HttpReply{reply.status, std::move(reply.body)};
    });
    auto port = server_->start(plan.address, error);
    if (!port) return false;
    const bool v6 = plan.address.host.find(':') != std::string::npos;
    fmt::print(
        "mblab serve: dashboard on http://{}{}{}:{}/, REST API under /api, metrics at "
        "/metrics{}\n",
        v6 ? "[" : "", plan.address.host, v6 ? "]" : "", *port,
        plan.token.empty() ? "" : "; writes need the token");
    std::fflush(stdout);
    return true;
}

}  // namespace mblab::cli
