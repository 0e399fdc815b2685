#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "conformance/dut.hpp"

// Where a report came from, so that a report read months later can be tied to the build, the
// invocation, the declarations and the device it judged. The command line reaches this layer
// already split into words: parsing it is the cli's business.
namespace mblab::conformance {

class Session;

// The device's own answer to read device identification (FC 2B / 0E, basic stream).
struct DeviceIdentity {
    bool answered = false;
    std::string vendor_name;   // object 00
    std::string product_code;  // object 01
    std::string revision;      // object 02 (MajorMinorRevision)
    std::string reason;        // when not answered: what came instead
};

// One DUT fact and where its value came from: "defaults", "flags", a DUT file's path, "profile
// reference.toml", "the lab PKI made for the run".
struct Declaration {
    std::string key;  // as dut_keys() names it
    std::variant<bool, std::uint32_t, std::string> value;
    std::string source;
};

struct Provenance {
    std::string version;  // mblab's, as --version prints it
    std::string commit;   // the git commit the binary was built from, or "unknown"
    std::string started;  // UTC, ISO 8601
    std::string finished;
    std::vector<std::string> command_line;  // argv as given
    std::string declared_by;                // Dut::declared_by
    std::vector<Declaration> declarations;
    DeviceIdentity device;
};

// "2026-11-24T08:54:31Z".
std::string iso8601_utc(std::chrono::system_clock::time_point time);

// Every key of `dut` that holds a value, in dut_keys() order, with the source `source_of` names.
std::vector<Declaration> declarations_of(
    const Dut& dut, const std::function<std::string(std::string_view)>& source_of);

// The top-level keys a DUT file sets (already checked by load_dut_file); empty when unreadable.
std::vector<std::string> dut_file_keys(const std::string& path);

// Asks the device once, over the run's session, for the basic identification stream (read code
// 01 from object 00). Whatever happens, the answer is a DeviceIdentity: a device that does not
// implement FC 2B, stays silent or closes the connection is "not answered", never a failed run.
DeviceIdentity ask_device_identity(Session& session);

// The argv words joined as a POSIX shell would need them quoted to run them again.
std::string shell_words(const std::vector<std::string>& words);

// "not answered (...)" or the three objects, for one-line uses.
std::string identity_text(const DeviceIdentity& identity);

// A declaration's value as text: true/false, decimal, or the string itself.
std::string value_text(const Declaration& declaration);

// The provenance as lines of "name: value", for formats whose metadata is free text.
std::vector<std::string> provenance_lines(const Provenance& provenance);

}  // namespace mblab::conformance
