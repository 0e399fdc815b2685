#include "robustness/case_generator.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>

#include "conformance/plain_requests.hpp"
#include "protocol/request_template.hpp"
#include "robustness/in_turn.hpp"
#include "robustness/line_cases.hpp"
#include "robustness/pairwise_cases.hpp"
#include "robustness/request_bytes.hpp"

namespace mblab::robustness {

namespace {

using Bytes = std::vector<std::uint8_t>;

std::uint16_t field16(std::span<const std::uint8_t> pdu, std::size_t at) {
    return static_cast<std::uint16_t>(pdu[at] << 8 | pdu[at + 1]);
}

}  // namespace

bool may_send(std::span<const std::uint8_t> pdu, const WritePolicy& policy) {
    if (pdu.empty() || policy.allow_writes) return true;
    const std::uint8_t function = pdu[0];
    if (function == 0x08) {
        if (pdu.size() < 3) return true;
        const auto sub = field16(pdu, 1);
        return sub != 0x01 && sub != 0x03 && sub != 0x04;
    }
    if (!protocol::writes(function)) return true;
    // The range the request writes, as its template names it; file records have none in the
    // writable range, and what is cut off names nothing.
    const auto* request = protocol::find_template(function);
    const auto* address_field = protocol::field_with(*request, protocol::FieldRole::Address);
    if (!policy.writable || address_field == nullptr) return false;
    const auto address = protocol::read_field(pdu, *address_field);
    if (!address) return true;
    const auto* quantity_field = protocol::field_with(*request, protocol::FieldRole::Quantity);
    const auto quantity =
        quantity_field != nullptr ? protocol::read_field(pdu, *quantity_field) : std::nullopt;
    const std::uint32_t count = std::max<std::uint32_t>(quantity.value_or(1), 1);
    const std::uint32_t start = policy.writable->start;
    return *address >= start && *address + count <= start + policy.writable->count;
}

CaseGenerator::CaseGenerator(Recon recon, WritePolicy policy, std::uint64_t seed,
                             protocol::Framing framing, std::chrono::milliseconds gap,
                             ResourceLimits limits)
    : recon_(std::move(recon)),
      policy_(policy),
      framing_(framing),
      limits_(limits),
      prng_(seed),
      by_class_(kBadInputCount) {
    write_address_ = policy_.writable ? policy_.writable->start : 0;
    fixed_frames();
    fixed_streams();
    resource_cases();
    pairwise();
    if (framing_ != protocol::Framing::Mbap) {
        for (auto& cases : by_class_) {
            std::vector<FuzzCase> kept;
            for (const auto& c : cases) {
                if (auto framed = on_line(c, framing_)) kept.push_back(std::move(*framed));
            }
            cases = std::move(kept);
        }
        for (auto& c : line_cases(framing_, recon_.unit, recon_.check_address, gap))
            add(std::move(c));
    }
    // A class at a time in turn, so that a short budget reaches every class.
    fixed_ = in_turn(std::move(by_class_));
    by_class_.clear();
}

void CaseGenerator::add(FuzzCase c) {
    by_class_[static_cast<std::size_t>(c.kind)].push_back(std::move(c));
}

bool CaseGenerator::withhold(BadInput kind, std::span<const std::uint8_t> pdu) {
    if (may_send(pdu, policy_)) return false;
    withheld_.resize(kBadInputCount);
    ++withheld_[static_cast<std::size_t>(kind)];
    return true;
}

void CaseGenerator::add_frame(BadInput kind, std::string name, std::span<const std::uint8_t> pdu) {
    if (withhold(kind, pdu)) return;
    FuzzCase c{kind, std::move(name), {}, false};
    c.steps.push_back({0, mbap_frame(next_transaction(), recon_.unit, pdu), {}});
    add(std::move(c));
}

void CaseGenerator::pairwise() {
    // On a line the MBAP fields are no parameters: each row is a frame that re-frames whole.
    for (auto& frame :
         pairwise_frames(recon_, policy_.writable, framing_ == protocol::Framing::Mbap)) {
        if (withhold(BadInput::Pairwise, frame.pdu)) continue;
        FuzzCase c{BadInput::Pairwise, std::move(frame.name), {}, false};
        c.steps.push_back({0,
                           mbap_frame(frame.transaction.value_or(next_transaction()), frame.unit,
                                      frame.pdu, frame.protocol, frame.length),
                           {}});
        add(std::move(c));
    }
}

void CaseGenerator::choose(const std::array<bool, kBadInputCount>& classes) {
    chosen_ = classes;
    std::erase_if(fixed_, [&](const FuzzCase& c) { return !chosen(c.kind); });
    for (std::size_t i = 0; i < withheld_.size(); ++i) {
        if (!chosen_[i]) withheld_[i] = 0;
    }
}

FuzzCase CaseGenerator::next() {
    if (taken_ < fixed_.size()) return fixed_[taken_++];
    ++taken_;
    if (framing_ == protocol::Framing::Mbap) return mutation();
    // A mutation of the MBAP header alone has nothing to say on a line: another is drawn.
    while (true) {
        if (auto framed = on_line(mutation(), framing_)) return std::move(*framed);
    }
}

FuzzCase CaseGenerator::mutation() {
    // The valid requests mutations start from: reads of what answers, and the plain requests of
    // every public function that the policy lets through, served or not (a stack may parse what
    // it then refuses with exception 01).
    std::vector<Bytes> bases = {words(0x03, {recon_.check_address, 1}),
                                words(0x03, {recon_.check_address, recon_.max_read})};
    for (std::uint8_t function : conformance::functions_with_plain_requests()) {
        if (auto pdu = probe_request(function, true); pdu && may_send(*pdu, policy_))
            bases.push_back(*pdu);
        if (auto safe = probe_request(function, false)) bases.push_back(*safe);
    }
    auto pick = [&](std::size_t n) { return static_cast<std::size_t>(prng_.next() % n); };
    static constexpr std::array<std::uint8_t, 8> kBoundaryBytes{0x00, 0x01, 0x7F, 0x80,
                                                                0xFE, 0xFF, 0x10, 0x7D};
    for (int attempt = 0;; ++attempt) {
        Bytes pdu = bases[pick(bases.size())];
        std::string what;
        const std::size_t changes = 1 + pick(3);
        for (std::size_t i = 0; i < changes; ++i) {
            const std::size_t at = pdu.empty() ? 0 : pick(pdu.size());
            switch (pick(7)) {
                case 0:
                    if (pdu.empty()) break;
                    pdu[at] ^= static_cast<std::uint8_t>(1U << pick(8));
                    what += fmt::format(" flip@{}", at);
                    break;
                case 1:
                    if (pdu.empty()) break;
                    pdu[at] = kBoundaryBytes[pick(kBoundaryBytes.size())];
                    what += fmt::format(" set@{}={:02X}", at, pdu[at]);
                    break;
                case 2:
                    pdu.insert(pdu.begin() + static_cast<long>(at),
                               static_cast<std::uint8_t>(prng_.next()));
                    what += fmt::format(" insert@{}", at);
                    break;
                case 3:
                    if (pdu.size() < 2) break;
                    pdu.erase(pdu.begin() + static_cast<long>(at));
                    what += fmt::format(" delete@{}", at);
                    break;
                case 4:
                    if (pdu.size() < 2) break;
                    pdu.resize(1 + pick(pdu.size() - 1));
                    what += fmt::format(" cut@{}", pdu.size());
                    break;
                case 5: {
                    const std::size_t extra = 1 + pick(8);
                    for (std::size_t k = 0; k < extra; ++k)
                        pdu.push_back(static_cast<std::uint8_t>(prng_.next()));
                    what += fmt::format(" append{}", extra);
                    break;
                }
                default:
                    if (pdu.size() < 3) break;
                    pdu[at == 0 ? 1 : at] = 0xFF;
                    if (at + 1 < pdu.size()) pdu[at + 1] = 0xFF;
                    what += fmt::format(" ffff@{}", at == 0 ? 1 : at);
                    break;
            }
        }
        if (pdu.empty() || (!may_send(pdu, policy_) && attempt < 50)) continue;
        if (!may_send(pdu, policy_)) pdu = bases.front();
        std::optional<std::uint16_t> length;
        std::uint16_t protocol = 0;
        std::uint8_t unit = recon_.unit;
        // Mostly a correct header, so the PDU is what is tested; sometimes the header too.
        switch (pick(10)) {
            case 0:
                length = static_cast<std::uint16_t>(pdu.size() + 1 + pick(5) - 2);
                what += fmt::format(" length={}", *length);
                break;
            case 1:
                unit = static_cast<std::uint8_t>(prng_.next());
                what += fmt::format(" unit={}", unit);
                break;
            case 2:
                protocol = static_cast<std::uint16_t>(prng_.next());
                what += fmt::format(" protocol={:04X}", protocol);
                break;
            default:
                break;
        }
        FuzzCase c{BadInput::Mutation,
                   fmt::format("mutation {}: FC 0x{:02X}{}", taken_ - fixed_.size(), pdu[0], what),
                   {},
                   false};
        c.steps.push_back({0, mbap_frame(next_transaction(), unit, pdu, protocol, length), {}});
        return c;
    }
}

}  // namespace mblab::robustness
