#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "device/reference_device.hpp"

// Reference devices for tests, from a shipped profile or from profile text. A profile that does
// not load fails the test that asked for it.
namespace mblab::test {

// Loads profiles/<name>.toml from the source tree.
std::unique_ptr<device::ReferenceDevice> shipped_device(std::string_view name);
// Loads profile text.
std::unique_ptr<device::ReferenceDevice> device_from(std::string_view toml);
// The loader's error for profile text ("" if it loaded).
std::string profile_error(std::string_view toml);

}  // namespace mblab::test
