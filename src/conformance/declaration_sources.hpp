#pragma once

#include <chrono>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "conformance/dut.hpp"
#include "conformance/provenance.hpp"

// Where each declaration of the device under test came from, for the reports' provenance, and
// the declarations a lab PKI directory makes by itself.
namespace mblab::conformance {

// A key nobody set since the last reset comes from `base` (the built-in device's profile, or
// the defaults).
class DeclarationSources {
  public:
    explicit DeclarationSources(std::string base) : base_(std::move(base)) {}
    void reset(std::string base);
    void set(std::string_view key, std::string source);
    std::string operator()(std::string_view key) const;

  private:
    std::string base_;
    std::map<std::string, std::string> sources_;
};

// A lab PKI made by `mblab pki` holds the tester's own certificate (client-Administrator) and
// the CA: they are taken from it where the declarations name none.
void take_client_files_from_pki(Dut& dut, DeclarationSources& sources);

// What mblab says of itself in a report's provenance.
struct ToolIdentity {
    std::string version;
    std::string commit;
    std::vector<std::string> argv;
};

// What the reports say about where they came from. The device is asked who it is after the run,
// so the question cannot change any verdict; an interrupted run is not kept waiting for it.
Provenance make_provenance(const ToolIdentity& tool, Session& session,
                           const DeclarationSources& sources,
                           std::chrono::system_clock::time_point started, bool interrupted);

}  // namespace mblab::conformance
