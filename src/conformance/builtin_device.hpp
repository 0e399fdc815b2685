#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "client/target.hpp"
#include "conformance/dut.hpp"
#include "device/reference_device.hpp"
#include "protocol/result.hpp"
#include "server/background_server.hpp"

// What `mblab conform` without a target tests: the reference device on a loopback port of its
// own, declared as its profile describes it.
namespace mblab::conformance {

class BuiltinDevice {
  public:
    BuiltinDevice() = default;
    BuiltinDevice(const BuiltinDevice&) = delete;
    BuiltinDevice& operator=(const BuiltinDevice&) = delete;
    ~BuiltinDevice();

    // Loads the profile, declares `dut` from it and starts the device; "" when it runs, else
    // one line saying why not. `target` gets its tcp:// address.
    std::string start(const std::filesystem::path& profile, Dut& dut, client::Target& target);
    // Starts the device of `profile` as `options` say (TLS, roles): the port it listens on.
    protocol::Result<std::uint16_t, std::string> serve(device::Profile profile,
                                                       server::ServerOptions options);

  private:
    std::unique_ptr<device::ReferenceDevice> device_;
    std::unique_ptr<server::BackgroundServer> server_;
};

}  // namespace mblab::conformance
