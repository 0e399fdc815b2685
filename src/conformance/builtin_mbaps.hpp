#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "client/target.hpp"
#include "conformance/builtin_device.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/dut.hpp"
#include "security/temporary_pki.hpp"

// What `mblab conform` without a target tests over Modbus/TCP Security when a suite asks for it.
namespace mblab::conformance {

// Whether any case of `suites` runs a Modbus/TCP Security procedure.
bool uses_mbaps(const std::vector<Suite>& suites);

// The built-in device's Modbus/TCP Security side, for the security suite: a lab PKI made for the
// run in a directory of its own (removed afterwards), and the reference device a second time
// behind TLS, with the profile's [[role]] rules. A second device rather than a second listener
// on the first, because each BackgroundServer calls its device from its own thread.
class BuiltinMbaps {
  public:
    // Starts it; "" when it runs, else why not. `dut` gets the PKI and the tester's certificate.
    std::string start(const std::filesystem::path& profile, Dut& dut, client::Target& secure);

  private:
    security::TemporaryPki pki_;  // destroyed last: the server is stopped before it goes
    BuiltinDevice device_;
};

}  // namespace mblab::conformance
