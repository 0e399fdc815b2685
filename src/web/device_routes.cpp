#include "web/device_routes.hpp"

#include "web/dashboard_page.hpp"
#include "web/json_text.hpp"
#include "web/metrics_text.hpp"
#include "web/serve_metrics.hpp"

namespace mblab::web {

namespace {

// How often the dashboard's event stream sends the counters and the page it shows.
constexpr std::chrono::milliseconds kEventPeriod{500};

HttpHandler constant(std::string_view body, const char* type) {
    return [body, type](const HttpRequest&) { return HttpReply{200, std::string(body), type}; };
}

}  // namespace

void add_device_routes(HttpRoutes& routes, DeviceApi& api) {
    routes.get("/", constant(dashboard_page(), "text/html; charset=utf-8"));
    routes.get("/dashboard.css", constant(dashboard_style(), "text/css; charset=utf-8"));
    routes.get("/dashboard.js", constant(dashboard_script(), "text/javascript; charset=utf-8"));
    routes.get("/metrics", [&api](const HttpRequest&) {
        return HttpReply{200, serve_metrics(api.view()), kMetricsContentType};
    });
    routes.events(
        "/api/events", [&api](const auto& query) { return json_text(api.live_event(query)); },
        kEventPeriod);
    routes.under("/api", [&api](const HttpRequest& request) {
        auto reply = api.handle({request.method, request.path, request.query, request.body});
        return HttpReply{reply.status, std::move(reply.body)};
    });
}

}  // namespace mblab::web
