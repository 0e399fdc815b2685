#include "load/exchanges.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <vector>

#include "conformance/judge.hpp"
#include "protocol/adu_writer.hpp"

namespace mblab::load {

namespace {

using std::chrono::duration_cast;
using std::chrono::microseconds;

// The expected answers as they apply to one request on the wire: with its transaction id in
// place of the catalogue's, so the evidence marks only bytes that really differ.
std::vector<conformance::ResolvedPattern> with_transaction_id(
    const std::vector<conformance::ResolvedPattern>& expect, std::uint16_t tid) {
    std::vector<conformance::ResolvedPattern> out = expect;
    for (auto& pattern : out) {
        const std::uint8_t bytes[2] = {static_cast<std::uint8_t>(tid >> 8),
                                       static_cast<std::uint8_t>(tid & 0xFF)};
        for (std::size_t i = 0; i < 2 && i < pattern.tokens.size(); ++i) {
            auto& token = pattern.tokens[i];
            if (token.kind == conformance::PatternToken::Kind::Byte ||
                token.kind == conformance::PatternToken::Kind::Any) {
                token = {conformance::PatternToken::Kind::Byte, bytes[i], {}};
            }
        }
    }
    return out;
}
}  // namespace

std::uint32_t next_mix_exchange(const LoadPlan& plan, Prng& prng) {
    const auto& sums = plan.mix_cumulative;
    const std::uint64_t pick = prng.next() % sums.back();
    const auto at = std::upper_bound(sums.begin(), sums.end(), pick) - sums.begin();
    return static_cast<std::uint32_t>(plan.test_exchanges + static_cast<std::size_t>(at));
}

bool next_test_exchange(const LoadPlan& plan, const NodeTally& tally, std::size_t& cursor,
                        std::uint32_t& out) {
    for (std::size_t tried = 0; tried < plan.test_exchanges; ++tried) {
        const std::size_t index = cursor;
        cursor = (cursor + 1) % plan.test_exchanges;
        if (tally.not_applicable[plan.exchanges[index].test_case].empty()) {
            out = static_cast<std::uint32_t>(index);
            return true;
        }
    }
    return false;
}

std::optional<FailureKind> judge_load_answer(const LoadPlan& plan, NodeTally& tally, bool tests,
                                             std::uint32_t exchange,
                                             std::span<const std::uint8_t> frame) {
    const LoadExchange& sent = plan.exchanges[exchange];
    std::optional<FailureKind> failure = judge_answer(sent.answers, frame);
    if (failure && tests && plan.cases[sent.test_case].unsupported_is_na &&
        conformance::is_exception_answer(sent.request, frame,
                                         protocol::ExceptionCode::IllegalFunction)) {
        tally.not_applicable[sent.test_case] = fmt::format(
            "N/A: the device answered exception 01 to function {:02X}", sent.function());
        failure.reset();
    }
    return failure;
}

void count_failure(NodeTally& tally, const LoadPlan& plan, LoadClock::time_point start,
                   FailureKind kind, const LoadSent* sent, const LoadSeen& seen,
                   LoadClock::time_point now, std::string_view reason) {
    tally.failures[static_cast<std::size_t>(kind)].add();
    if (sent != nullptr) tally.exchange(sent->exchange).failed.add();
    if (tally.first_failure) return;
    // Only the node's first failure keeps its evidence: the only allocation after setup.
    client::Received received{
        seen.status, {seen.bytes.begin(), seen.bytes.end()}, std::string(seen.detail)};
    FailureRecord record;
    record.kind = kind;
    record.at = duration_cast<microseconds>(now - start);
    const auto timeout = plan.settings.timeout;
    if (sent != nullptr) {
        const LoadExchange& exchange = plan.exchanges[sent->exchange];
        std::vector<std::uint8_t> request = exchange.request;
        protocol::put_mbap_transaction_id(request, sent->tid);
        record.exchange = exchange.name;
        record.evidence = conformance::judge(request, std::move(received), timeout,
                                             with_transaction_id(exchange.expect, sent->tid))
                              .exchange;
    } else {
        record.evidence.status = received.status;
        record.evidence.received = std::move(received.bytes);
        record.evidence.detail = std::move(received.detail);
        record.evidence.waited = timeout;
    }
    record.reason = reason.empty() ? conformance::describe_failure(record.evidence)
                                   : std::string(reason) + std::string(seen.detail);
    tally.first_failure = std::move(record);
}

}  // namespace mblab::load
