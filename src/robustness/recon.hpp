#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

// Reconnaissance: what the device serves, learned with plain requests before any bad one, so the
// cases aim at code that runs and the liveness check asks something the device answers.
namespace mblab::robustness {

// The four data tables a request can reach.
enum class Table : std::uint8_t { Coils, DiscreteInputs, HoldingRegisters, InputRegisters };
inline constexpr std::size_t kTableCount = 4;
// "coils", "discrete inputs", "holding registers", "input registers".
const char* table_name(Table table);
// "coils", "discrete_inputs", ...: the JSON report's keys.
const char* table_key(Table table);

// Where a map that does not start at 0 is looked for, in this order: the liveness check's
// holding register, and where `mblab scan` looks for each table.
inline constexpr std::array<std::uint16_t, 5> kProbeAddresses{0, 1, 100, 1000, 40000};

struct AddressRange {
    std::uint16_t first = 0;
    std::uint16_t last = 0;  // inclusive: a range may end at 0xFFFF
    friend bool operator==(const AddressRange&, const AddressRange&) = default;
};

// The addresses that answered, per table, sorted and merged (adjacent ranges join).
class AnsweredRanges {
  public:
    void add(Table table, AddressRange range);
    const std::vector<AddressRange>& of(Table table) const {
        return tables_[static_cast<std::size_t>(table)];
    }
    bool empty() const;

  private:
    std::array<std::vector<AddressRange>, kTableCount> tables_;
};

// A reconnaissance probe after which the device stopped answering the read it answered before:
// a finding of its own, with the probe as its reproducer.
struct ProbeDeath {
    std::uint8_t function = 0;
    std::vector<std::uint8_t> request;  // the probe's PDU
};

struct Recon {
    std::uint8_t unit = 1;
    std::vector<std::uint8_t> served;      // function codes answered other than with exception 01
    std::vector<std::uint8_t> not_served;  // answered 01
    std::vector<std::uint8_t> silent;      // not answered at all
    std::vector<std::uint8_t> not_asked;   // functions that write, with ReconOptions::reads_only
    std::uint16_t check_address = 0;       // a holding register FC 03 reads: the liveness check
    std::uint16_t max_read = 125;          // the largest FC 03 quantity answered there
    bool answers_unit_0 = false;
    bool answers_unit_255 = false;
    // "probed", the DUT file that declared unit and max_read, or "learned from FILE (...)".
    std::string source = "probed";
    AnsweredRanges ranges;  // where requests were answered with data or an echo
    // Declared by a DUT file (--dut): a file FC 14 reads, a FIFO FC 18 reads.
    std::optional<std::uint16_t> file_number;
    std::optional<std::uint16_t> fifo_address;
    // Set when a probe killed the device: the reconnaissance stopped there, the rest is unknown.
    std::optional<ProbeDeath> killed_by;

    bool serves(std::uint8_t function) const;
};

// One request and its answer's PDU: nullopt when none came (timeout, closed connection).
using Ask = std::function<std::optional<std::vector<std::uint8_t>>(
    std::uint8_t unit, std::span<const std::uint8_t> pdu)>;

struct ReconOptions {
    std::uint8_t unit = 1;
    bool allow_writes = false;
    // Functions that write are not asked at all, not even with requests the device must refuse
    // (a device that does not refuse them would carry them out): `mblab scan`.
    bool reads_only = false;
    // Declared facts that replace the probed ones (from --dut).
    std::optional<std::uint16_t> max_read;
    std::optional<std::uint16_t> check_address;
};

// The request probing `function` without changing anything: a write that the device must
// refuse (quantity 0, a coil value other than 0000/FF00) unless writes are allowed, where it is
// the plain request. nullopt for codes not probed.
std::optional<std::vector<std::uint8_t>> probe_request(std::uint8_t function, bool allow_writes);

// Adds to `ranges` the addresses `request` reached when `answer` is its normal answer (read data
// of the size asked, a write's echo); returns whether it was. Exceptions, other function codes
// and answers that do not fit the request add nothing.
bool note_answered(std::span<const std::uint8_t> request, std::span<const std::uint8_t> answer,
                   AnsweredRanges& ranges);

// Fails with one line when no holding register answers FC 03 (nothing to check liveness with).
// The register is looked for before the probes and read again after each: a device that answered
// it before a probe and answers it no more after is left in `out.killed_by`, with no failure.
std::optional<std::string> reconnoitre(const Ask& ask, const ReconOptions& options, Recon& out);

}  // namespace mblab::robustness
