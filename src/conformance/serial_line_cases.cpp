#include "conformance/serial_line_cases.hpp"

#include <fmt/core.h>

#include <array>

#include "client/hex_text.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/procedures.hpp"
#include "conformance/serial_line_probe.hpp"
#include "conformance/session.hpp"
#include "protocol/crc16.hpp"

// The rules that make a multi-drop line work ([SER 2.2], [SER 2.4], [SER 2.5]): who answers
// what, what a broadcast does, what a spoiled frame does. Each case asks on the line in its own
// framing and judges the bytes that came back.
namespace mblab::conformance {

namespace {

constexpr std::uint8_t kBroadcast = 0;
constexpr std::uint8_t kDiagnostics = 0x08;
constexpr std::uint8_t kBusErrorCount = 0x0C;  // [APP 6.8.1] sub-function 0C
// A value that differs from the one read in every bit, so its effect cannot go unseen.
constexpr std::uint16_t kFlip = 0xFFFF;

Outcome pass(std::string remark) {
    return Outcome{Verdict::Pass, std::move(remark), {}};
}

// After a request nobody was to execute: the register still holds `before`.
std::optional<Outcome> unchanged(Session& session, LineProbe& line, std::uint16_t before,
                                 const Exchange& request, std::string_view what) {
    std::string failure;
    Exchange failed;
    const auto after = line.read_register(failure, failed);
    if (!after) return line_failure(session, "read back: " + failure, failed);
    if (*after == before) return std::nullopt;
    return line_failure(session,
                        fmt::format("{} was executed: register {:04X} went from {:04X} to {:04X}",
                                    what, line.register_address(), before, *after),
                        request);
}

// The answer nobody was to send, in words.
Outcome answered(Session& session, const LineProbe& line, const LineAnswer& answer,
                 std::string_view what) {
    return line_failure(session, fmt::format("{} was answered: {}", what, line.what_came(answer)),
                        answer.exchange);
}

// FC 08 sub-function 0C, when the device serves it.
std::optional<std::uint16_t> bus_error_count(LineProbe& line) {
    const std::array<std::uint8_t, 5> ask{kDiagnostics, 0x00, kBusErrorCount, 0x00, 0x00};
    const auto answer = line.ask(line.own(), ask);
    const auto& pdu = answer.pdu;
    if (!answer.frame() || !answer.exchange.detail.empty() || answer.address != line.own() ||
        pdu.size() != 5 || pdu[0] != kDiagnostics || pdu[2] != kBusErrorCount) {
        return std::nullopt;
    }
    return static_cast<std::uint16_t>(pdu[3] << 8 | pdu[4]);
}

// The register's value before a case writes to it; the failure when it cannot be read.
std::optional<std::uint16_t> value_before(LineProbe& line, Outcome& failed, Session& session) {
    std::string failure;
    Exchange evidence;
    auto value = line.read_register(failure, evidence);
    if (!value) failed = line_failure(session, failure, evidence);
    return value;
}

// What is wrong with the answer as it crossed the line, for the RTU framing.
std::optional<std::string> rtu_layout_fault(const LineAnswer& answer) {
    const auto& bytes = answer.exchange.received;
    if (answer.exchange.status != client::ReceiveStatus::Malformed || bytes.size() < 4)
        return std::nullopt;
    const auto crc = protocol::crc16(std::span(bytes).first(bytes.size() - 2));
    if (bytes[bytes.size() - 2] == (crc >> 8) && bytes.back() == (crc & 0xFF)) {
        return fmt::format(
            "the CRC {:04X} is sent high byte first; [SER 2.5.1.2] sends its low "
            "byte first",
            crc);
    }
    return std::nullopt;
}

// FC 03 to another address is not answered [SER 2.2].
Outcome run_other_address_read(Session& session, const Case& c) {
    LineProbe line(session, c);
    const auto answer = line.ask(line.other(), read_holding(line.register_address()));
    if (!answer.silent()) {
        return answered(
            session, line, answer,
            fmt::format("FC 03 to address {} (not the device's {})", line.other(), line.own()));
    }
    return pass(fmt::format("FC 03 to address {} went unanswered for {} ms", line.other(),
                            line.timeout().count()));
}

// FC 06 to another address is neither answered nor executed [SER 2.2].
Outcome run_other_address_write(Session& session, const Case& c) {
    LineProbe line(session, c);
    Outcome failed;
    const auto before = value_before(line, failed, session);
    if (!before) return failed;
    const auto write = line.write_request(static_cast<std::uint16_t>(*before ^ kFlip));
    const auto what =
        fmt::format("FC 06 to address {} (not the device's {})", line.other(), line.own());
    const auto answer = line.ask(line.other(), write);
    if (!answer.silent()) return answered(session, line, answer, what);
    if (auto executed = unchanged(session, line, *before, answer.exchange, what)) return *executed;
    return pass(fmt::format("{} went unanswered and register {:04X} kept {:04X}", what,
                            line.register_address(), *before));
}

// FC 06 to address 0 is executed, not answered, and the device answers again once the declared
// turnaround delay is over [SER 2.2, 2.4.1].
Outcome run_broadcast_write(Session& session, const Case& c) {
    LineProbe line(session, c);
    Outcome failed;
    const auto before = value_before(line, failed, session);
    if (!before) return failed;
    // The register must take a unicast write, or a broadcast one says nothing.
    const auto same = line.ask(line.own(), line.write_request(*before));
    if (!same.frame() || same.pdu != line.write_request(*before) || same.address != line.own()) {
        session.close();
        return Outcome{Verdict::NotApplicable,
                       fmt::format("register {:04X} does not take FC 06 at address {} ({}); "
                                   "declare a writable one as the case's `register`",
                                   line.register_address(), line.own(), line.what_came(same)),
                       {}};
    }
    const auto value = static_cast<std::uint16_t>(*before ^ kFlip);
    const auto turnaround = std::chrono::milliseconds(session.dut().turnaround_ms.value_or(
        static_cast<std::uint32_t>(param(c, "turnaround_ms"))));
    const auto broadcast = line.ask(line.frame(kBroadcast, line.write_request(value)), turnaround);
    if (!broadcast.silent()) return answered(session, line, broadcast, "FC 06 to address 0");
    // [SER 2.4.1]: once the turnaround delay is over the master may ask again.
    std::string failure;
    Exchange evidence;
    const auto after = line.read_register(failure, evidence);
    if (!after) {
        return line_failure(
            session, fmt::format("{} ms after the broadcast: {}", turnaround.count(), failure),
            evidence);
    }
    // The value is put back either way, so later cases meet the register as it was.
    const auto restore = line.ask(line.own(), line.write_request(*before));
    if (*after != value) {
        return line_failure(session,
                            fmt::format("FC 06 to address 0 was not executed: register {:04X} "
                                        "holds {:04X}, not the {:04X} broadcast",
                                        line.register_address(), *after, value),
                            broadcast.exchange);
    }
    if (!restore.frame()) {
        return line_failure(session, "restoring the register: " + line.what_came(restore),
                            restore.exchange);
    }
    return pass(fmt::format("executed, unanswered, and the device answered {} ms later",
                            turnaround.count()));
}

// A read (`function` 3) or FC 08 (`function` 8) to address 0 is never answered [SER 2.2].
Outcome run_broadcast_unanswered(Session& session, const Case& c) {
    LineProbe line(session, c);
    const bool diagnostic = param(c, "function") == kDiagnostics;
    const std::array<std::uint8_t, 5> echo{kDiagnostics, 0x00, 0x00, 0xA5, 0x5A};
    const auto request = diagnostic ? echo : read_holding(line.register_address());
    const auto what = diagnostic ? std::string("FC 08 (return query data) to address 0")
                                 : std::string("FC 03 to address 0");
    const auto answer = line.ask(kBroadcast, request);
    if (!answer.silent()) return answered(session, line, answer, what);
    return pass(fmt::format("{} went unanswered for {} ms", what, line.timeout().count()));
}

// A write with a wrong CRC or LRC is neither answered nor executed, and FC 08 sub-function 0C
// counts it where it is served [SER 2.4.2, 2.5.1.2, 2.5.2.2, 6.1].
Outcome run_wrong_checksum(Session& session, const Case& c) {
    LineProbe line(session, c);
    const auto checksum = line.ascii() ? "LRC" : "CRC";
    const auto count_before = bus_error_count(line);
    Outcome failed;
    const auto before = value_before(line, failed, session);
    if (!before) return failed;
    const auto write = line.write_request(static_cast<std::uint16_t>(*before ^ kFlip));
    const auto what = fmt::format("FC 06 with a wrong {}", checksum);
    const auto answer = line.ask(line.own(), write, Spoil::Checksum);
    if (!answer.silent()) return answered(session, line, answer, what);
    if (auto executed = unchanged(session, line, *before, answer.exchange, what)) return *executed;
    if (!count_before) {
        return pass(
            "unanswered and not executed; FC 08 sub-function 0C is not served, so the bus "
            "communication error count was not checked");
    }
    const auto count_after = bus_error_count(line);
    if (!count_after || *count_after != static_cast<std::uint16_t>(*count_before + 1)) {
        return line_failure(
            session,
            fmt::format("unanswered and not executed, but the bus communication error count "
                        "(FC 08 sub-function 0C) went from {} to {}, not {}",
                        *count_before, count_after ? fmt::format("{}", *count_after) : "no answer",
                        *count_before + 1),
            answer.exchange);
    }
    return pass(fmt::format("unanswered, not executed, and counted ({} bus communication errors)",
                            *count_after));
}

// The answer carries the device's own address, its checksum laid out as the framing says, and
// nothing after it [SER 2.5.1, 2.5.2].
Outcome run_answer_frame(Session& session, const Case& c) {
    LineProbe line(session, c);
    const auto answer = line.ask(line.own(), read_holding(line.register_address()));
    if (!line.ascii()) {
        if (auto fault = rtu_layout_fault(answer))
            return line_failure(session, *fault, answer.exchange);
    }
    if (!answer.frame() || !answer.exchange.detail.empty() || answer.address != line.own()) {
        return line_failure(session, "FC 03: " + line.what_came(answer), answer.exchange);
    }
    // Bytes after the frame would be taken for the start of the next one [SER 2.5.1.1].
    const auto after = session.take_unasked(std::max(session.options().settle, line.timeout() / 4));
    if (!after.bytes.empty()) {
        Exchange evidence = answer.exchange;
        evidence.received.insert(evidence.received.end(), after.bytes.begin(), after.bytes.end());
        return line_failure(session,
                            fmt::format("{} bytes followed the answer's frame: {}",
                                        after.bytes.size(), client::hex_bytes(after.bytes)),
                            evidence);
    }
    return pass(line.ascii() ? "':', upper-case hex, LRC and CR LF; the device's own address"
                             : "the device's own address, CRC low byte first, nothing after");
}

// ASCII: a write in lower-case hex is a framing error, neither answered nor executed [SER 2.5.2].
Outcome run_ascii_lower_case(Session& session, const Case& c) {
    LineProbe line(session, c);
    Outcome failed;
    const auto before = value_before(line, failed, session);
    if (!before) return failed;
    // A value whose frame has a letter among its hex digits, or lower case would change nothing.
    std::vector<std::uint8_t> write;
    for (const std::uint16_t mask : {0xABCD, 0xBCDE, 0xCDEF, 0xFEDC}) {
        write = line.write_request(static_cast<std::uint16_t>(*before ^ mask));
        if (line.frame(line.own(), write) != line.frame(line.own(), write, Spoil::LowerCase)) break;
    }
    const auto what = std::string("FC 06 in lower-case hex");
    const auto answer = line.ask(line.own(), write, Spoil::LowerCase);
    if (!answer.silent()) return answered(session, line, answer, what);
    if (auto executed = unchanged(session, line, *before, answer.exchange, what)) return *executed;
    return pass("unanswered and not executed");
}

}  // namespace

std::vector<ProcedureInfo> serial_line_procedures() {
    return {
        modbus_procedure("other_address_read",
                         "FC 03 to another address on the line is not answered (SER 2.2)",
                         &run_other_address_read, {{"register", 0x0010}, {"other_address", 0}}),
        modbus_procedure("other_address_write",
                         "FC 06 to another address is neither answered nor executed: the register "
                         "read back at the device's own address is unchanged (SER 2.2)",
                         &run_other_address_write, {{"register", 0x0010}, {"other_address", 0}}),
        modbus_procedure(
            "broadcast_write",
            "FC 06 to address 0 is executed and not answered; the device answers a read once the "
            "turnaround delay is over, and the value is put back (SER 2.2, 2.4.1)",
            &run_broadcast_write, {{"register", 0x0010}, {"turnaround_ms", 200}}),
        modbus_procedure("broadcast_unanswered",
                         "a request to address 0 (FC 03, or FC 08 with function = 8) is never "
                         "answered (SER 2.2)",
                         &run_broadcast_unanswered, {{"register", 0x0010}, {"function", 3}}),
        modbus_procedure("wrong_checksum",
                         "FC 06 with a wrong CRC (RTU) or LRC (ASCII) is neither answered nor "
                         "executed; FC 08 sub-function 0C counts it where served (SER 2.4.2, 6.1)",
                         &run_wrong_checksum, {{"register", 0x0010}}),
        modbus_procedure(
            "answer_frame",
            "the answer to FC 03 carries the device's own address, its CRC low byte first or ':', "
            "upper-case hex, LRC and CR LF, and nothing after it (SER 2.5.1, 2.5.2)",
            &run_answer_frame, {{"register", 0x0010}}),
        modbus_procedure(
            "ascii_lower_case",
            "ASCII: FC 06 in lower-case hex is neither answered nor executed (SER 2.5.2)",
            &run_ascii_lower_case, {{"register", 0x0010}}),
    };
}

}  // namespace mblab::conformance
