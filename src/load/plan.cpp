#include "load/plan.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <optional>
#include <set>

#include "conformance/procedures.hpp"
#include "protocol/limits.hpp"
#include "protocol/request_template.hpp"

namespace mblab::load {

namespace {

namespace limits = protocol::limits;

// Why a step cannot run in the loop; nothing when it can.
std::optional<std::string> loop_obstacle(const conformance::Step& step) {
    if (!step.split.empty()) return "writes its request in pieces";
    if (step.silence) return "expects silence";
    if (step.accept_close || step.accept_silence) return "tolerates a close or silence";
    return std::nullopt;
}

// The runner frames answers by the MBAP length and writes transaction ids into requests, so a
// request must be one whole frame that says so.
bool is_whole_mbap_request(const std::vector<std::uint8_t>& bytes) {
    if (bytes.size() <= limits::kMbapHeader || bytes.size() > limits::kMaxTcpAdu) return false;
    const auto frame = protocol::read_mbap_frame(bytes);
    // The length field counts the unit id and the PDU.
    return frame->header.protocol_id == protocol::kModbusProtocolId &&
           frame->header.length == frame->pdu.size() + 1;
}

LoadExchange make_exchange(std::string name, std::string source, std::vector<std::uint8_t> request,
                           std::vector<conformance::ResolvedPattern> expect) {
    LoadExchange exchange;
    exchange.name = std::move(name);
    exchange.source = std::move(source);
    exchange.request = std::move(request);
    for (const auto& pattern : expect)
        exchange.answers.emplace_back(pattern);
    exchange.expect = std::move(expect);
    return exchange;
}

// The case's exchanges, or why it stays out of the loop.
protocol::Result<std::vector<LoadExchange>, std::string> case_exchanges(
    const conformance::Case& c, const conformance::Dut& dut) {
    if (c.isolated) return std::string("needs a connection of its own");
    for (const auto& requirement : c.requirements) {
        if (auto why = conformance::unmet(requirement, dut)) return "N/A: " + why->reason;
    }
    if (!c.procedure.empty()) {
        const conformance::ProcedureInfo* info = conformance::find_procedure(c.procedure);
        if (info == nullptr || info->load_steps == nullptr) {
            return fmt::format("procedure {}", c.procedure);
        }
        std::vector<LoadExchange> out;
        auto steps = info->load_steps(dut);
        for (std::size_t i = 0; i < steps.size(); ++i) {
            auto name = steps.size() == 1 ? c.id : fmt::format("{} step {}", c.id, i + 1);
            out.push_back(make_exchange(std::move(name), c.source, std::move(steps[i].request),
                                        std::move(steps[i].expect)));
            out.back().first_step = i == 0;
        }
        return out;
    }
    const conformance::DutFacts facts(dut);
    std::vector<LoadExchange> out;
    for (std::size_t i = 0; i < c.steps.size(); ++i) {
        const conformance::Step& step = c.steps[i];
        if (auto why = loop_obstacle(step)) return *why;
        auto request = conformance::resolve(step.request, facts);
        if (!request) return fmt::format("N/A: the DUT does not declare {}", request.error().name);
        auto bytes = conformance::render_bytes(request.value());
        if (!is_whole_mbap_request(bytes))
            return std::string("its request is not a whole MBAP frame");
        std::vector<conformance::ResolvedPattern> expect;
        for (const auto& alternative : step.expect) {
            auto pattern = conformance::resolve(alternative.pattern, facts);
            if (!pattern) {
                return fmt::format("N/A: the DUT does not declare {}", pattern.error().name);
            }
            expect.push_back(std::move(pattern.value()));
        }
        auto name = c.steps.size() == 1 ? c.id : fmt::format("{} step {}", c.id, i + 1);
        out.push_back(
            make_exchange(std::move(name), c.source, std::move(bytes), std::move(expect)));
        out.back().first_step = i == 0;
    }
    return out;
}

}  // namespace

protocol::Result<bool, std::string> add_protocol_tests(
    LoadPlan& plan, const std::vector<conformance::Suite>& suites, const conformance::Dut& dut,
    const std::vector<std::string>& only) {
    const std::set<std::string> wanted(only.begin(), only.end());
    std::set<std::string> found;
    for (const auto& suite : suites) {
        plan.suites.push_back(suite.name);
        for (const auto& c : suite.cases) {
            if (!wanted.empty() && (!wanted.contains(c.id) || !found.insert(c.id).second)) {
                continue;
            }
            auto exchanges = case_exchanges(c, dut);
            if (!exchanges) {
                plan.left_out.push_back({c.id, exchanges.error()});
                continue;
            }
            const std::size_t index = plan.cases.size();
            plan.cases.push_back({c.id, c.source, c.title, plan.exchanges.size(), exchanges->size(),
                                  c.unsupported_is_na});
            for (auto& exchange : exchanges.value()) {
                exchange.test_case = index;
                plan.exchanges.push_back(std::move(exchange));
            }
        }
    }
    for (const auto& id : only) {
        if (!found.contains(id)) return fmt::format("no case {} in the chosen suites", id);
    }
    plan.test_exchanges = plan.exchanges.size();
    return true;
}

namespace {

// The range a request names in its data table, from its request template: the read's range for
// a read, the written one for a write; nullopt when it names no quantity of a table.
struct Range {
    protocol::DataTable table = protocol::DataTable::None;
    std::uint32_t first = 0;
    std::uint32_t count = 0;
};

std::optional<Range> range_of(std::span<const std::uint8_t> pdu) {
    const auto* request = pdu.empty() ? nullptr : protocol::find_template(pdu[0]);
    if (request == nullptr || request->table == protocol::DataTable::None) return std::nullopt;
    const auto* address = protocol::field_with(*request, protocol::FieldRole::Address);
    const auto* quantity = protocol::field_with(*request, protocol::FieldRole::Quantity);
    if (address == nullptr || quantity == nullptr) return std::nullopt;
    const auto first = protocol::read_field(pdu, *address);
    const auto count = protocol::read_field(pdu, *quantity);
    if (!first || !count) return std::nullopt;
    return Range{request->table, *first, *count};
}

// A read-back among the test exchanges whose range a mix entry writes keeps its form (length,
// byte count) but no longer pins the values, which the generator changes under it.
void unpin_read_backs(LoadPlan& plan) {
    for (std::size_t i = 0; i < plan.test_exchanges; ++i) {
        LoadExchange& exchange = plan.exchanges[i];
        const auto pdu = protocol::read_mbap_frame(exchange.request)->pdu;
        const auto read = range_of(pdu);
        if (!read || protocol::writes(pdu[0])) continue;
        const bool overlapped = std::any_of(plan.mix.begin(), plan.mix.end(), [&](const auto& e) {
            return protocol::writes(e.function) &&
                   protocol::find_template(e.function)->table == read->table &&
                   e.address < read->first + read->count &&
                   read->first < std::uint32_t{e.address} + e.quantity;
        });
        if (!overlapped) continue;
        constexpr std::size_t kValuesAt = 9;  // after the MBAP header, function and byte count
        bool unpinned = false;
        for (auto& pattern : exchange.expect) {
            std::size_t position = 0;  // in bytes: {len} stands for two
            for (auto& token : pattern.tokens) {
                if (position >= kValuesAt && token.kind == conformance::PatternToken::Kind::Byte) {
                    token.kind = conformance::PatternToken::Kind::Any;
                    unpinned = true;
                }
                position += token.kind == conformance::PatternToken::Kind::Length ? 2 : 1;
            }
        }
        if (!unpinned) continue;  // an exception or values the pattern never pinned
        exchange.answers.clear();
        for (const auto& pattern : exchange.expect)
            exchange.answers.emplace_back(pattern);
        plan.values_unchecked.push_back(exchange.name);
    }
}

}  // namespace

void add_mix(LoadPlan& plan, const std::vector<MixEntry>& mix, const conformance::Dut& dut) {
    const conformance::DutFacts facts(dut);
    std::uint64_t sum = 0;
    for (const auto& entry : mix) {
        MixExchange patterns = mix_exchange(entry);
        // The mix only uses {unit}, which every DUT declares.
        auto request = conformance::resolve(patterns.request, facts);
        auto expect = conformance::resolve(patterns.expect, facts);
        plan.exchanges.push_back(make_exchange(entry.text, "--mix",
                                               conformance::render_bytes(request.value()),
                                               {std::move(expect.value())}));
        sum += entry.weight;
        plan.mix_cumulative.push_back(sum);
    }
    plan.mix = mix;
    unpin_read_backs(plan);
}

std::string format_duration_words(std::chrono::milliseconds duration) {
    const auto ms = duration.count();
    if (ms % 1000 != 0 || ms < 1000) return fmt::format("{:g} s", static_cast<double>(ms) / 1000);
    const auto seconds = ms / 1000;
    std::string out;
    auto part = [&](long long value, const char* unit) {
        if (value == 0) return;
        out += fmt::format("{}{} {}", out.empty() ? "" : " ", value, unit);
    };
    part(seconds / 3600, "h");
    part(seconds / 60 % 60, "min");
    part(seconds % 60, "s");
    return out;
}

std::size_t LoadPlan::tcp_connections() const {
    std::size_t count = 0;
    const bool tests = settings.tests && !cases.empty();
    for (const auto& target : targets) {
        if (tests && !target.line) ++count;
    }
    for (std::size_t i = 0; i < settings.connections && !targets.empty(); ++i) {
        if (!targets[node_of_traffic(i)].line) ++count;
    }
    return count;
}

}  // namespace mblab::load
