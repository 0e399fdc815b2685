#include "robustness/probe_finding.hpp"

#include <fmt/core.h>

#include "protocol/request_template.hpp"
#include "robustness/line_cases.hpp"

namespace mblab::robustness {

namespace {

// The class whose bad input the probe is: a write cut short (FC 06 without its value), a quantity
// of 0 (FC 0F, 10, 17), or a value no write may carry (FC 05 of 0x1234).
BadInput class_of_probe(std::uint8_t function, std::size_t size) {
    const auto* request = protocol::find_template(function);
    if (request == nullptr) return BadInput::Boundary;
    const auto sample = protocol::sample_request(function);
    if (sample && size < sample->size()) return BadInput::Truncated;
    if (protocol::field_with(*request, protocol::FieldRole::Quantity) != nullptr)
        return BadInput::Quantity;
    return BadInput::Boundary;
}

}  // namespace

FuzzResult probe_finding(const Recon& recon, const std::string& target, std::uint64_t seed,
                         protocol::Framing framing) {
    const auto& probe = *recon.killed_by;
    FuzzResult result;
    result.target = target;
    result.seed = seed;
    result.recon = recon;
    result.stopped_by = "finding";
    FuzzCase c{class_of_probe(probe.function, probe.request.size()),
               fmt::format("reconnaissance probe FC 0x{:02X} (a request the device must refuse)",
                           probe.function),
               {},
               false};
    c.steps.push_back({0, mbap_frame(1, recon.unit, probe.request), {}});
    if (framing != protocol::Framing::Mbap) {
        if (auto framed = on_line(c, framing)) c = std::move(*framed);
    }
    Finding finding;
    finding.kind = c.kind;
    finding.case_name = c.name;
    finding.case_number = 0;
    finding.reason = fmt::format(
        "stopped answering the known-good read (FC 03 of register {}) after a reconnaissance "
        "probe it had answered that read before",
        recon.check_address);
    finding.since_check = c.steps;
    finding.origins.assign(c.steps.size(), StepOrigin{c.kind, c.name, 0});
    finding.reproducer = c.steps;
    finding.minimise_note =
        "the probe alone: the device answered the read just before it and not after it";
    finding.minimised = true;
    result.findings.push_back(std::move(finding));
    return result;
}

}  // namespace mblab::robustness
