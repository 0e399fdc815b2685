#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <thread>
#include <vector>

#include "conformance/catalogue.hpp"
#include "conformance/procedures.hpp"
#include "conformance/serial_line_cases.hpp"
#include "conformance/serial_line_probe.hpp"
#include "conformance/session.hpp"
#include "transport/serial_port.hpp"

// The serial suite's timing cases: silence delimits RTU frames [SER 2.5.1.1] and may sit
// between ASCII characters for up to a second [SER 2.5.2.1]. The tester makes silences by
// waiting between writes and measures them between reads, so what it sees of the line's timing
// is bounded by the port: a pty passes bytes on as written (the timing is logical), and a USB
// adapter hands them over in bursts at its latency timer. Each verdict states that budget.
namespace mblab::conformance {

namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;

constexpr std::uint8_t kReadHolding = 0x03;
constexpr std::uint16_t kFlip = 0xFFFF;
// [SER 2.5.2.1]: up to one second may pass between the characters of an ASCII frame.
constexpr milliseconds kAsciiCharTimeout{1000};

// What the tester can tell of the line's timing through this port.
struct LineTiming {
    transport::CharTimes times{};
    unsigned baud = 0;
    bool pty = false;
    bool paced = false;      // the tester sends at the baud rate (pace=1)
    milliseconds budget{0};  // added to every measured silence by the port and the scheduler

    std::string words(bool ascii) const {
        const auto t =
            ascii ? fmt::format("{} baud", baud)
                  : fmt::format("t1.5 = {:.2f} ms and t3.5 = {:.2f} ms at {} baud",
                                times.t15.count() / 1000.0, times.t35.count() / 1000.0, baud);
        if (pty && paced) {
            return fmt::format(
                "{}; over a pty the tester sends at the baud rate (pace=1) and sees the "
                "device's bytes as it writes them, measured to within {} ms",
                t, budget.count());
        }
        if (pty) {
            return fmt::format(
                "{}; over a pty the timing is logical (a pty does not pace bytes at the baud "
                "rate), measured to within {} ms",
                t, budget.count());
        }
        return fmt::format(
            "{}; through this port each silence is measured to within {} ms (an adapter's "
            "latency timer; declare `latency_ms` for yours)",
            t, budget.count());
    }
};

LineTiming line_timing(const Session& session, const Case& c) {
    LineTiming out;
    const auto& line = session.target().serial->line;
    out.baud = line.baud;
    out.times = transport::rtu_char_times(line.baud);
    out.pty = transport::is_pseudo_terminal(line.device);
    out.paced = session.target().serial->paced;
    out.budget = milliseconds(param(c, out.pty ? "pty_latency_ms" : "latency_ms"));
    return out;
}

double ms(microseconds value) {
    return static_cast<double>(value.count()) / 1000.0;
}

Outcome rtu_broken_request(Session& session, const Case& c, LineProbe& line,
                           const LineTiming& timing) {
    std::string failure;
    Exchange evidence;
    const auto before = line.read_register(failure, evidence);
    if (!before) return line_failure(session, failure, evidence);
    const auto silence = milliseconds(param(c, "silence_ms"));
    // After the address, the function code and the register: the rest would still pass the CRC
    // if the device joined the parts.
    const RequestPause pause{4, silence};
    const auto what =
        fmt::format("FC 06 broken by a {} ms silence after its 4th byte", silence.count());
    const auto write = line.write_request(static_cast<std::uint16_t>(*before ^ kFlip));
    const auto answer = line.ask(line.frame(line.own(), write), line.timeout(), pause);
    if (!answer.silent()) {
        return line_failure(
            session,
            fmt::format("{} was answered ({}): a silence over t1.5 inside a frame makes it "
                        "incomplete and it must be discarded [SER 2.5.1.1]; {}",
                        what, line.what_came(answer), timing.words(line.ascii())),
            answer.exchange);
    }
    const auto after = line.read_register(failure, evidence);
    if (!after) return line_failure(session, "after the broken frame: " + failure, evidence);
    if (*after != *before) {
        return line_failure(session,
                            fmt::format("{} was executed: register {:04X} went from {:04X} to "
                                        "{:04X} [SER 2.5.1.1]",
                                        what, line.register_address(), *before, *after),
                            answer.exchange);
    }
    return Outcome{Verdict::Pass,
                   fmt::format("{} was neither answered nor executed, and the device answered "
                               "the next read; {}",
                               what, timing.words(line.ascii())),
                   {}};
}

Outcome ascii_paused_request(Session& session, const Case& c, LineProbe& line) {
    const auto silence = std::min(milliseconds(param(c, "ascii_pause_ms")), kAsciiCharTimeout);
    // After ':' and the address: the device must wait for the rest.
    const RequestPause pause{3, silence};
    const auto wire = line.frame(line.own(), read_holding(line.register_address()));
    const auto answer = line.ask(wire, line.timeout(), pause);
    const auto what = fmt::format("FC 03 with a {} ms pause after its address", silence.count());
    if (!answer.frame() || answer.address != line.own() || answer.pdu.empty() ||
        answer.pdu[0] != kReadHolding) {
        return line_failure(session,
                            fmt::format("{}: {}; up to 1 s may pass between the characters of "
                                        "an ASCII frame [SER 2.5.2.1]",
                                        what, line.what_came(answer)),
                            answer.exchange);
    }
    return Outcome{Verdict::Pass,
                   fmt::format("{} was answered (up to 1 s is allowed between characters)", what),
                   {}};
}

// The value at quantile q of sorted `values`.
microseconds quantile(const std::vector<microseconds>& sorted, double q) {
    const auto at = static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1) + 0.5);
    return sorted[std::min(at, sorted.size() - 1)];
}

