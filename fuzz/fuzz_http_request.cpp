// Bytes from an HTTP client into the request handling of `mblab serve --http`, as its I/O loop
// drives it: head parsed and bounded, the gate's checks, the body, the route table serve uses,
// the REST API over the reference device, the answer written; several requests in one input
// are handled in turn, as on a kept-alive connection. Nothing may throw past the handling, and
// every JSON answer must parse back (a path of invalid UTF-8 once ended the process).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string_view>

#include "device/profile_paths.hpp"
#include "device/reference_device.hpp"
#include "web/device_routes.hpp"
#include "web/http_gate.hpp"

namespace {

struct Served {
    std::unique_ptr<mblab::device::ReferenceDevice> device;
    mblab::web::RequestMeter meter;
    std::unique_ptr<mblab::web::DeviceApi> api;
    mblab::web::HttpRoutes routes;
    mblab::web::HttpGate gate{{"t0k", "127.0.0.1", 8080, {"plc.example"}}};
};

Served& served() {
    static std::unique_ptr<Served> instance = [] {
        auto s = std::make_unique<Served>();
        const auto path = std::filesystem::path(MBLAB_SOURCE_DIR) / "profiles" / "reference.toml";
        auto loaded = mblab::device::load_profile(path);
        if (!loaded) {
            std::fprintf(stderr, "%s\n", loaded.error().c_str());
            std::abort();
        }
        s->device = std::move(loaded).value();
        s->api = std::make_unique<mblab::web::DeviceApi>(
            mblab::web::ServeView{*s->device, s->meter, [] { return std::uint64_t{1}; }, {}});
        mblab::web::add_device_routes(s->routes, *s->api);
        return s;
    }();
    return *instance;
}

void check_json(const mblab::web::HttpReply& reply) {
    if (reply.content_type != "application/json") return;
    if (nlohmann::json::parse(reply.body, nullptr, false).is_discarded()) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    auto& s = served();
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    for (int requests = 0; requests < 8 && !bytes.empty(); ++requests) {
        auto head = mblab::web::parse_head(bytes);
        if (head.kind == mblab::web::HeadResult::Kind::NeedMore) return 0;
        if (head.kind == mblab::web::HeadResult::Kind::Refused) {
            if (head.status < 400 || head.status > 505) std::abort();
            return 0;
        }
        bytes.remove_prefix(head.used);
        auto& request = head.request;
        if (auto refusal = s.gate.check(request)) {
            check_json(*refusal);
            return 0;
        }
        if (request.body_length > bytes.size()) return 0;
        request.body = std::string(bytes.substr(0, request.body_length));
        bytes.remove_prefix(request.body_length);
        const auto outcome = s.routes.route(request);
        if (outcome.stream) {
            const auto event = mblab::web::HttpRoutes::next_event(*outcome.stream, request.query);
            if (event && event->substr(0, 6) != "data: ") std::abort();
            continue;
        }
        check_json(outcome.reply);
        const auto written =
            mblab::web::write_reply(outcome.reply, request.keep_alive, request.method == "HEAD");
        if (written.rfind("HTTP/1.1 ", 0) != 0) std::abort();
    }
    return 0;
}
