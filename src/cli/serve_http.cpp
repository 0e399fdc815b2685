#include "cli/serve_http.hpp"

#include <fmt/core.h>
#include <sys/random.h>

#include <fstream>

#include "web/device_routes.hpp"

namespace mblab::cli {

namespace {

// 128 bits from the kernel's generator, as hex: what a page on another site cannot guess.
std::string random_token() {
    unsigned char bytes[16] = {};
    std::size_t got = 0;
    while (got < sizeof bytes) {
        const auto n = ::getrandom(bytes + got, sizeof bytes - got, 0);
        if (n > 0) got += static_cast<std::size_t>(n);
    }
    std::string out;
    for (const auto b : bytes)
        out += fmt::format("{:02x}", b);
    return out;
}

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
                       "require \"Authorization: Bearer TOKEN\" on --http changes (by default a "
                       "random token is made and printed)");
    command.add_option("--http-token-file", options.token_file,
                       "as --http-token, the token being the first line of FILE");
    command.add_flag("--http-no-token", options.no_token,
                     "on a loopback --http address, take changes without a token (any program "
                     "of any user on this machine may then make them)");
    command.add_option("--http-allow-host", options.allowed_hosts,
                       "a host name the HTTP side answers to besides its address and localhost "
                       "(others are refused against DNS rebinding); repeatable");
}

std::optional<HttpPlan> plan_http(const HttpOptions& options, std::string& error) {
    if (options.address.empty()) {
        if (!options.token.empty() || !options.token_file.empty() || options.no_token ||
            !options.allowed_hosts.empty()) {
            error =
                "--http-token, --http-token-file, --http-no-token and --http-allow-host "
                "need --http";
        }
        return std::nullopt;
    }
    auto address = web::parse_http_address(options.address, error);
    if (!address) {
        error = "--http " + error;
        return std::nullopt;
    }
    HttpPlan plan{*address, options.token, options.allowed_hosts};
    if ((!options.token.empty() + !options.token_file.empty() + options.no_token) > 1) {
        error = "give one of --http-token, --http-token-file and --http-no-token";
        return std::nullopt;
    }
    if (!options.token_file.empty() && !read_token_file(options.token_file, plan.token, error)) {
        return std::nullopt;
    }
    if (options.no_token && !web::is_loopback(plan.address.host)) {
        error = fmt::format(
            "--http {}: not a loopback address, so changes need a token (--http-no-token is for "
            "loopback only)",
            options.address);
        return std::nullopt;
    }
    if (plan.token.empty() && !options.no_token) {
        plan.token = random_token();
        plan.token_made = true;
    }
    return plan;
}

bool LiveDevice::start(const HttpPlan& plan, std::function<std::uint64_t()> connections,
                       std::function<bool(std::string&)> save_state, std::string& error) {
    api_ = std::make_unique<web::DeviceApi>(web::ServeView{
        device_, meter_, std::move(connections), std::move(save_state), write_values_, traffic_});
    server_ = std::make_unique<web::HttpServer>(web::GateOptions{plan.token, {}, 0, plan.names});
    web::add_device_routes(server_->routes(), *api_);
    auto port = server_->start(plan.address, error);
    if (!port) return false;
    const bool v6 = plan.address.host.find(':') != std::string::npos;
    const auto base =
        fmt::format("http://{}{}{}:{}/", v6 ? "[" : "", plan.address.host, v6 ? "]" : "", *port);
    if (plan.token_made) {
        fmt::print(
            "mblab serve: dashboard on {}#token={}, REST API under /api (changes need "
            "\"Authorization: Bearer {}\"), metrics at /metrics\n",
            base, plan.token, plan.token);
    } else {
        fmt::print("mblab serve: dashboard on {}, REST API under /api, metrics at /metrics{}\n",
                   base, plan.token.empty() ? "" : "; changes need the token");
    }
    std::fflush(stdout);
    return true;
}

}  // namespace mblab::cli
