#include "robustness/scan_report.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>

namespace mblab::robustness {

namespace {

struct TableKey {
    const char* key;  // the DUT key counting the table's addresses from 0
    const char* read;
};

constexpr std::array<TableKey, kTableCount> kTableKeys{{{"coils", "FC 01"},
                                                        {"discrete_inputs", "FC 02"},
                                                        {"registers", "FC 03"},
                                                        {"input_registers", "FC 04"}}};

std::string codes_text(const std::vector<std::uint8_t>& codes) {
    if (codes.empty()) return "none";
    std::string out;
    for (auto code : codes)
        out += fmt::format("{}{:02X}", out.empty() ? "" : " ", code);
    return out;
}

bool unanswered(const Recon& recon, std::uint8_t function) {
    return std::find(recon.silent.begin(), recon.silent.end(), function) != recon.silent.end();
}

LearnedFact table_fact(const DeviceScan& scan, std::size_t i) {
    const auto& [key, read] = kTableKeys[i];
    const auto function = static_cast<std::uint8_t>(i + 1);
    const auto& range = scan.tables[i];
    if (!range) {
        if (!scan.recon.serves(function)) {
            return {key, "",
                    fmt::format("{} {}", read,
                                unanswered(scan.recon, function) ? "got no answer"
                                                                 : "is not served (exception 01)")};
        }
        return {key, "", fmt::format("{} answered no read at 0, 1, 100, 1000 or 40000", read)};
    }
    const std::string span = fmt::format("{} answered {}..{}", read, range->first, range->last);
    if (range->first != 0) {
        return {key, "",
                span +
                    ", not from 0 (the key counts from 0; check the device's manual for "
                    "where its map starts)"};
    }
    return {key, std::to_string(std::uint32_t{range->last} + 1),
            span + ", each address read once in whole reads"};
}

LearnedFact max_read_fact(const DeviceScan& scan) {
    const Recon& recon = scan.recon;
    if (!scan.recon_failure.empty()) return {"max_read", "", "no holding register answered FC 03"};
    const std::string at = fmt::format("at {}", recon.check_address);
    if (recon.max_read == 125) {
        return {"max_read", "125",
                fmt::format("FC 03 of 125 registers (the most [APP] 6.3 allows) answered {}", at)};
    }
    const auto& holding = scan.tables[static_cast<std::size_t>(Table::HoldingRegisters)];
    // A read one longer would pass the last register: the map's end, not the device's limit.
    const bool map_end =
        holding && std::uint32_t{recon.check_address} + recon.max_read - 1 == holding->last;
    return {"max_read", std::to_string(recon.max_read),
            fmt::format("FC 03 of {} registers answered {}, of {} did not{}", recon.max_read, at,
                        recon.max_read + 1,
                        map_end ? " (it would pass the last register: the device's own limit "
                                  "may be higher)"
                                : "")};
}

LearnedFact echo_fact(const DeviceScan& scan) {
    const EchoScan& echo = scan.echo;
    if (!echo.asked) {
        return {"echo_max_words", "",
                unanswered(scan.recon, 0x08) ? "FC 08 got no answer"
                                             : "FC 08 is not served (exception 01)"};
    }
    if (echo.echoed == 0) return {"echo_max_words", "", "FC 08/00 echoed no data word"};
    const std::string echoed =
        fmt::format("FC 08/00 echoed {} data word{}", echo.echoed, echo.echoed == 1 ? "" : "s");
    if (echo.echoed == kMaxEchoWords) {
        return {"echo_max_words", "",
                echoed +
                    ", as many as a PDU holds: the device sets no limit of its own (INSTR "
                    "5.7.1 asks for 100)"};
    }
    if (echo.refusal) {
        return {"echo_max_words", std::to_string(echo.echoed),
                fmt::format("{}; {} answered exception {:02X}", echoed, echo.echoed + 1,
                            *echo.refusal)};
    }
    return {
        "echo_max_words", "",
        fmt::format("{}; {} got {} where INSTR 5.7.1 expects exception 03: no limit to "
                    "declare",
                    echoed, echo.echoed + 1, echo.data_refused ? "another answer" : "no answer")};
}

std::vector<std::string> seen_lines(const DeviceScan& scan) {
    std::vector<std::string> lines;
    lines.push_back(fmt::format("units tried: {}; answering FC 03: {}; scanned: {}",
                                units_text(scan.tried, ", "), units_text(scan.answering, ", "),
                                scan.recon.unit));
    lines.push_back(fmt::format("function codes served: {}", codes_text(scan.recon.served)));
    lines.push_back(
        fmt::format("answered exception 01 (not served): {}", codes_text(scan.recon.not_served)));
    lines.push_back(fmt::format("no answer: {}", codes_text(scan.recon.silent)));
    lines.push_back(fmt::format("not asked (they write): {}", codes_text(scan.recon.not_asked)));
    lines.push_back(
        fmt::format("device identification (FC 2B/0E): {}", identity_text(scan.identity)));
    return lines;
}

constexpr std::string_view kNeedsWrites =
    "read_only_register, read_only_coil, fifo_count_writable: finding them takes a write, and "
    "mblab scan writes nothing";
constexpr std::string_view kSecurity =
    "pki, client_cert, client_key, ca, read_only_role, write_role, null_role_granted: the "
    "security suite's, declared by hand (docs/security.md)";
constexpr std::string_view kLine =
    "other_address, turnaround_ms: what the rest of a serial line uses, known to its owner";

}  // namespace

std::vector<LearnedFact> learned_facts(const DeviceScan& scan) {
    std::vector<LearnedFact> facts;
    const std::size_t answering = scan.answering.size();
    facts.push_back({"unit", std::to_string(scan.recon.unit),
                     answering == 1 ? std::string("the only unit that answered FC 03")
                                    : fmt::format("{} of the {} units that answered FC 03",
                                                  scan.recon.unit, answering)});
    facts.push_back(table_fact(scan, static_cast<std::size_t>(Table::HoldingRegisters)));
    facts.push_back(max_read_fact(scan));
    for (auto table : {Table::Coils, Table::DiscreteInputs, Table::InputRegisters})
        facts.push_back(table_fact(scan, static_cast<std::size_t>(table)));
    if (scan.object_messaging) {
        facts.push_back({"object_messaging", "true",
                         "FC 5B get attribute (class 1, instance 1, attribute 1) was answered"});
    } else {
        facts.push_back({"object_messaging", "",
                         fmt::format("FC 5B get attribute (CTP 7.13.1's request) {}",
                                     scan.object_messaging_silent ? "got no answer"
                                                                  : "answered exception 01")});
    }
    if (scan.semi_signature) {
        facts.push_back({"alternate_encoding", "true",
                         fmt::format("SEMI signature 5345 4D49 5F72 at holding register {}",
                                     *scan.semi_signature)});
    } else {
        facts.push_back(
            {"alternate_encoding", "", "no SEMI signature in the holding registers read"});
    }
    facts.push_back(echo_fact(scan));
    if (scan.file_number) {
        facts.push_back({"file_number", std::to_string(*scan.file_number),
                         "FC 14 of file 1, record 0 answered data"});
    } else {
        facts.push_back({"file_number", "", "FC 14 of file 1, record 0 answered no data"});
    }
    if (scan.fifo_address) {
        facts.push_back({"fifo_address", std::to_string(*scan.fifo_address),
                         "FC 18 at 0 answered a FIFO queue"});
    } else {
        facts.push_back({"fifo_address", "",
                         "FC 18 at 0 answered no FIFO queue (other addresses are not tried)"});
    }
    return facts;
}

std::string scan_dut_toml(const DeviceScan& scan, const ScanOrigin& origin) {
    std::string out = fmt::format(
        "# Declarations of the device at {}, learned by mblab scan {} at {}.\n"
        "# Each value was learned from the device's answers, not its documentation: check them\n"
        "# against its manual, then: {} --dut FILE\n#\n",
        origin.target, origin.version, origin.started,
        conformance::shell_words({"mblab", "conform", origin.target}));
    for (const auto& line : seen_lines(scan))
        out += "# " + line + "\n";
    out += "\n";
    for (const auto& fact : learned_facts(scan)) {
        if (!fact.value.empty()) {
            out += fmt::format("{} = {}  # learned by mblab scan: {}\n", fact.key, fact.value,
                               fact.why);
        }
    }
    out += "\n# Not declared:\n";
    for (const auto& fact : learned_facts(scan)) {
        if (fact.value.empty()) out += fmt::format("# {}: {}\n", fact.key, fact.why);
    }
    out += fmt::format("# {}\n# {}\n# {}\n", kNeedsWrites, kSecurity, kLine);
    return out;
}

std::string scan_text(const DeviceScan& scan) {
    std::string out;
    for (const auto& line : seen_lines(scan))
        out += line + "\n";
    const auto facts = learned_facts(scan);
    std::size_t width = 0;
    for (const auto& fact : facts)
        width = std::max(width, fact.key.size() + 3 + std::max<std::size_t>(fact.value.size(), 1));
    for (const auto& fact : facts) {
        const std::string declared =
            fmt::format("{} {}", fact.key, fact.value.empty() ? "-" : "= " + fact.value);
        out += fmt::format("  {:<{}}  {}\n", declared, width, fact.why);
    }
    out += fmt::format("{} requests, none of them a write\n", scan.requests);
    return out;
}

}  // namespace mblab::robustness
