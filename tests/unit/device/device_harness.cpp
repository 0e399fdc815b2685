#include "device_harness.hpp"

#include <gtest/gtest.h>

#include <array>

#include "support/hex.hpp"

namespace mblab::test {

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
void expect_dialogue(device::ReferenceDevice& device, std::string_view script) {
    std::size_t line_number = 0;
    while (!script.empty()) {
        const auto end = script.find('\n');
        std::string_view line = script.substr(0, end);
        script = end == std::string_view::npos ? std::string_view() : script.substr(end + 1);
        ++line_number;
        line = line.substr(0, line.find('#'));
        const auto arrow = line.find("->");
        const auto trimmed = [](std::string_view text) {
            const auto first = text.find_first_not_of(' ');
            if (first == std::string_view::npos) return std::string_view();
            return text.substr(first, text.find_last_not_of(' ') - first + 1);
        };
        if (trimmed(line).empty()) continue;
        if (arrow == std::string_view::npos) {
            ADD_FAILURE() << "dialogue line " << line_number << " has no \"->\": " << line;
            continue;
        }
        const auto request = trimmed(line.substr(0, arrow));
        EXPECT_EQ(ask(device, request), trimmed(line.substr(arrow + 2)))
            << "dialogue line " << line_number << ": " << request;
    }
}

}  // namespace mblab::test
