// Random request PDUs into the reference device (profiles/reference.toml): it must never crash,
// read out of bounds or write past the response buffer, whatever the unit id, link or state.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>

#include "device/profile_paths.hpp"
#include "device/reference_device.hpp"

namespace {

mblab::device::ReferenceDevice& device() {
    static std::unique_ptr<mblab::device::ReferenceDevice> instance = [] {
        std::filesystem::path path =
            std::filesystem::path(MBLAB_SOURCE_DIR) / "profiles" / "reference.toml";
        if (std::getenv("MBLAB_PROFILES_DIR")) path = mblab::device::default_profile_path();
        auto loaded = mblab::device::load_profile(path);
        if (!loaded) {
            std::fprintf(stderr, "%s\n", loaded.error().c_str());
            std::abort();
        }
        return std::move(loaded).value();
    }();
    return *instance;
}

}  // namespace

// The first byte picks the link and unit id; the rest is the request PDU.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    static constexpr std::array<std::uint8_t, 4> kUnits = {1, 0, 0xFF, 2};
    mblab::device::RequestContext context;
    context.link = (data[0] & 0x80) ? mblab::device::Link::Serial : mblab::device::Link::Tcp;
    context.unit = kUnits[data[0] & 0x03];
    if (data[0] & 0x40) device().counters().count_crc_error();
    if (data[0] & 0x20) device().counters().count_overrun();
    std::array<std::uint8_t, 253> response{};
    const auto reply = device().handle(context, std::span(data + 1, size - 1), response);
    if (reply.size > response.size()) std::abort();
    return 0;
}
