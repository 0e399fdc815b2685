#include "robustness/reproducer.hpp"

#include <arpa/inet.h>
#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <sstream>

#include "client/hex_text.hpp"

namespace mblab::robustness {

std::string reproducer_text(const std::vector<Step>& steps, const std::string& comment) {
    std::string out;
    std::istringstream lines(comment);
    for (std::string line; std::getline(lines, line);)
        out += "# " + line + "\n";
    for (const auto& step : steps) {
        std::string line = step.connection == 0 ? "" : fmt::format("@{} ", step.connection);
        line += client::hex_bytes(step.bytes);
        if (step.pause.count() > 0) line += fmt::format(" +{}ms", step.pause.count());
        if (step.unread) line += " unread";
        if (step.vanish) line += " vanish";
        out += line + "\n";
    }
    return out;
}

protocol::Result<std::vector<Step>, std::string> parse_reproducer(const std::string& text) {
    std::vector<Step> steps;
    std::istringstream lines(text);
    std::size_t number = 0;
    for (std::string line; std::getline(lines, line);) {
        ++number;
        line = line.substr(0, line.find('#'));
        std::istringstream words(line);
        Step step;
        bool any = false;
        for (std::string word; words >> word;) {
            auto bad = [&](std::string_view why) {
                return fmt::format("line {}: '{}' {}", number, word, why);
            };
            if (word.front() == '@' && !any && step.bytes.empty()) {
                const auto digits = word.substr(1);
                if (digits.empty() || digits.size() > 4 ||
                    digits.find_first_not_of("0123456789") != std::string::npos)
                    return bad("is not a connection number (@1, @2, ...)");
                step.connection = std::stoul(digits);
                any = true;
                continue;
            }
            if (word.front() == '+' && word.ends_with("ms")) {
                const auto digits = word.substr(1, word.size() - 3);
                if (digits.empty() || digits.size() > 6 ||
                    digits.find_first_not_of("0123456789") != std::string::npos)
                    return bad("is not a pause (+20ms)");
                step.pause = std::chrono::milliseconds(std::stoul(digits));
                continue;
            }
            if (word == "unread" || word == "vanish") {
                if (step.bytes.empty()) return bad("comes after the bytes it is about");
                (word == "unread" ? step.unread : step.vanish) = true;
                continue;
            }
            if (word.size() != 2 || !std::isxdigit(static_cast<unsigned char>(word[0])) ||
                !std::isxdigit(static_cast<unsigned char>(word[1])))
                return bad("is not a byte: give two hex digits a byte (00 01 FF)");
            step.bytes.push_back(static_cast<std::uint8_t>(std::stoul(word, nullptr, 16)));
            any = true;
        }
        if (!any && step.pause.count() == 0) continue;
        if (step.bytes.empty())
            return fmt::format("line {}: no bytes: a step is hex bytes on the wire", number);
        steps.push_back(std::move(step));
    }
    if (steps.empty()) return std::string("no steps: a reproducer has a line of hex bytes");
    return steps;
}

std::vector<conformance::CaptureEvent> reproducer_capture(const std::vector<Step>& steps,
                                                          const std::string& host,
                                                          std::uint16_t port) {
    using Kind = conformance::CaptureEvent::Kind;
    // The device's address as given; a name the capture cannot show stays all zero (loopback).
    client::LinkAddresses addresses;
    in6_addr peer6{};
    in_addr peer4{};
    if (::inet_pton(AF_INET6, host.c_str(), &peer6) == 1) {
        addresses.ipv6 = true;
        std::memcpy(addresses.peer_ip.data(), &peer6, sizeof peer6);
    } else if (::inet_pton(AF_INET, host.c_str(), &peer4) == 1) {
        std::memcpy(addresses.peer_ip.data(), &peer4, sizeof peer4);
    }
    addresses.peer_port = port;
    auto time = std::chrono::system_clock::now();
    std::vector<conformance::CaptureEvent> events;
    std::vector<std::size_t> opened;
    // One connection's events in a row; a pcap of segments interleaved between connections
    // needs the connection's addresses on every packet, which the capture gives at Open only.
    for (const auto& step : steps) {
        if (std::find(opened.begin(), opened.end(), step.connection) != opened.end()) continue;
        opened.push_back(step.connection);
        conformance::CaptureEvent open{Kind::Open, time, {}, {}, false};
        open.addresses = addresses;
        open.addresses.local_port = static_cast<std::uint16_t>(40000 + opened.size());
        events.push_back(open);
        for (const auto& other : steps) {
            if (other.connection != step.connection) continue;
            events.push_back({Kind::Sent, time, other.bytes, {}, false});
            time += other.pause + std::chrono::milliseconds(1);
        }
        events.push_back({Kind::Close, time, {}, {}, false});
    }
    return events;
}

}  // namespace mblab::robustness
