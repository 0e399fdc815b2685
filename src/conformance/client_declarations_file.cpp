#include "conformance/client_declarations_file.hpp"

#include <optional>
#include <regex>

#include "conformance/toml_reader.hpp"

namespace mblab::conformance {

namespace {

bool regex_ok(TomlReader& reader, const toml::table& table, std::string_view key,
              std::string& out) {
    if (!reader.get(table, key, out)) return false;
    if (out.empty()) return true;
    try {
        std::regex checked(out);
    } catch (const std::regex_error& error) {
        return reader.fail(table.get(key),
                           std::string(key) + ": not a regular expression: " + error.what());
    }
    return true;
}

protocol::Result<ClientDeclarations, std::string> declarations_of(
    TomlReader& reader, const std::optional<toml::table>& table, ClientDeclarations declared) {
    if (!table) return reader.error();
    std::optional<std::uint8_t> unit;
    std::optional<std::uint16_t> address;
    std::optional<std::uint16_t> count;
    std::optional<std::uint32_t> timeout_ms;
    std::optional<unsigned> retries;
    std::string value_pattern;
    const bool ok =
        reader.only_keys(
            *table, {"client-unit", "client-timeout", "client-retries", "client-pipelining",
                     "client-broadcast", "error-pattern", "value-pattern", "address", "count"}) &&
        reader.get_number(*table, "client-unit", unit, 0, 255) &&
        reader.get_number(*table, "client-timeout", timeout_ms, 1, 600000) &&
        reader.get_number(*table, "client-retries", retries, 0, 100) &&
        reader.get(*table, "client-pipelining", declared.pipelining) &&
        reader.get(*table, "client-broadcast", declared.broadcast) &&
        regex_ok(reader, *table, "error-pattern", declared.error_pattern) &&
        regex_ok(reader, *table, "value-pattern", value_pattern) &&
        reader.get_number(*table, "address", address, 0, 65535) &&
        reader.get_number(*table, "count", count, 1, 125);
    if (!ok) return reader.error();
    if (unit) declared.unit = *unit;
    if (address) declared.address = *address;
    if (count) declared.count = *count;
    if (timeout_ms) declared.timeout = std::chrono::milliseconds(*timeout_ms);
    if (retries) declared.retries = *retries;
    if (!value_pattern.empty()) declared.value_pattern = value_pattern;
    return declared;
}

}  // namespace

protocol::Result<ClientDeclarations, std::string> read_client_declarations(
    const std::string& path, ClientDeclarations base) {
    TomlReader reader(path);
    const auto table = reader.parse_file();
    return declarations_of(reader, table, std::move(base));
}

protocol::Result<ClientDeclarations, std::string> parse_client_declarations(
    std::string_view text, const std::string& name, ClientDeclarations base) {
    TomlReader reader(name);
    const auto table = reader.parse_text(text);
    return declarations_of(reader, table, std::move(base));
}

}  // namespace mblab::conformance
