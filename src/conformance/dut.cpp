#include "conformance/dut.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>

#include "conformance/toml_reader.hpp"
#include "transport/serial_url.hpp"

namespace mblab::conformance {

namespace {

constexpr std::uint32_t kAddressSpace = 65536;
constexpr std::uint16_t kPolicyOutOfRange = 0x8001;  // CTP 9.1.2.2

std::vector<std::uint8_t> be16(std::uint32_t value) {
    return {static_cast<std::uint8_t>(value >> 8), static_cast<std::uint8_t>(value & 0xFF)};
}

template <class T>
DutValue declared(const std::optional<T>& value) {
    if (!value) return {};
    return static_cast<std::uint32_t>(*value);
}

DutValue declared(const std::string& text) {
    if (text.empty()) return {};
    return text;
}

std::string joined(const std::vector<std::string>& settings) {
    std::string all;
    for (const auto& setting : settings)
        all += (all.empty() ? "" : ", ") + setting;
    return all;
}

// Every key of a DUT file, in the order the reports list them, and what the Dut holds for it.
struct DutKey {
    std::string_view name;
    DutValue (*value)(const Dut& dut);
};

constexpr std::array kDutKeys = {
    DutKey{"unit", [](const Dut& d) -> DutValue { return std::uint32_t{d.unit}; }},
    DutKey{"registers", [](const Dut& d) { return declared(d.registers); }},
    DutKey{"max_read", [](const Dut& d) -> DutValue { return std::uint32_t{d.max_read}; }},
    DutKey{"object_messaging", [](const Dut& d) -> DutValue { return d.object_messaging; }},
    DutKey{"alternate_encoding", [](const Dut& d) -> DutValue { return d.alternate_encoding; }},
    DutKey{"coils", [](const Dut& d) { return declared(d.coils); }},
    DutKey{"discrete_inputs", [](const Dut& d) { return declared(d.discrete_inputs); }},
    DutKey{"input_registers", [](const Dut& d) { return declared(d.input_registers); }},
    DutKey{"read_only_register", [](const Dut& d) { return declared(d.read_only_register); }},
    DutKey{"read_only_coil", [](const Dut& d) { return declared(d.read_only_coil); }},
    DutKey{"fifo_address", [](const Dut& d) { return declared(d.fifo_address); }},
    DutKey{"fifo_count_writable", [](const Dut& d) -> DutValue { return d.fifo_count_writable; }},
    DutKey{"file_number", [](const Dut& d) { return declared(d.file_number); }},
    DutKey{"echo_max_words", [](const Dut& d) { return declared(d.echo_max_words); }},
    DutKey{"other_address", [](const Dut& d) { return declared(d.other_address); }},
    DutKey{"turnaround_ms", [](const Dut& d) { return declared(d.turnaround_ms); }},
    DutKey{"line_settings", [](const Dut& d) { return declared(joined(d.line_settings)); }},
    DutKey{"pki", [](const Dut& d) { return declared(d.security.pki); }},
    DutKey{"client_cert", [](const Dut& d) { return declared(d.security.client.cert); }},
    DutKey{"client_key", [](const Dut& d) { return declared(d.security.client.key); }},
    DutKey{"ca", [](const Dut& d) { return declared(d.security.client.ca); }},
    DutKey{"read_only_role", [](const Dut& d) { return declared(d.security.read_only_role); }},
    DutKey{"write_role", [](const Dut& d) { return declared(d.security.write_role); }},
    DutKey{"null_role_granted",
           [](const Dut& d) -> DutValue { return d.security.null_role_granted; }},
};

// Numbers `requires` can compare: booleans count as 1 when declared true, and names, paths and
// line settings only say whether they were given.
std::optional<std::int64_t> number_of(const Dut& dut, std::string_view name) {
    const DutValue value = dut_value(dut, name);
    if (const auto* number = std::get_if<std::uint32_t>(&value)) return *number;
    if (const auto* yes = std::get_if<bool>(&value)) {
        return *yes ? std::optional<std::int64_t>(1) : std::nullopt;
    }
    if (std::holds_alternative<std::string>(value)) return 1;
    return std::nullopt;
}

// CTP 9.1.2: 0x8001 unless that offset is valid; then the first offset past the end, or,
// when all 65536 offsets are valid, a two-register read from the last one.
std::vector<std::uint8_t> out_of_range_read(const Dut& dut) {
    std::uint32_t offset = kPolicyOutOfRange;
    std::uint32_t count = 1;
    if (dut.registers && *dut.registers > kPolicyOutOfRange) {
        if (*dut.registers < kAddressSpace) {
            offset = *dut.registers;
        } else {
            offset = kAddressSpace - 1;
            count = 2;
        }
    }
    auto out = be16(offset);
    auto tail = be16(count);
    out.insert(out.end(), tail.begin(), tail.end());
    return out;
}

std::vector<std::uint8_t> echo_words(std::uint32_t words) {
    std::vector<std::uint8_t> out;
    for (std::uint32_t i = 0; i < words; ++i) {
        // Distinct words so a device that reorders or truncates the echo is caught.
        out.push_back(static_cast<std::uint8_t>(0xA0 + (i >> 8)));
        out.push_back(static_cast<std::uint8_t>(i & 0xFF));
    }
    return out;
}

constexpr std::array kComputedFacts = {std::string_view("out_of_range_registers"),
                                       std::string_view("echo_max_data"),
                                       std::string_view("echo_over_data")};

constexpr std::string_view kMbapRequirement = "mbap";
// The serial-line suite's cases: "line" needs a serial framing, "ascii" the ASCII one.
constexpr std::string_view kLineRequirement = "line";
constexpr std::string_view kAsciiRequirement = "ascii";
// The line-timing cases: a serial port (RTU or ASCII), where silence delimits frames.
constexpr std::string_view kSerialPortRequirement = "serial_port";

}  // namespace

const std::vector<std::string_view>& dut_keys() {
    static const std::vector<std::string_view> keys = [] {
        std::vector<std::string_view> out;
        for (const auto& key : kDutKeys)
            out.push_back(key.name);
        return out;
    }();
    return keys;
}

DutValue dut_value(const Dut& dut, std::string_view key) {
    for (const auto& known : kDutKeys) {
        if (known.name == key) return known.value(dut);
    }
    return {};
}

bool is_known_fact(std::string_view name) {
    const auto& keys = dut_keys();
    return std::find(keys.begin(), keys.end(), name) != keys.end() ||
           std::find(kComputedFacts.begin(), kComputedFacts.end(), name) != kComputedFacts.end();
}

std::optional<std::vector<std::uint8_t>> DutFacts::fact(std::string_view name) const {
    if (name == "unit") return std::vector<std::uint8_t>{dut_.unit};
    if (name == "out_of_range_registers") return out_of_range_read(dut_);
    if (name == "echo_max_data" || name == "echo_over_data") {
        if (!dut_.echo_max_words) return std::nullopt;
        return echo_words(*dut_.echo_max_words + (name == "echo_over_data" ? 1U : 0U));
    }
    // A path or a text (client_cert, line_settings) is no request field: only `requires` asks
    // whether it was declared.
    if (std::holds_alternative<std::string>(dut_value(dut_, name))) return std::nullopt;
    auto value = number_of(dut_, name);
    if (!value) return std::nullopt;
    return be16(static_cast<std::uint32_t>(*value));
}

protocol::Result<Dut, std::string> load_dut_file(const std::string& path) {
    TomlReader reader(path);
    auto table = reader.parse_file();
    Dut dut;
    dut.declared_by = path;
    std::int64_t unit = dut.unit;
    std::int64_t max_read = dut.max_read;
    bool ok = table && reader.only_keys(*table, dut_keys()) &&
              reader.get(*table, "unit", unit, 0, 255) &&
              reader.get_number(*table, "registers", dut.registers, 1, kAddressSpace) &&
              reader.get(*table, "max_read", max_read, 1, 125) &&
              reader.get(*table, "object_messaging", dut.object_messaging) &&
              reader.get(*table, "alternate_encoding", dut.alternate_encoding) &&
              reader.get_number(*table, "coils", dut.coils, 1, kAddressSpace) &&
              reader.get_number(*table, "discrete_inputs", dut.discrete_inputs, 1, kAddressSpace) &&
              reader.get_number(*table, "input_registers", dut.input_registers, 1, kAddressSpace) &&
              reader.get_number(*table, "read_only_register", dut.read_only_register, 0, 65535) &&
              reader.get_number(*table, "read_only_coil", dut.read_only_coil, 0, 65535) &&
              reader.get_number(*table, "fifo_address", dut.fifo_address, 0, 65535) &&
              reader.get(*table, "fifo_count_writable", dut.fifo_count_writable) &&
              reader.get_number(*table, "file_number", dut.file_number, 1, 65535) &&
              reader.get_number(*table, "echo_max_words", dut.echo_max_words, 1, 124) &&
              reader.get_number(*table, "other_address", dut.other_address, 1, 247) &&
              reader.get_number(*table, "turnaround_ms", dut.turnaround_ms, 0, 60000);
    std::vector<std::pair<std::string, const toml::node*>> settings;
    ok = ok && reader.get_strings(*table, "line_settings", settings);
    for (const auto& [setting, node] : settings) {
        if (!ok) break;
        if (auto why = transport::line_settings_error(setting)) {
            ok = reader.fail(node, "line_settings: '" + setting + "': " + *why);
        } else {
            dut.line_settings.push_back(setting);
        }
    }
    SecurityDut& security = dut.security;
    ok = ok && reader.get(*table, "pki", security.pki) &&
         reader.get(*table, "client_cert", security.client.cert) &&
         reader.get(*table, "client_key", security.client.key) &&
         reader.get(*table, "ca", security.client.ca) &&
         reader.get(*table, "read_only_role", security.read_only_role) &&
         reader.get(*table, "write_role", security.write_role) &&
         reader.get(*table, "null_role_granted", security.null_role_granted);
    if (!ok) return reader.error();
    // Paths in the file are relative to the file, so it can travel with its certificates.
    const auto base = std::filesystem::path(path).parent_path();
    for (std::string* file :
         {&security.pki, &security.client.cert, &security.client.key, &security.client.ca}) {
        if (!file->empty() && std::filesystem::path(*file).is_relative()) {
            *file = (base / *file).lexically_normal().string();
        }
    }
    dut.unit = static_cast<std::uint8_t>(unit);
    dut.max_read = static_cast<std::uint16_t>(max_read);
    return dut;
}

protocol::Result<Requirement, std::string> parse_requirement(std::string_view text) {
    Requirement out;
    out.text = std::string(text);
    std::size_t i = 0;
    auto skip_space = [&] {
        while (i < text.size() && text[i] == ' ')
            ++i;
    };
    skip_space();
    std::size_t start = i;
    while (i < text.size() && (std::islower(static_cast<unsigned char>(text[i])) || text[i] == '_'))
        ++i;
    out.fact = std::string(text.substr(start, i - start));
    if (!is_known_fact(out.fact) && out.fact != kMbapRequirement && out.fact != kLineRequirement &&
        out.fact != kAsciiRequirement && out.fact != kSerialPortRequirement) {
        return fmt::format("requirement '{}' names no DUT fact", text);
    }
    skip_space();
    if (i == text.size()) return out;
    for (std::string_view op : {">=", "<=", "==", "!=", ">", "<"}) {
        if (text.substr(i, op.size()) == op) {
            out.op = std::string(op);
            i += op.size();
            break;
        }
    }
    skip_space();
    std::string_view number = text.substr(i);
    if (out.op.empty() || number.empty() || !std::all_of(number.begin(), number.end(), [](char c) {
            return std::isdigit(static_cast<unsigned char>(c));
        })) {
        return fmt::format("requirement '{}' is not 'fact' or 'fact OP number'", text);
    }
    out.value = std::stoll(std::string(number));
    return out;
}

std::optional<Unmet> unmet(const Requirement& requirement, const Dut& dut) {
    if (requirement.fact == kMbapRequirement) {
        if (dut.serial_framing.empty()) return std::nullopt;
        return Unmet{fmt::format("a Modbus/TCP (MBAP) test; the device is reached over {}",
                                 dut.serial_framing),
                     ""};
    }
    if (requirement.fact == kLineRequirement && dut.serial_framing.empty())
        return Unmet{"a serial-line test; the device is reached over Modbus/TCP", ""};
    if (requirement.fact == kAsciiRequirement && dut.serial_framing != "ASCII") {
        return Unmet{fmt::format("an ASCII framing test; the device is reached over {}",
                                 dut.serial_framing.empty() ? "Modbus/TCP" : dut.serial_framing),
                     ""};
    }
    if (requirement.fact == kSerialPortRequirement &&
        (dut.serial_framing.empty() || dut.serial_framing == "RTU over TCP")) {
        return Unmet{dut.serial_framing.empty()
                         ? "a line-timing test; the device is reached over Modbus/TCP"
                         : "a line-timing test; over RTU over TCP frames are cut by their "
                           "length, not by silence on a line",
                     ""};
    }
    if (requirement.fact == kLineRequirement || requirement.fact == kAsciiRequirement ||
        requirement.fact == kSerialPortRequirement)
        return std::nullopt;
    auto value = number_of(dut, requirement.fact);
    if (!value) {
        return Unmet{fmt::format("the DUT does not declare {}", requirement.fact),
                     requirement.fact};
    }
    if (requirement.op.empty()) return std::nullopt;
    const std::int64_t v = *value;
    const std::int64_t want = requirement.value;
    bool met = requirement.op == ">="   ? v >= want
               : requirement.op == "<=" ? v <= want
               : requirement.op == ">"  ? v > want
               : requirement.op == "<"  ? v < want
               : requirement.op == "==" ? v == want
                                        : v != want;
    if (met) return std::nullopt;
    return Unmet{
        fmt::format("needs {}; the DUT declares {} = {}", requirement.text, requirement.fact, v),
        ""};
}

std::optional<std::string> settle_serial_unit(Dut& dut, bool declared, std::string_view target) {
    if (!declared) dut.unit = 1;
    const unsigned unit = dut.unit;
    if (unit >= 1 && unit <= 247) return std::nullopt;
    return fmt::format(
        "unit {} is not a serial device address: on {} a device answers at an address from 1 "
        "to 247 (0 is the broadcast); give it with --unit",
        unit, target);
}

}  // namespace mblab::conformance
