#include <fmt/core.h>

#include "conformance/catalogue.hpp"
#include "conformance/judge.hpp"
#include "conformance/procedures.hpp"
#include "conformance/session.hpp"

// CTP 9.1.2: a read at 0x8001 answers exception 02, unless 0x8001 is a register of the
// device; then (the policy's note) a read past the highest register is used. With the register
// count declared that offset is known before the run. Without it, the policy's request goes
// first, and only when 0x8001 answers data does a read of two registers from 0xFFFF, past the
// end of any device's address space, decide: a conformant device never fails for not declaring.
namespace mblab::conformance {

namespace {

constexpr std::uint8_t kReadHolding = 0x03;
constexpr std::uint8_t kIllegalDataAddress = 0x02;
constexpr std::uint32_t kAddressSpace = 65536;
constexpr std::uint16_t kPolicyOffset = 0x8001;  // CTP 9.1.2.2

struct Read {
    std::uint16_t offset = 0;
    std::uint16_t count = 1;
};

std::vector<std::uint8_t> request_for(std::uint8_t unit, Read read) {
    Pattern request;
    request.u16(0).u16(0).length().byte(unit).byte(kReadHolding).u16(read.offset).u16(read.count);
    return render_bytes(ResolvedPattern{request.tokens()});
}

ResolvedPattern refusal(std::uint8_t unit) {
    Pattern answer;
    answer.u16(0).u16(0).length().byte(unit).byte(kReadHolding | 0x80).byte(kIllegalDataAddress);
    return ResolvedPattern{answer.tokens()};
}

ResolvedPattern data_answer(std::uint8_t unit, std::uint16_t count) {
    Pattern answer;
    const auto bytes = static_cast<std::uint8_t>(2 * count);
    answer.u16(0).u16(0).length().byte(unit).byte(kReadHolding).byte(bytes).any(bytes);
    return ResolvedPattern{answer.tokens()};
}

// The read past the end when the count is declared (0x8001 when that is already past it).
Read declared_read(std::uint32_t registers) {
    if (registers <= kPolicyOffset) return {kPolicyOffset, 1};
    if (registers < kAddressSpace) return {static_cast<std::uint16_t>(registers), 1};
    return {0xFFFF, 2};
}

constexpr Read kPastTheEnd{0xFFFF, 2};

std::string read_text(Read read) {
    return fmt::format("read of {} register{} at {:04X}", read.count, read.count == 1 ? "" : "s",
                       read.offset);
}

Judgement exchange(Session& session, Read read, const std::vector<ResolvedPattern>& expect,
                   bool& sent) {
    const auto request = request_for(session.dut().unit, read);
    client::LinkError error;
    const auto timeout = session.options().timeout;
    sent = session.send(request, 1, error);
    if (!sent) {
        return judge(request, client::Received{client::ReceiveStatus::Closed, {}, error.message},
                     timeout, expect);
    }
    Judgement judgement = judge(request, session.receive_frame(timeout), timeout, expect);
    judgement.exchange.on_connection = session.connection_requests();
    return judgement;
}

Outcome failed(Session& session, Read read, const Judgement& judgement, std::string_view step) {
    std::string reason = describe_failure(judgement.exchange, session.framing());
    if (judgement.exchange.status == client::ReceiveStatus::Timeout &&
        judgement.exchange.received.empty()) {
        reason += session.no_answer_hint(judgement.exchange.sent);
    }
    session.close();
    return Outcome{Verdict::Fail,
                   fmt::format("{}{}: {}", step, read_text(read), reason),
                   {judgement.exchange}};
}

}  // namespace

Outcome run_out_of_range(Session& session, const Case& c) {
    (void)c;
    const Dut& dut = session.dut();
    const std::uint8_t unit = dut.unit;
    bool sent = false;
    if (dut.registers) {
        const Read read = declared_read(*dut.registers);
        auto judgement = exchange(session, read, {refusal(unit)}, sent);
        if (judgement.matched < 0) return failed(session, read, judgement, "");
        return Outcome{
            Verdict::Pass,
            fmt::format("{} answered 02; {} registers declared", read_text(read), *dut.registers),
            {}};
    }
    const Read policy{kPolicyOffset, 1};
    auto first = exchange(session, policy, {refusal(unit), data_answer(unit, 1)}, sent);
    if (first.matched < 0) return failed(session, policy, first, "");
    if (first.matched == 0) {
        return Outcome{Verdict::Pass,
                       fmt::format("{} answered 02; no register count declared", read_text(policy)),
                       {}};
    }
    auto second = exchange(session, kPastTheEnd, {refusal(unit)}, sent);
    if (second.matched < 0) {
        return failed(session, kPastTheEnd, second,
                      "8001 is a register of this device (it answered data), so the read past "
                      "the end decides: ");
    }
    return Outcome{Verdict::Pass,
                   fmt::format("8001 is a register of this device (it answered data) and no "
                               "register count is declared; the {}, past the end of the "
                               "address space, answered 02 and decided the verdict",
                               read_text(kPastTheEnd)),
                   {}};
}

std::vector<ProcedureStep> out_of_range_steps(const Dut& dut) {
    if (dut.registers) {
        const Read read = declared_read(*dut.registers);
        return {{request_for(dut.unit, read), {refusal(dut.unit)}}};
    }
    // Under load each answer is judged alone: 0x8001 may answer either way, and the read past
    // the end must answer 02.
    return {
        {request_for(dut.unit, {kPolicyOffset, 1}), {refusal(dut.unit), data_answer(dut.unit, 1)}},
        {request_for(dut.unit, kPastTheEnd), {refusal(dut.unit)}}};
}

}  // namespace mblab::conformance
