#include "conformance/serial_line_probe.hpp"

#include <fmt/core.h>

#include <array>
#include <cctype>
#include <thread>

#include "client/hex_text.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/procedures.hpp"
#include "conformance/session.hpp"
#include "protocol/adu.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"
#include "protocol/limits.hpp"
#include "protocol/lrc.hpp"
#include "support/hex_digits.hpp"

namespace mblab::conformance {

namespace {

constexpr std::uint8_t kReadHolding = 0x03;
constexpr std::uint8_t kWriteSingle = 0x06;
constexpr std::uint8_t kLastAddress = 247;  // [SER 2.2]: 248..255 are reserved

char upper_hex(unsigned nibble) {
    return kHexDigits[nibble & 0x0F];
}

// The two hex digits of an ASCII frame's LRC sit before its CR LF.
void replace_lrc(std::vector<std::uint8_t>& wire, std::uint8_t lrc) {
    const std::size_t at = wire.size() - 4;
    wire[at] = static_cast<std::uint8_t>(upper_hex(lrc >> 4));
    wire[at + 1] = static_cast<std::uint8_t>(upper_hex(lrc));
}

// The DUT's declaration first (it knows the line), then the case's parameter, then the next
// address.
std::uint8_t other_address(const Dut& dut, const Case& c, std::uint8_t own) {
    if (dut.other_address) return *dut.other_address;
    const auto declared = param(c, "other_address");
    if (declared >= 1 && declared <= kLastAddress) return static_cast<std::uint8_t>(declared);
    return own == kLastAddress ? kLastAddress - 1 : own + 1;
}

}  // namespace

std::array<std::uint8_t, 5> read_holding(std::uint16_t address, std::uint16_t count) {
    return {kReadHolding, static_cast<std::uint8_t>(address >> 8),
            static_cast<std::uint8_t>(address), static_cast<std::uint8_t>(count >> 8),
            static_cast<std::uint8_t>(count)};
}

LineProbe::LineProbe(Session& session, const Case& c)
    : session_(session),
      own_(session.dut().unit),
      other_(other_address(session.dut(), c, own_)),
      register_(static_cast<std::uint16_t>(param(c, "register"))) {}

std::chrono::milliseconds LineProbe::timeout() const {
    return session_.options().timeout;
}

bool LineProbe::ascii() const {
    return session_.framing() == client::Framing::Ascii;
}

std::vector<std::uint8_t> LineProbe::frame(std::uint8_t address, std::span<const std::uint8_t> pdu,
                                           Spoil spoil) const {
    std::array<std::uint8_t, protocol::limits::kMaxAsciiChars> out{};
    const std::size_t size = protocol::write_adu({session_.framing(), address}, pdu, out);
    std::vector<std::uint8_t> wire(out.begin(), out.begin() + static_cast<long>(size));
    if (spoil == Spoil::Checksum && ascii()) {
        std::vector<std::uint8_t> body{address};
        body.insert(body.end(), pdu.begin(), pdu.end());
        replace_lrc(wire, static_cast<std::uint8_t>(protocol::lrc(body) + 1));
    } else if (spoil == Spoil::Checksum && wire.size() >= 2) {
        wire[wire.size() - 2] ^= 0xFF;
    } else if (spoil == Spoil::LowerCase) {
        for (auto& c : wire)
            c = static_cast<std::uint8_t>(std::tolower(c));
    }
    return wire;
}

LineAnswer LineProbe::ask(std::vector<std::uint8_t> wire, std::chrono::milliseconds wait,
                          RequestPause pause) {
    LineAnswer answer;
    answer.exchange.sent = std::move(wire);
    answer.exchange.framing = session_.framing();
    answer.exchange.waited = wait;
    const std::span<const std::uint8_t> sent = answer.exchange.sent;
    const std::size_t first = pause.after < sent.size() ? pause.after : sent.size();
    client::LinkError error;
    bool went = session_.send_on_wire(sent.first(first), error);
    if (went && first < sent.size()) {
        std::this_thread::sleep_for(pause.silence);
        went = session_.send_on_wire(sent.subspan(first), error);
    }
    if (!went) {
        answer.exchange.status = client::ReceiveStatus::Closed;
        answer.exchange.detail = error.message;
        return answer;
    }
    const auto asked_at = std::chrono::steady_clock::now();
    auto got = session_.receive_from_wire(wait);
    answer.response = std::chrono::duration_cast<std::chrono::microseconds>(
        std::chrono::steady_clock::now() - asked_at);
    answer.largest_gap = got.largest_gap;
    answer.exchange.status = got.status;
    answer.exchange.received = std::move(got.bytes);
    answer.exchange.detail = got.violation.empty() ? std::move(got.detail) : got.violation;
    answer.exchange.discarded = got.discarded;
    answer.exchange.on_connection = session_.connection_requests();
    if (got.status == client::ReceiveStatus::Frame) {
        answer.address = got.header.unit;
        answer.pdu = std::move(got.pdu);
    }
    return answer;
}

LineAnswer LineProbe::ask(std::uint8_t address, std::span<const std::uint8_t> pdu, Spoil spoil) {
    return ask(frame(address, pdu, spoil), timeout());
}

std::vector<std::uint8_t> LineProbe::write_request(std::uint16_t value) const {
    return {kWriteSingle, static_cast<std::uint8_t>(register_ >> 8),
            static_cast<std::uint8_t>(register_), static_cast<std::uint8_t>(value >> 8),
            static_cast<std::uint8_t>(value)};
}

std::optional<std::uint16_t> LineProbe::read_register(std::string& failure, Exchange& failed) {
    auto answer = ask(own_, read_holding(register_));
    const auto& pdu = answer.pdu;
    if (answer.frame() && answer.address == own_ && pdu.size() == 4 && pdu[0] == kReadHolding &&
        pdu[1] == 2) {
        return static_cast<std::uint16_t>(pdu[2] << 8 | pdu[3]);
    }
    failure = fmt::format("FC 03 of register {:04X} at address {}: {}", register_, own_,
                          what_came(answer));
    failed = std::move(answer.exchange);
    return std::nullopt;
}

std::string LineProbe::what_came(const LineAnswer& answer) const {
    const Exchange& got = answer.exchange;
    const auto sent_to = [&] {
        if (got.sent.empty()) return std::string();
        // The address is the first byte on RTU, the two hex digits after ':' on ASCII.
        if (!ascii()) return fmt::format(" from address {}", got.sent[0]);
        return got.sent.size() > 2
                   ? fmt::format(" from address {:c}{:c} (hex)", static_cast<char>(got.sent[1]),
                                 static_cast<char>(got.sent[2]))
                   : std::string();
    };
    switch (got.status) {
        case client::ReceiveStatus::Timeout:
            if (got.received.empty()) {
                return fmt::format("no answer{}: timeout after {} ms", sent_to(),
                                   got.waited.count());
            }
            return fmt::format("an unfinished answer ({} bytes): timeout after {} ms",
                               got.received.size(), got.waited.count());
        case client::ReceiveStatus::Closed:
            return fmt::format("no answer{}: {}", sent_to(), got.detail);
        case client::ReceiveStatus::Malformed:
            return fmt::format("a malformed answer ({})", got.detail);
        case client::ReceiveStatus::Frame:
            break;
    }
    if (!got.detail.empty()) return fmt::format("a malformed answer ({})", got.detail);
    if (answer.address != own_) {
        return fmt::format("an answer carrying address {} where the device's is {}", answer.address,
                           own_);
    }
    if (answer.pdu.size() == 2 && (answer.pdu[0] & protocol::kExceptionBit) != 0) {
        const auto code = static_cast<protocol::ExceptionCode>(answer.pdu[1]);
        return fmt::format("exception {:02X} ({})", answer.pdu[1], protocol::exception_name(code));
    }
    return fmt::format("an unexpected answer, PDU {}", client::hex_bytes(answer.pdu));
}

Outcome line_failure(Session& session, std::string reason, const Exchange& evidence) {
    session.close();
    return Outcome{Verdict::Fail, std::move(reason), {evidence}};
}

}  // namespace mblab::conformance
