#include "conformance/builtin_device.hpp"

#include <fmt/format.h>

#include <utility>

#include "conformance/device_dut.hpp"
#include "device/profile_loader.hpp"

namespace mblab::conformance {

BuiltinDevice::~BuiltinDevice() {
    // The server calls the device from its thread: it ends first.
    server_.reset();
}

std::string BuiltinDevice::start(const std::filesystem::path& profile, Dut& dut,
                                 client::Target& target) {
    auto loaded = device::read_profile(profile);
    if (!loaded) return loaded.error();
    dut = dut_from_profile(*loaded, "profile " + profile.filename().string());
    auto port = serve(std::move(loaded.value()), {});
    if (!port) return "cannot start the reference device: " + port.error();
    target.tcp = client::Endpoint{"127.0.0.1", *port, nullptr};
    target.name = fmt::format("tcp://127.0.0.1:{}", *port);
    return {};
}

protocol::Result<std::uint16_t, std::string> BuiltinDevice::serve(device::Profile profile,
                                                                  server::ServerOptions options) {
    server_.reset();  // it serves the device about to be replaced
    device_ = std::make_unique<device::ReferenceDevice>(std::move(profile));
    server_ = std::make_unique<server::BackgroundServer>(*device_, std::move(options));
    return server_->start();
}

}  // namespace mblab::conformance
