#include "conformance/procedures.hpp"

#include "conformance/catalogue.hpp"
#include "conformance/security_cases.hpp"
#include "conformance/serial_line_cases.hpp"
#include "conformance/sunspec_cases.hpp"
#include "conformance/verdict.hpp"

namespace mblab::conformance {

namespace {

std::vector<ProcedureInfo> with_sunspec(std::vector<ProcedureInfo> list) {
    auto sunspec = sunspec_procedures();
    list.insert(list.end(), sunspec.begin(), sunspec.end());
    return list;
}

}  // namespace

const std::vector<ProcedureInfo>& procedures() {
    static const std::vector<ProcedureInfo> list = with_sunspec({
        {"ping",
         "ICMP echo requests to the device's host; all must be answered (CTP 7.2)",
         {{"count", 10}, {"payload", 32}, {"timeout_ms", 1000}},
         {},
         false,
         &run_ping,
         nullptr},
        {"register_sweep",
         "FC 03 reads of every size from 0, then in maximal blocks, then shrinking to the last "
         "register; checks length field, byte count and register count (CTP 7.5.2)",
         {},
         {"registers"},
         true,
         &run_register_sweep,
         nullptr},
        {"semi_signature_scan",
         "FC 03 reads in blocks until 5345 4D49 5F72 appear in consecutive registers (CTP "
         "7.13.2)",
         {{"block", 125}},
         {},
         true,
         &run_semi_scan,
         nullptr},
        {"out_of_range_read",
         "FC 03 at 0x8001 answers 02; when 0x8001 is a register, a read past the highest one "
         "(declared count, else 2 registers from 0xFFFF) decides (CTP 9.1.2 and its note)",
         {},
         {},
         true,
         &run_out_of_range,
         &out_of_range_steps},
        {"other_address_read",
         "FC 03 to another address on the line is not answered (SER 2.2)",
         {{"register", 0x0010}, {"other_address", 0}},
         {},
         true,
         &run_other_address_read,
         nullptr},
        {"other_address_write",
         "FC 06 to another address is neither answered nor executed: the register read back at the "
         "device's own address is unchanged (SER 2.2)",
         {{"register", 0x0010}, {"other_address", 0}},
         {},
         true,
         &run_other_address_write,
         nullptr},
        {"broadcast_write",
         "FC 06 to address 0 is executed and not answered; the device answers a read once the "
         "turnaround delay is over, and the value is put back (SER 2.2, 2.4.1)",
         {{"register", 0x0010}, {"turnaround_ms", 200}},
         {},
         true,
         &run_broadcast_write,
         nullptr},
        {"broadcast_unanswered",
         "a request to address 0 (FC 03, or FC 08 with function = 8) is never answered (SER 2.2)",
         {{"register", 0x0010}, {"function", 3}},
         {},
         true,
         &run_broadcast_unanswered,
         nullptr},
        {"wrong_checksum",
         "FC 06 with a wrong CRC (RTU) or LRC (ASCII) is neither answered nor executed; FC 08 "
         "sub-function 0C counts it where served (SER 2.4.2, 6.1)",
         {{"register", 0x0010}},
         {},
         true,
         &run_wrong_checksum,
         nullptr},
        {"answer_frame",
         "the answer to FC 03 carries the device's own address, its CRC low byte first or ':', "
         "upper-case hex, LRC and CR LF, and nothing after it (SER 2.5.1, 2.5.2)",
         {{"register", 0x0010}},
         {},
         true,
         &run_answer_frame,
         nullptr},
        {"ascii_lower_case",
         "ASCII: FC 06 in lower-case hex is neither answered nor executed (SER 2.5.2)",
         {{"register", 0x0010}},
         {},
         true,
         &run_ascii_lower_case,
         nullptr},
        {"broken_request",
         "RTU: FC 06 broken by a silence over t1.5 is neither answered nor executed; ASCII: FC 03 "
         "with a pause under 1 s between its characters is answered (SER 2.5.1.1, 2.5.2.1)",
         {{"register", 0x0010},
          {"silence_ms", 50},
          {"ascii_pause_ms", 300},
          {"latency_ms", 16},
          {"pty_latency_ms", 2}},
         {},
         true,
         &run_broken_request,
         nullptr},
        {"answer_timing",
         "FC 03 reads, each sent t3.5 after the last answer, all answered with no silence over "
         "t1.5 inside an answer; response times reported against the timeout (SER 2.5.1.1, "
         "2.4.1)",
         {{"register", 0x0010}, {"count", 10}, {"latency_ms", 16}, {"pty_latency_ms", 2}},
         {},
         true,
         &run_answer_timing,
         nullptr},
        {"tls_handshake",
         "[SEC] handshake with the tester's certificate (TLS 1.2+, mutual authentication, the "
         "device's certificate verified against the CA), then an FC 03 read answered inside TLS",
         {},
         {},
         false,
         &run_tls_handshake,
         nullptr,
         true},
        {"tls10_refused",
         "a TLS 1.0-only ClientHello is refused (R-34)",
         {},
         {},
         false,
         &run_tls10_refused,
         nullptr,
         true},
        {"tls11_refused",
         "a TLS 1.1-only ClientHello is refused (R-34)",
         {},
         {},
         false,
         &run_tls11_refused,
         nullptr,
         true},
        {"no_certificate_refused",
         "a client that sends no certificate is refused with a fatal alert (R-10, R-44)",
         {},
         {},
         false,
         &run_no_certificate_refused,
         nullptr,
         true},
        {"expired_certificate_refused",
         "the PKI's client-expired certificate is refused (R-06, R-47)",
         {},
         {},
         false,
         &run_expired_certificate_refused,
         nullptr,
         true},
        {"foreign_ca_certificate_refused",
         "the PKI's client-foreign-ca certificate is refused (R-06)",
         {},
         {},
         false,
         &run_foreign_ca_certificate_refused,
         nullptr,
         true},
        {"self_signed_certificate_refused",
         "the PKI's client-self-signed certificate is refused (R-06)",
         {},
         {},
         false,
         &run_self_signed_certificate_refused,
         nullptr,
         true},
        {"null_role_denied",
         "the PKI's client-norole certificate: every public function code answered exception 01 "
         "(R-23, R-31)",
         {},
         {},
         false,
         &run_null_role_denied,
         nullptr,
         true},
        {"read_only_role",
         "the declared read-only role: FC 03 of register 0x0010 answered with data, FC 06 and FC "
         "10 "
         "answered exception 01 (R-04, R-30, R-31)",
         {},
         {},
         false,
         &run_read_only_role,
         nullptr,
         true},
        {"write_role",
         "the declared write role: FC 03 and FC 06 of register 0x0010 answered (R-04, R-30)",
         {},
         {},
         false,
         &run_write_role,
         nullptr,
         true},
        {"tls_renegotiation",
         "TLS 1.2 session: the RFC 5746 indication present (R-60); a renegotiation request leaves "
         "the device serving",
         {},
         {},
         false,
         &run_tls_renegotiation,
         nullptr,
         true},
        {"tls_close_notify",
         "close_notify after a read: the device ends the session and serves new ones",
         {},
         {},
         false,
         &run_tls_close_notify,
         nullptr,
         true},
    });
    return list;
}

const ProcedureInfo* find_procedure(std::string_view name) {
    for (const auto& info : procedures()) {
        if (info.name == name) return &info;
    }
    return nullptr;
}

bool is_security_procedure(std::string_view procedure) {
    const ProcedureInfo* info = find_procedure(procedure);
    return info != nullptr && info->needs_mbaps;
}

std::int64_t param(const Case& c, std::string_view name) {
    if (auto it = c.params.find(std::string(name)); it != c.params.end()) return it->second;
    if (const ProcedureInfo* info = find_procedure(c.procedure)) {
        for (const auto& [key, value] : info->params) {
            if (key == name) return value;
        }
    }
    return 0;
}

}  // namespace mblab::conformance
