#pragma once

#include "web/device_api.hpp"
#include "web/http_routes.hpp"

// What `serve --http` answers, path by path: the dashboard and its files, /metrics, the event
// stream and the REST API. One table for serve, the tests and the fuzz target.
namespace mblab::web {

void add_device_routes(HttpRoutes& routes, DeviceApi& api);

}  // namespace mblab::web
