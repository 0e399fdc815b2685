#include "conformance/builtin_device.hpp"

#include <fmt/format.h>

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
    device_ = std::make_unique<device::ReferenceDevice>(std::move(loaded.value()));
    server_ = std::make_unique<server::BackgroundServer>(*device_);
    auto port = server_->start();
    if (!port) return "cannot start the reference device: " + port.error();
    target.tcp = client::Endpoint{"127.0.0.1", *port, nullptr};
    target.name = fmt::format("tcp://127.0.0.1:{}", *port);
    return {};
}

}  // namespace mblab::conformance
