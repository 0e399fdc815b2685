#include "conformance/provenance.hpp"

#include <fmt/core.h>
#include <toml++/toml.h>

#include <array>
#include <ctime>
#include <span>
#include <type_traits>
#include <variant>

#include "conformance/session.hpp"
#include "protocol/adu.hpp"
#include "protocol/limits.hpp"
#include "protocol/mbap_header.hpp"
#include "protocol/response.hpp"

namespace mblab::conformance {

namespace {

constexpr std::uint8_t kVendorName = 0x00;
constexpr std::uint8_t kProductCode = 0x01;
constexpr std::uint8_t kRevision = 0x02;

std::string not_answered_reason(const client::Received& received,
                                std::chrono::milliseconds timeout) {
    switch (received.status) {
        case client::ReceiveStatus::Timeout:
            return fmt::format("no answer within {} ms", timeout.count());
        case client::ReceiveStatus::Closed:
            return received.detail.empty() ? "connection closed"
                                           : "connection closed: " + received.detail;
        case client::ReceiveStatus::Malformed:
            return received.detail.empty() ? "malformed answer"
                                           : "malformed answer: " + received.detail;
        case client::ReceiveStatus::Frame:
            break;
    }
    return "no answer";
}

// Keeps objects 00-02 of one answer; true when the stream goes on past them.
bool take_objects(const protocol::ReadDeviceIdResponse& answer, DeviceIdentity& identity,
                  std::uint8_t& next) {
    protocol::DeviceIdObject object;
    std::size_t offset = 0;
    std::uint8_t last = 0;
    bool any = false;
    while (answer.next(offset, object)) {
        auto value = object.text();
        if (object.id == kVendorName) identity.vendor_name = std::move(value);
        if (object.id == kProductCode) identity.product_code = std::move(value);
        if (object.id == kRevision) identity.revision = std::move(value);
        last = object.id;
        any = true;
    }
    // Each answer must move forward, or a device could keep the tester asking forever.
    if (answer.more_follows != 0xFF || !any || answer.next_object_id <= last) return false;
    next = answer.next_object_id;
    return next <= kRevision;
}

}  // namespace

std::string iso8601_utc(std::chrono::system_clock::time_point time) {
    const std::time_t seconds = std::chrono::system_clock::to_time_t(time);
    std::tm utc{};
    ::gmtime_r(&seconds, &utc);
    std::array<char, 32> text{};
    const std::size_t size = std::strftime(text.data(), text.size(), "%Y-%m-%dT%H:%M:%SZ", &utc);
    return std::string(text.data(), size);
}

std::vector<Declaration> declarations_of(
    const Dut& dut, const std::function<std::string(std::string_view)>& source_of) {
    std::vector<Declaration> out;
    for (std::string_view key : dut_keys()) {
        std::visit(
            [&](const auto& value) {
                if constexpr (!std::is_same_v<std::decay_t<decltype(value)>, std::monostate>)
                    out.push_back({std::string(key), value, source_of(key)});
            },
            dut_value(dut, key));
    }
    return out;
}

std::vector<std::string> dut_file_keys(const std::string& path) {
    std::vector<std::string> keys;
    try {
        const toml::table table = toml::parse_file(path);
        for (const auto& [key, node] : table)
            keys.emplace_back(key.str());
    } catch (const toml::parse_error&) {
        // load_dut_file has read it already; a file changed since has no keys to show.
    }
    return keys;
}

DeviceIdentity ask_device_identity(Session& session) {
    DeviceIdentity identity;
    // A fresh connection, so bytes a case left unread are not taken for the answer.
    session.close();
    const auto timeout = session.options().timeout;
    std::uint8_t next = kVendorName;
    // Three answers at most: each must move forward through objects 00-02.
    for (std::uint16_t asked = 0; asked < 3; ++asked) {
        const std::uint16_t transaction = 0x2B00 + asked;
        // 2B / 0E, read code 01 (basic), from object `next`.
        const std::array<std::uint8_t, 4> pdu = {0x2B, 0x0E, 0x01, next};
        std::array<std::uint8_t, protocol::limits::kMaxTcpAdu> adu{};
        const auto request = std::span(adu).first(protocol::write_adu(
            {protocol::Framing::Mbap, session.dut().unit, transaction}, pdu, adu));
        client::LinkError error;
        if (!session.send(request, 1, error)) {
            identity.reason = error.message.empty()
                                  ? "the request could not be sent"
                                  : "the request could not be sent: " + error.message;
            break;
        }
        const client::Received received = session.receive_frame(timeout);
        if (received.status != client::ReceiveStatus::Frame) {
            identity.reason = not_answered_reason(received, timeout);
            break;
        }
        const auto frame = protocol::read_mbap_frame(received.bytes);
        if (!frame || frame->pdu.empty() || frame->header.transaction_id != transaction) {
            identity.reason = "the answer does not belong to the request";
            break;
        }
        const auto decoded = protocol::decode_response(frame->pdu);
        if (!decoded) {
            identity.reason = fmt::format("undecodable answer: {} ({})", decoded.error().reason,
                                          decoded.error().field);
            break;
        }
        if (const auto* exception = std::get_if<protocol::ExceptionResponse>(&*decoded)) {
            identity.reason =
                fmt::format("exception {:02X} ({})", static_cast<unsigned>(exception->code),
                            protocol::exception_name(exception->code));
            break;
        }
        const auto* answer = std::get_if<protocol::ReadDeviceIdResponse>(&*decoded);
        if (answer == nullptr) {
            identity.reason = "an answer of another function code";
            break;
        }
        if (!take_objects(*answer, identity, next)) break;
    }
    identity.answered = !identity.vendor_name.empty() || !identity.product_code.empty() ||
                        !identity.revision.empty();
    if (identity.answered) {
        identity.reason.clear();
    } else if (identity.reason.empty()) {
        identity.reason = "the answer held none of objects 00-02";
    }
    return identity;
}

std::string shell_words(const std::vector<std::string>& words) {
    std::string out;
    for (const auto& word : words) {
        if (!out.empty()) out += ' ';
        const bool plain =
            !word.empty() && word.find_first_not_of(
                                 "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                 "0123456789_@%+=:,./-") == std::string::npos;
        if (plain) {
            out += word;
            continue;
        }
        out += '\'';
        for (char c : word)
            out += c == '\'' ? std::string("'\\''") : std::string(1, c);
        out += '\'';
    }
    return out;
}

std::string identity_text(const DeviceIdentity& identity) {
    if (!identity.answered) return fmt::format("not answered ({})", identity.reason);
    return fmt::format("vendor name \"{}\", product code \"{}\", revision \"{}\"",
                       identity.vendor_name, identity.product_code, identity.revision);
}

std::string value_text(const Declaration& declaration) {
    if (const auto* flag = std::get_if<bool>(&declaration.value)) return *flag ? "true" : "false";
    if (const auto* number = std::get_if<std::uint32_t>(&declaration.value))
        return std::to_string(*number);
    return std::get<std::string>(declaration.value);
}

std::vector<std::string> provenance_lines(const Provenance& provenance) {
    std::vector<std::string> lines = {
        fmt::format("mblab version: {}", provenance.version),
        fmt::format("git commit: {}", provenance.commit),
        fmt::format("started: {}", provenance.started),
        fmt::format("finished: {}", provenance.finished),
        fmt::format("command line: {}", shell_words(provenance.command_line)),
        fmt::format("declared by: {}", provenance.declared_by),
    };
    for (const auto& declaration : provenance.declarations) {
        lines.push_back(fmt::format("dut {}: {} ({})", declaration.key, value_text(declaration),
                                    declaration.source));
    }
    lines.push_back("device identity: " + identity_text(provenance.device));
    return lines;
}

}  // namespace mblab::conformance
