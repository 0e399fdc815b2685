// The authorization rules of Modbus/TCP Security from any profile text, then any request judged
// by them: loading must refuse bad [[role]] tables with a message, never crash, and a loaded rule
// set must decide every request for every role without reading past the PDU.
//
// Input: TOML text, a NUL byte, then requests as [role index][unit][length][PDU bytes]...
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "device/profile_loader.hpp"
#include "device/role_rules.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto* end = static_cast<const std::uint8_t*>(std::memchr(data, 0, size));
    const std::size_t text_size = end ? static_cast<std::size_t>(end - data) : size;
    // A unit is added so that profiles fail on their [[role]] tables, not on a missing [[unit]].
    const std::string text =
        std::string(reinterpret_cast<const char*>(data), text_size) + "\n[[unit]]\nid = 1\n";
    auto loaded = mblab::device::parse_profile(text, "fuzz.toml");
    if (!loaded) return 0;
    const mblab::device::RoleRules rules(loaded.value().roles);
    std::span<const std::uint8_t> rest(data + text_size, size - text_size);
    if (!rest.empty()) rest = rest.subspan(1);
    while (rest.size() >= 3) {
        const std::size_t role_index = rest[0];
        const std::uint8_t unit = rest[1];
        const std::size_t length = std::min<std::size_t>(rest[2], rest.size() - 3);
        const auto pdu = rest.subspan(3, length);
        std::optional<std::string> role;
        if (role_index < rules.rules().size()) role = rules.rules()[role_index].role;
        if (role_index == rules.rules().size()) role = std::string("unlisted");
        (void)rules.permits(role, unit, pdu);
        rest = rest.subspan(3 + length);
    }
    return 0;
}
