#pragma once

#include <string>
#include <vector>

#include "robustness/scan.hpp"

// What `mblab scan` learned, as the declarations of a DUT file (docs/catalogue.md, "The device
// under test") and as the console's table: one list of facts, so both say the same.
namespace mblab::robustness {

// One DUT key: the value learned and what it was learned from; without a value, why it is not
// declared.
struct LearnedFact {
    std::string key;    // as dut_keys() names it
    std::string value;  // TOML: "65536", "true"; empty: not declared
    std::string why;    // "FC 03 answered 0..65535, read whole in reads of 125"
};

std::vector<LearnedFact> learned_facts(const DeviceScan& scan);

// What the file's opening comment names: where and when the scan ran, and which mblab ran it.
struct ScanOrigin {
    std::string target;
    std::string version;
    std::string started;  // UTC, ISO 8601
};

// A DUT file `mblab conform --dut` reads: each declared key with "# learned by mblab scan: ..."
// beside it, the keys not declared as comments saying why, and what the scan saw that no key
// holds (units, function codes, identification) in the opening comment.
std::string scan_dut_toml(const DeviceScan& scan, const ScanOrigin& origin);

// The console's summary: units, function codes, then a row per fact.
std::string scan_text(const DeviceScan& scan);

}  // namespace mblab::robustness
