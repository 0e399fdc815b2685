#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

// Modbus/TCP Security authorization ([SEC]): what a client's role may ask of the device. The role
// comes from the client's certificate; these rules come from the profile's [[role]] tables. Deny
// by default: a request no rule of its role allows is refused (the server answers exception 01),
// and a client without a role (no role in its certificate) is refused everything.
namespace mblab::device {

enum class RoleAccess : std::uint8_t {
    Any,    // the codes listed, reading or writing
    Read,   // only codes that change nothing (the function table's "writes" column)
    Write,  // only codes that change data
};

struct RoleRule {
    std::string role;  // compared exactly (case matters, as in the certificate)
    // The codes allowed; empty: every code, user-defined ones included.
    std::vector<std::uint8_t> functions;
    RoleAccess access = RoleAccess::Any;
    std::vector<std::uint8_t> units;  // empty: every unit
    // Only requests whose data addresses all lie inside [first, last]; a request naming no
    // address passes, one whose addresses cannot be read (a malformed PDU) does not.
    std::optional<std::uint16_t> first_address;
    std::optional<std::uint16_t> last_address;
};

class RoleRules {
  public:
    RoleRules() = default;
    explicit RoleRules(std::vector<RoleRule> rules) : rules_(std::move(rules)) {}

    // Whether `role` (none: the client's certificate names no role) may send `pdu` to `unit`.
    bool permits(const std::optional<std::string>& role, std::uint8_t unit,
                 std::span<const std::uint8_t> pdu) const;
    bool has_role(std::string_view role) const;
    bool empty() const { return rules_.empty(); }
    const std::vector<RoleRule>& rules() const { return rules_; }

  private:
    std::vector<RoleRule> rules_;
};

}  // namespace mblab::device
