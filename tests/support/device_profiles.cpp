#include "support/device_profiles.hpp"

#include <gtest/gtest.h>

#include <utility>

namespace mblab::test {
namespace {

template <class Loaded>
std::unique_ptr<device::ReferenceDevice> device_or_failure(Loaded loaded) {
    if (!loaded) {
        ADD_FAILURE() << loaded.error();
        return nullptr;
    }
    return std::move(loaded).value();
}

}  // namespace

std::unique_ptr<device::ReferenceDevice> shipped_device(std::string_view name) {
    return device_or_failure(device::load_profile(std::string(MBLAB_SOURCE_DIR) + "/profiles/" +
                                                  std::string(name) + ".toml"));
}

std::unique_ptr<device::ReferenceDevice> device_from(std::string_view toml) {
    return device_or_failure(device::load_profile_text(toml, "test.toml"));
}

std::string profile_error(std::string_view toml) {
    auto loaded = device::parse_profile(toml, "test.toml");
    return loaded ? std::string() : loaded.error();
}

}  // namespace mblab::test
