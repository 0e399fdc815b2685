#include "conformance/evidence_text.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "conformance/line_evidence.hpp"

namespace mblab::conformance {

namespace {

std::string received_text(const Exchange& exchange) {
    std::string bytes = frame_text(exchange.framing, exchange.received);
    std::string why;
    switch (exchange.status) {
        case client::ReceiveStatus::Frame:
            return bytes;
        case client::ReceiveStatus::Timeout:
            if (exchange.silence_expected) return bytes.empty() ? "nothing" : bytes;
            why = fmt::format("timeout after {} ms", exchange.waited.count());
            break;
        case client::ReceiveStatus::Closed:
            why = exchange.detail;
            break;
        case client::ReceiveStatus::Malformed:
            why = exchange.detail;
            break;
    }
    return bytes.empty() ? why : fmt::format("{}  ({})", bytes, why);
}

std::string marks(const Exchange& exchange) {
    std::string line;
    for (std::size_t position : exchange.match.differs) {
        const std::size_t column = frame_column(exchange.framing, position);
        if (line.size() < column + 2) line.resize(column + 2, ' ');
        line[column] = '^';
        line[column + 1] = '^';
    }
    return line;
}

}  // namespace

std::vector<std::string> evidence_lines(const Exchange& exchange) {
    std::vector<std::string> lines;
    lines.push_back("sent      " + frame_text(exchange.framing, exchange.sent));
    lines.push_back("received  " + received_text(exchange));
    if (exchange.silence_expected) {
        lines.emplace_back("expected  nothing");
        return lines;
    }
    lines.push_back("expected  " + expected_text(exchange));
    // Only a received frame can be compared byte by byte.
    if (!exchange.received.empty() && !exchange.match.differs.empty()) {
        lines.push_back("          " + marks(exchange));
    }
    return lines;
}

std::string format_duration(std::chrono::microseconds elapsed) {
    const double seconds = static_cast<double>(elapsed.count()) / 1e6;
    if (seconds >= 0.1) return fmt::format("{:.2f} s", seconds);
    return fmt::format("{:.1f} ms", seconds * 1e3);
}

std::string describe_dut(const Dut& dut) {
    auto yes_no = [](bool value) { return value ? "yes" : "no"; };
    std::string registers =
        dut.registers ? fmt::format("{} registers", *dut.registers) : "registers not declared";
    return fmt::format("unit {}, {}, max read {}, object messaging: {}, alternate encoding: {}",
                       dut.unit, registers, dut.max_read, yes_no(dut.object_messaging),
                       yes_no(dut.alternate_encoding));
}

}  // namespace mblab::conformance
