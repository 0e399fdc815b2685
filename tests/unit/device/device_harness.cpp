#include "device_harness.hpp"

#include <gtest/gtest.h>

#include <array>

#include "support/hex.hpp"

namespace mblab::test {

std::unique_ptr<device::ReferenceDevice> shipped_device(std::string_view name) {
    const std::string path =
        std::string(MBLAB_SOURCE_DIR) + "/profiles/" + std::string(name) + ".toml";
    auto loaded = device::load_profile(path);
    if (!loaded) {
        ADD_FAILURE() << loaded.error();
        return nullptr;
    }
    return std::move(loaded).value();
}

std::unique_ptr<device::ReferenceDevice> device_from(std::string_view toml) {
    auto loaded = device::load_profile_text(toml, "test.toml");
    if (!loaded) {
        ADD_FAILURE() << loaded.error();
        return nullptr;
    }
    return std::move(loaded).value();
}

std::string profile_error(std::string_view toml) {
    auto loaded = device::parse_profile(toml, "test.toml");
    return loaded ? std::string() : loaded.error();
}

device::Reply ask_reply(device::ReferenceDevice& device, std::string_view request_hex,
                        std::string& response_hex, std::uint8_t unit, device::Link link) {
    const auto request = hex(request_hex);
    std::array<std::uint8_t, 260> response{};
    const device::Reply reply =
        device.handle(device::RequestContext{unit, link}, request, response);
    switch (reply.action) {
        case device::ReplyAction::Answer:
            response_hex = to_hex(std::span(response).first(reply.size));
            break;
        case device::ReplyAction::NoAnswer:
            response_hex = "NO ANSWER";
            break;
        case device::ReplyAction::Close:
            response_hex = "CLOSE";
            break;
    }
    return reply;
}

std::string ask(device::ReferenceDevice& device, std::string_view request_hex, std::uint8_t unit,
                device::Link link) {
    std::string out;
    ask_reply(device, request_hex, out, unit, link);
    return out;
}

}  // namespace mblab::test

namespace mblab::test {
std::string text_hex(std::string_view text) {
    return to_hex(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}
}  // namespace mblab::test
