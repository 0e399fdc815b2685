#include <nlohmann/json.hpp>
#include <variant>

#include "conformance/line_evidence.hpp"
#include "conformance/reports.hpp"
#include "protocol/adu.hpp"
#include "support/json_document.hpp"
#include "support/name_table.hpp"

namespace mblab::conformance {

namespace {

using nlohmann::json;

std::string_view status_name(client::ReceiveStatus status) {
    static constexpr Named<client::ReceiveStatus> kNames[] = {
        {client::ReceiveStatus::Frame, "frame"},
        {client::ReceiveStatus::Timeout, "timeout"},
        {client::ReceiveStatus::Closed, "closed"},
        {client::ReceiveStatus::Malformed, "malformed"}};
    return name_of(kNames, status, "unknown");
}

double millis(std::chrono::microseconds elapsed) {
    return static_cast<double>(elapsed.count()) / 1000.0;
}

// On a line `sent` and `received` are the frames as it carried them (line_evidence.hpp), and
// "framing" says which: "RTU" or "ASCII".
json exchange_json(const Exchange& exchange) {
    json out = {{"sent", frame_text(exchange.framing, exchange.sent)},
                {"status", status_name(exchange.status)},
                {"received", frame_text(exchange.framing, exchange.received)},
                {"waited_ms", exchange.waited.count()}};
    if (exchange.framing != client::Framing::Mbap)
        out["framing"] = protocol::framing_name(exchange.framing);
    if (!exchange.detail.empty()) out["detail"] = exchange.detail;
    if (exchange.silence_expected) {
        out["expected"] = nullptr;
    } else {
        out["expected"] = exchange.expected;
        out["differs"] = exchange.match.differs;
    }
    return out;
}

json dut_json(const Dut& dut) {
    json out = {{"unit", dut.unit},
                {"max_read", dut.max_read},
                {"object_messaging", dut.object_messaging},
                {"alternate_encoding", dut.alternate_encoding},
                {"declared_by", dut.declared_by}};
    auto optional = [&](const char* key, const auto& value) {
        if (value) out[key] = *value;
    };
    optional("registers", dut.registers);
    optional("coils", dut.coils);
    optional("discrete_inputs", dut.discrete_inputs);
    optional("input_registers", dut.input_registers);
    optional("read_only_register", dut.read_only_register);
    optional("read_only_coil", dut.read_only_coil);
    optional("fifo_address", dut.fifo_address);
    optional("file_number", dut.file_number);
    optional("echo_max_words", dut.echo_max_words);
    optional("other_address", dut.other_address);
    optional("turnaround_ms", dut.turnaround_ms);
    if (!dut.line_settings.empty()) out["line_settings"] = dut.line_settings;
    return out;
}

json counts_json(const Counts& counts) {
    return {{"passed", counts.passed},
            {"failed", counts.failed},
            {"not_applicable", counts.not_applicable},
            {"not_run", counts.not_run},
            {"total", counts.total()}};
}

json provenance_json(const Provenance& provenance) {
    json declarations = json::array();
    for (const auto& declaration : provenance.declarations) {
        json value;
        std::visit([&](const auto& held) { value = held; }, declaration.value);
        declarations.push_back(
            {{"key", declaration.key}, {"value", value}, {"source", declaration.source}});
    }
    const DeviceIdentity& device = provenance.device;
    json identity = {{"status", device.answered ? "answered" : "not answered"}};
    if (device.answered) {
        identity["vendor_name"] = device.vendor_name;
        identity["product_code"] = device.product_code;
        identity["revision"] = device.revision;
    } else {
        identity["reason"] = device.reason;
    }
    return {{"mblab_version", provenance.version},
            {"git_commit", provenance.commit},
            {"started", provenance.started},
            {"finished", provenance.finished},
            {"command_line", provenance.command_line},
            {"declared_by", provenance.declared_by},
            {"declarations", declarations},
            {"device_identity", identity}};
}

json run_json(const RunResult& result) {
    json suites = json::array();
    for (const auto& suite : result.suites) {
        json cases = json::array();
        for (const auto& c : suite.cases) {
            json evidence = json::array();
            for (const auto& exchange : c.outcome.evidence)
                evidence.push_back(exchange_json(exchange));
            cases.push_back({{"id", c.id},
                             {"source", c.source},
                             {"title", c.title},
                             {"verdict", verdict_label(c.outcome.verdict)},
                             {"reason", c.outcome.reason},
                             {"elapsed_ms", millis(c.elapsed)},
                             {"requests", c.requests},
                             {"evidence", evidence}});
        }
        suites.push_back({{"name", suite.name},
                          {"title", suite.title},
                          {"file", suite.file},
                          {"summary", counts_json(count(suite))},
                          {"cases", cases}});
    }
    return {{"tool", "mblab conform"},
            {"target", result.target},
            {"dut", dut_json(result.dut)},
            {"passed", result.all_passed() && !result.interrupted},
            {"interrupted", result.interrupted},
            {"summary", counts_json(result.counts())},
            {"elapsed_ms", millis(result.elapsed)},
            {"requests", result.requests},
            {"suites", suites}};
}

}  // namespace

std::string json_report(const RunResult& result, const Provenance& provenance) {
    json report = run_json(result);
    report["provenance"] = provenance_json(provenance);
    return json_document(report) + "\n";
}

std::string json_report(const RunResult& result) {
    return json_document(run_json(result)) + "\n";
}

}  // namespace mblab::conformance
