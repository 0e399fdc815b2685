#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "protocol/adu.hpp"
#include "robustness/fuzz_case.hpp"
#include "robustness/recon.hpp"
#include "robustness/writable_range.hpp"
#include "support/prng.hpp"

// The cases of a run, the same for the same recon, policy and seed: first every class's fixed
// cases (the pairwise rows among them), taken a class at a time in turn so that a short budget
// reaches every class, then seeded mutations of valid requests without end. On a serial line (RTU,
// ASCII) the same cases re-framed for it, less those that test MBAP or TCP, plus the line-only
// classes (robustness/line_cases.hpp).
namespace mblab::robustness {

struct WritePolicy {
    bool allow_writes = false;  // anything goes: the device is a lab device
    std::optional<WritableRange> writable;
};

// Whether `pdu` may be sent under `policy`: reads always; a write only when writes are allowed
// or every address it writes lies inside the writable range; FC 08 sub-functions that change the
// device's mode (01 restart, 03 ASCII delimiter, 04 listen only) only when writes are allowed,
// since a device that obeys them has not failed.
bool may_send(std::span<const std::uint8_t> pdu, const WritePolicy& policy);

// What the tester's own machine allows the resource cases.
struct ResourceLimits {
    std::size_t connections = 2000;  // held at once by the largest many-connections case
    bool half_open = true;           // connections can be let go without a FIN (TCP_REPAIR)
};

class CaseGenerator {
  public:
    // `gap` is the silence the line-gap class leaves inside an RTU frame (longer than t1.5).
    CaseGenerator(Recon recon, WritePolicy policy, std::uint64_t seed,
                  protocol::Framing framing = protocol::Framing::Mbap,
                  std::chrono::milliseconds gap = std::chrono::milliseconds(2),
                  ResourceLimits limits = {});

    // Keeps the fixed cases of the chosen classes only, and the mutations only when that class
    // is chosen (indexed by BadInput).
    void choose(const std::array<bool, kBadInputCount>& classes);
    bool chosen(BadInput kind) const { return chosen_[static_cast<std::size_t>(kind)]; }
    // No case is left: the fixed ones are taken and mutations are not chosen.
    bool exhausted() const { return !chosen(BadInput::Mutation) && taken_ >= fixed_.size(); }
    // The next case; fixed ones first, then mutations. Not to be called once exhausted.
    FuzzCase next();
    // Fixed cases left out because they would write outside the policy, per class.
    const std::vector<std::size_t>& withheld() const { return withheld_; }
    std::size_t fixed_cases() const { return fixed_.size(); }
    const ResourceLimits& limits() const { return limits_; }

  private:
    void add(FuzzCase c);
    // Counts the frame as withheld when the policy does not let it out.
    bool withhold(BadInput kind, std::span<const std::uint8_t> pdu);
    void add_frame(BadInput kind, std::string name, std::span<const std::uint8_t> pdu);
    // The class's reads of a quantity at an address, named "FC 0x03 address 0xFFFF quantity 2".
    void add_ranged(BadInput kind);
    std::uint16_t next_transaction() { return ++transaction_; }
    // The cases of one frame (robustness/frame_cases.cpp).
    void fixed_frames();
    // The cases of several steps or connections (robustness/stream_cases.cpp).
    void fixed_streams();
    void resource_cases();
    void pairwise();
    FuzzCase mutation();

    Recon recon_;
    WritePolicy policy_;
    protocol::Framing framing_;
    ResourceLimits limits_;
    Prng prng_;
    std::uint16_t transaction_ = 0;
    std::uint16_t write_address_ = 0;
    std::vector<std::vector<FuzzCase>> by_class_;
    std::vector<FuzzCase> fixed_;
    std::size_t taken_ = 0;
    std::vector<std::size_t> withheld_;
    std::array<bool, kBadInputCount> chosen_ = [] {
        std::array<bool, kBadInputCount> all{};
        all.fill(true);
        return all;
    }();
};

}  // namespace mblab::robustness
