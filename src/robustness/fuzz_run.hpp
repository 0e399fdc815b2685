#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "client/link.hpp"
#include "client/target.hpp"
#include "robustness/case_generator.hpp"
#include "robustness/case_links.hpp"
#include "robustness/fuzz_case.hpp"
#include "robustness/liveness.hpp"
#include "robustness/monitor_cases.hpp"
#include "robustness/recon.hpp"
#include "robustness/run_clock.hpp"

// A robustness run: cases from the generator, the liveness oracle after each (or every N), and a
// finding minimised by replaying from a restarted device. How the cases and the check reach the
// device over the target's framing is the run's links' business (robustness/case_links.hpp).
namespace mblab::robustness {

struct FuzzOptions {
    client::Target target;
    std::uint64_t seed = 1;
    std::optional<std::size_t> cases;                   // budget: this many cases
    std::optional<std::chrono::milliseconds> duration;  // budget: this long
    double rate = 200;                                  // sends per second at most (0: no limit)
    std::size_t check_every = 1;                        // the liveness check after every N cases
    std::chrono::milliseconds timeout{1000};
    // How long each case's connections are read for answers before they are closed.
    std::chrono::milliseconds settle{10};
    // On a line: how long it must stay silent before the check asks (at least t3.5).
    std::chrono::milliseconds quiet{5};
    // Restarts the device (the user's --restart command); empty when none was given.
    std::function<bool()> restart;
    std::chrono::milliseconds restart_patience{10000};
    // Record every finding instead of stopping at the first: after each, the device is restarted
    // (or, without a restart command, waited for up to restart_patience) and the run goes on.
    bool keep_going = false;
    // How links to the device open: client::open_link on the target when unset (tests give a
    // memory link); the target still names the run and its framing.
    Dial dial;
    RunClock clock;
    // Record each case's time in the result (an essential-function monitor lays its missed
    // cycles against them).
    bool timeline = false;
};

struct ClassTally {
    std::size_t run = 0;
    std::size_t withheld = 0;         // left out: they would write outside the writable range
    std::string_view not_applicable;  // why the class is not tried over the target's framing
};

// Which case a step came from.
struct StepOrigin {
    BadInput kind = BadInput::Mutation;
    std::string case_name;
    std::size_t case_number = 0;
};

// The case after which the check failed, until minimisation names the case whose frames kill.
struct Finding {
    BadInput kind = BadInput::Mutation;
    std::string case_name;
    std::size_t case_number = 0;
    std::string reason;
    std::chrono::milliseconds waited{0};
    std::vector<Step> since_check;    // every step since the last good check, in order
    std::vector<StepOrigin> origins;  // of each step of since_check
    std::vector<Step> reproducer;     // the shortest that still kills, or since_check
    std::string minimise_note;
    bool minimised = false;
};

// What a flood's ledger saw: the last write the device acknowledged and what it reads back.
struct LedgerTally {
    std::size_t floods = 0;          // floods whose register was read back
    std::size_t acknowledged = 0;    // FC 06 answers received in them
    std::size_t unacknowledged = 0;  // floods whose writes the device refused or did not answer
};

// The device's memory, when it runs on this machine and the user named its process.
struct DeviceMemory {
    int pid = 0;
    std::size_t start_kb = 0;  // resident at the start
    std::size_t end_kb = 0;    // resident at the end
    std::size_t peak_kb = 0;   // the process's high-water mark (VmHWM)
};

struct FuzzResult {
    std::string target;
    std::uint64_t seed = 1;
    Recon recon;
    std::size_t cases = 0;
    std::size_t checks = 0;
    std::size_t sends = 0;
    std::array<ClassTally, kBadInputCount> classes{};
    std::chrono::milliseconds longest_wait{0};  // the oracle's longest check
    std::chrono::milliseconds elapsed{0};
    std::vector<Finding> findings;  // in the order found; one at most without keep_going
    // "case budget", "time budget", "every chosen case", "finding", "interrupted", or "finding;
    // the device did not come back" when keep_going could not go on.
    std::string stopped_by;
    bool one_connection_at_a_time = false;  // the bystander check was dropped
    LedgerTally ledger;
    std::optional<DeviceMemory> memory;
    // Each case's time, in order, with FuzzOptions::timeline: from its first frame to the next
    // case's (its check included), the last to the run's end.
    std::vector<CaseSpan> timeline;
};

// Told of each case as it starts (the console's progress line).
using FuzzProgress = std::function<void(const FuzzResult&, const FuzzCase&)>;

class FuzzRunner {
  public:
    FuzzRunner(FuzzOptions options, Recon recon, client::LinkObserver* observer);

    FuzzResult run(CaseGenerator& generator, const FuzzProgress& progress,
                   const std::function<bool()>& stop);
    // Sends `steps` as a reproducer does, then asks the oracle.
    Liveness replay(const std::vector<Step>& steps);

  private:
    void pace();
    // The steps of a case or a replay, each on its connection's link.
    void send_steps(const std::vector<Step>& steps, bool hold,
                    const std::optional<WriteLedger>& ledger = std::nullopt);
    // After a flood with a ledger: why the register read back betrays a lost write, or "".
    std::string check_ledger(const WriteLedger& ledger, std::uint16_t acknowledged,
                             std::uint16_t highest_sent, FuzzResult& result);
    void minimise_finding(Finding& finding);
    // After a finding with keep_going: the device restarted or back by itself, the bystander
    // open again; false when it did not come back.
    bool recover();

    FuzzOptions options_;
    Recon recon_;
    client::Framing framing_;
    std::unique_ptr<CaseLinks> links_;
    LivenessOracle oracle_;
    std::uint16_t acknowledged_ = 0;  // by the last case's flood
    Clock::time_point next_send_{};
    std::size_t sends_ = 0;
};

}  // namespace mblab::robustness
