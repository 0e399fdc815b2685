#include "web/http_routes.hpp"

#include <fmt/format.h>

#include <exception>

#include "web/json_text.hpp"

namespace mblab::web {

HttpReply json_error(int status, const std::string& reason) {
    return {status, json_text({{"error", reason}})};
}

void HttpRoutes::get(std::string path, HttpHandler handler) {
    routes_.push_back({std::move(path), false, std::move(handler)});
}

void HttpRoutes::under(std::string prefix, HttpHandler handler) {
    routes_.push_back({std::move(prefix), true, std::move(handler)});
}

void HttpRoutes::events(std::string path, EventSource source, std::chrono::milliseconds period) {
    events_.push_back({std::move(path), std::move(source), period});
}

HttpRoutes::Outcome HttpRoutes::route(const HttpRequest& request) const {
    const bool reading = request.method == "GET" || request.method == "HEAD";
    for (const auto& stream : events_) {
        if (request.path != stream.path) continue;
        if (request.method != "GET") return {json_error(405, stream.path + " takes GET")};
        return {{}, &stream};
    }
    for (const auto& route : routes_) {
        const bool match = route.prefix ? request.path == route.path ||
                                              request.path.rfind(route.path + "/", 0) == 0
                                        : request.path == route.path;
        if (!match) continue;
        if (!route.prefix && !reading) return {json_error(405, route.path + " takes GET")};
        try {
            return {route.handler(request)};
        } catch (const std::exception& e) {
            return {json_error(500, fmt::format("internal error: {}", e.what()))};
        } catch (...) {
            return {json_error(500, "internal error")};
        }
    }
    return {json_error(404, fmt::format("no such resource: {} {}", request.method, request.path))};
}

std::optional<std::string> HttpRoutes::next_event(const EventRoute& route,
                                                  const std::map<std::string, std::string>& query) {
    try {
        return "data: " + route.source(query) + "\n\n";
    } catch (...) {
        return std::nullopt;
    }
}

}  // namespace mblab::web
