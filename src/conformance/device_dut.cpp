#include "conformance/device_dut.hpp"

#include <array>
#include <optional>
#include <string>

#include "protocol/function_code.hpp"

namespace mblab::conformance {

namespace {

const std::vector<device::RangeSpec>& bank(const device::UnitSpec& spec, device::BankKind kind) {
    return spec.banks[static_cast<std::size_t>(kind)];
}

// Addresses readable from 0 without a hole, as FC 01..04 see them.
std::optional<std::uint32_t> readable_from_zero(const device::UnitSpec& spec,
                                                device::BankKind kind) {
    std::uint32_t end = 0;
    for (const auto& range : bank(spec, kind)) {
        if (range.start != end || range.access == device::Access::WriteOnly) break;
        end = range.start + range.count;
    }
    if (end == 0) return std::nullopt;
    return end;
}

// Whether FC 05/06 may write `address`: it lies in a range that takes writes.
bool writable(const device::UnitSpec& spec, device::BankKind kind, std::uint32_t address) {
    for (const auto& range : bank(spec, kind)) {
        if (address >= range.start && address < range.start + range.count) {
            return range.access != device::Access::ReadOnly;
        }
    }
    return false;
}

// A read-only address whose writes the unit refuses with an exception [EPS Access to Variables];
// lenient units accept and ignore such writes, so they declare none.
std::optional<std::uint16_t> refused_read_only(const device::UnitSpec& spec,
                                               device::BankKind kind) {
    if (!spec.access_policy.write_read_only) return std::nullopt;
    for (const auto& range : bank(spec, kind)) {
        if (range.access == device::Access::ReadOnly && range.count > 0) {
            return static_cast<std::uint16_t>(range.start);
        }
    }
    return std::nullopt;
}

// The first role of the profile's [[role]] rules that may read holding register 0x0010 and, as
// `writes` asks, may or may not write it: what the security suite's role cases need declared.
std::string role_that(const device::Profile& profile, std::uint8_t unit, bool writes) {
    constexpr std::array<std::uint8_t, 5> kRead = {0x03, 0x00, 0x10, 0x00, 0x01};
    constexpr std::array<std::uint8_t, 5> kWrite = {0x06, 0x00, 0x10, 0x00, 0x00};
    const device::RoleRules rules(profile.roles);
    for (const auto& rule : profile.roles) {
        const std::optional<std::string> role = rule.role;
        if (rules.permits(role, unit, kRead) && rules.permits(role, unit, kWrite) == writes) {
            return rule.role;
        }
    }
    return {};
}

}  // namespace

Dut dut_from_profile(const device::Profile& profile, std::string declared_by) {
    const device::UnitSpec& spec = profile.units.front();
    Dut dut;
    dut.declared_by = std::move(declared_by);
    dut.unit = spec.id;
    dut.registers = readable_from_zero(spec, device::BankKind::HoldingRegisters);
    dut.max_read = spec.max_read_registers;
    dut.object_messaging =
        spec.functions[static_cast<std::size_t>(protocol::FunctionCode::ObjectMessaging)];
    dut.alternate_encoding = spec.semi_signature.has_value();
    dut.coils = readable_from_zero(spec, device::BankKind::Coils);
    dut.discrete_inputs = readable_from_zero(spec, device::BankKind::DiscreteInputs);
    dut.input_registers = readable_from_zero(spec, device::BankKind::InputRegisters);
    dut.read_only_register = refused_read_only(spec, device::BankKind::HoldingRegisters);
    dut.read_only_coil = refused_read_only(spec, device::BankKind::Coils);
    if (!spec.fifos.empty()) {
        dut.fifo_address = spec.fifos.front();
        dut.fifo_count_writable =
            writable(spec, device::BankKind::HoldingRegisters, spec.fifos.front());
    }
    if (!spec.files.empty()) dut.file_number = spec.files.front().number;
    dut.echo_max_words = spec.diagnostics.echo_max_words;
    dut.security.read_only_role = role_that(profile, spec.id, false);
    dut.security.write_role = role_that(profile, spec.id, true);
    return dut;
}

}  // namespace mblab::conformance