// The timing cases, on a serial port only (`requires =
// ["serial_port"]`): over RTU over TCP frames are cut by their length.
// RTU: FC 06 broken by a silence over t1.5 is neither answered nor executed [SER 2.5.1.1].
// ASCII: FC 03 with a pause under 1 s between its characters is answered [SER 2.5.2.1].
Outcome run_broken_request(Session& session, const Case& c) {
    LineProbe line(session, c);
    if (line.ascii()) return ascii_paused_request(session, c, line);
    return rtu_broken_request(session, c, line, line_timing(session, c));
}

// FC 03 reads, each sent t3.5 after the last answer, are all answered, with no silence over t1.5
// inside an answer; the response times are reported against the timeout [SER 2.5.1.1, 2.4.1].
Outcome run_answer_timing(Session& session, const Case& c) {
    LineProbe line(session, c);
    const LineTiming timing = line_timing(session, c);
    const auto declared = session.dut().registers;
    // A long answer shows gaps best: the declared registers from 0, else one at `register`.
    const std::uint16_t count =
        declared
            ? static_cast<std::uint16_t>(std::min<std::uint32_t>(*declared, session.dut().max_read))
            : 1;
    const std::uint16_t address = declared ? 0 : line.register_address();
    const auto reads = static_cast<std::size_t>(std::max<std::int64_t>(1, param(c, "count")));
    // The master may send the next request once t3.5 has passed after the answer [SER 2.5.1.1].
    const auto pause = line.ascii() ? microseconds(0) : timing.times.t35;
    const auto allowed = line.ascii() ? microseconds(kAsciiCharTimeout) : timing.times.t15;
    const auto limit = allowed + microseconds(timing.budget);

    std::vector<microseconds> responses;
    microseconds widest{0};
    for (std::size_t i = 0; i < reads; ++i) {
        if (i > 0) std::this_thread::sleep_for(pause);
        const auto answer = line.ask(line.own(), read_holding(address, count));
        const auto what =
            fmt::format("read {} of {} (FC 03 of {} registers at {:04X}{})", i + 1, reads, count,
                        address, i > 0 && !line.ascii() ? ", sent t3.5 after the last answer" : "");
        if (!answer.frame() || !answer.exchange.detail.empty() || answer.address != line.own() ||
            answer.pdu.empty() || answer.pdu[0] != kReadHolding) {
            return line_failure(session, fmt::format("{}: {}", what, line.what_came(answer)),
                                answer.exchange);
        }
        if (answer.largest_gap > limit) {
            return line_failure(
                session,
                fmt::format("{}: a silence of {:.2f} ms inside the answer; at most {} may pass "
                            "between its characters [{}]; {}",
                            what, ms(answer.largest_gap),
                            line.ascii() ? std::string("1 s")
                                         : fmt::format("t1.5 ({:.2f} ms)", ms(timing.times.t15)),
                            line.ascii() ? "SER 2.5.2.1" : "SER 2.5.1.1",
                            timing.words(line.ascii())),
                answer.exchange);
        }
        widest = std::max(widest, answer.largest_gap);
        responses.push_back(answer.response);
    }
    std::sort(responses.begin(), responses.end());
    return Outcome{
        Verdict::Pass,
        fmt::format("{} reads answered{}: response time median {:.1f} ms, 90th percentile "
                    "{:.1f} ms, longest {:.1f} ms, against a timeout of {} ms; longest silence "
                    "inside an answer {:.2f} ms; {}",
                    reads, line.ascii() ? "" : ", each sent t3.5 after the last answer",
                    ms(quantile(responses, 0.5)), ms(quantile(responses, 0.9)),
                    ms(responses.back()), line.timeout().count(), ms(widest),
                    timing.words(line.ascii())),
        {}};
}

}  // namespace

std::vector<ProcedureInfo> line_timing_procedures() {
    return {
        modbus_procedure(
            "broken_request",
            "RTU: FC 06 broken by a silence over t1.5 is neither answered nor executed; ASCII: FC "
            "03 with a pause under 1 s between its characters is answered (SER 2.5.1.1, 2.5.2.1)",
            &run_broken_request,
            {{"register", 0x0010},
             {"silence_ms", 50},
             {"ascii_pause_ms", 300},
             {"latency_ms", 16},
             {"pty_latency_ms", 2}}),
        modbus_procedure(
            "answer_timing",
            "FC 03 reads, each sent t3.5 after the last answer, all answered with no silence over "
            "t1.5 inside an answer; response times reported against the timeout (SER 2.5.1.1, "
            "2.4.1)",
            &run_answer_timing,
            {{"register", 0x0010}, {"count", 10}, {"latency_ms", 16}, {"pty_latency_ms", 2}}),
    };
}

}  // namespace mblab::conformance
