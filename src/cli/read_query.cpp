#include "cli/read_query.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <optional>

#include "cli/diagnostic_readings.hpp"
#include "cli/modbus_address.hpp"
#include "cli/number_text.hpp"
#include "cli/pdu_text.hpp"
#include "protocol/limits.hpp"
#include "support/escaped_text.hpp"

namespace mblab::cli {

namespace {

struct KindInfo {
    const char* name;
    ReadKind kind;
    std::size_t min_args;
    std::size_t max_args;
    const char* usage;  // the arguments, for messages
    const char* what;   // for describe_query
};

constexpr std::array<KindInfo, 10> kKinds = {{
    {"coils", ReadKind::Coils, 1, 2, "coils ADDR [COUNT]", "coils"},
    {"discretes", ReadKind::Discretes, 1, 2, "discretes ADDR [COUNT]", "discrete inputs"},
    {"holding", ReadKind::Holding, 1, 2, "holding ADDR [COUNT]", "holding registers"},
    {"input", ReadKind::Input, 1, 2, "input ADDR [COUNT]", "input registers"},
    {"exception-status", ReadKind::ExceptionStatus, 0, 0, "exception-status", "exception status"},
    {"event-counter", ReadKind::EventCounter, 0, 0, "event-counter", "comm event counter"},
    {"event-log", ReadKind::EventLog, 0, 0, "event-log", "comm event log"},
    {"server-id", ReadKind::ServerId, 0, 0, "server-id", "server id"},
    {"fifo", ReadKind::Fifo, 1, 1, "fifo ADDR", "FIFO queue"},
    {"file", ReadKind::File, 2, 3, "file FILE RECORD [COUNT]", "file"},
}};

const KindInfo& info(ReadKind kind) {
    return kKinds[static_cast<std::size_t>(kind)];
}

bool is_register_kind(ReadKind kind) {
    return kind == ReadKind::Holding || kind == ReadKind::Input || kind == ReadKind::Fifo ||
           kind == ReadKind::File;
}

using Parsed = protocol::Result<std::uint16_t, std::string>;

Parsed number(const std::string& text, const char* name, std::uint64_t min, std::uint64_t max) {
    auto value = parse_unsigned(text, max);
    if (!value || *value < min) {
        return fmt::format("{} must be a number from {} to {} (decimal or 0x hex), got '{}'", name,
                           min, max, text);
    }
    return static_cast<std::uint16_t>(*value);
}

// The table ADDR of `kind` addresses; FILE's numbers are not addresses of a table.
std::optional<DataTable> address_table(ReadKind kind) {
    switch (kind) {
        case ReadKind::Coils:
            return DataTable::Coils;
        case ReadKind::Discretes:
            return DataTable::Discretes;
        case ReadKind::Holding:
        case ReadKind::Fifo:
            return DataTable::Holding;
        case ReadKind::Input:
            return DataTable::Input;
        default:
            return std::nullopt;
    }
}

std::string on_off(bool on) {
    return on ? "on" : "off";
}

Reading bits_reading(const std::vector<bool>& bits, std::uint16_t first) {
    Reading reading;
    reading.header = {"address", "raw", "value"};
    auto& values = reading.json["values"] = nlohmann::json::array();
    for (std::size_t i = 0; i < bits.size(); ++i) {
        const auto address = static_cast<unsigned>(first + i);
        reading.rows.push_back({address_text(address), bits[i] ? "1" : "0", on_off(bits[i])});
        values.push_back({{"address", address}, {"value", bool{bits[i]}}});
    }
    return reading;
}

// Registers of one value each and a remainder too short for a value are reported, not dropped.
void check_whole_values(Reading& reading, std::size_t registers, const ValueFormat& format) {
    const std::size_t per = registers_per_value(format.type);
    if (registers % per != 0) {
        reading.notes.push_back(fmt::format("{} registers left over: not a whole {} value",
                                            registers % per, value_type_name(format.type)));
    }
}

std::uint16_t register_count(const ReadQuery& query) {
    return static_cast<std::uint16_t>(query.count * registers_per_value(query.format.type));
}

}  // namespace

RowLabel address_label(std::uint16_t first) {
    return [first](std::size_t index) {
        const auto address = static_cast<unsigned>(first + index);
        return RowName{address_text(address), "address", address};
    };
}

Reading register_reading(std::span<const std::uint16_t> registers, const ValueFormat& format,
                         const RowLabel& label) {
    Reading reading;
    reading.header = {"address", "raw", std::string(value_type_name(format.type))};
    const std::size_t per = registers_per_value(format.type);
    auto& values = reading.json["values"] = nlohmann::json::array();
    for (std::size_t i = 0; i + per <= registers.size(); i += per) {
        const auto value = registers.subspan(i, per);
        const RowName name = label(i);
        reading.rows.push_back({name.text, raw_text(value), format_value(value, format)});
        values.push_back({{name.key, name.number},
                          {"raw", std::vector<std::uint16_t>(value.begin(), value.end())},
                          {"value", json_value(value, format)}});
    }
    reading.json["type"] = value_type_name(format.type);
    if (format.type == ValueType::Ascii) {
        const std::string text = ascii_text(registers, format);
        const auto* bytes = reinterpret_cast<const std::uint8_t*>(text.data());
        reading.notes.push_back("\"" + escaped_text({bytes, text.size()}) + "\"");
        reading.json["text"] = text;
    }
    check_whole_values(reading, registers.size(), format);
    return reading;
}

protocol::Result<ReadQuery, std::string> parse_read_query(const std::string& kind,
                                                          const std::vector<std::string>& args,
                                                          const ValueFormat& format,
                                                          bool type_given, int base) {
    auto found = std::find_if(kKinds.begin(), kKinds.end(),
                              [&](const KindInfo& k) { return kind == k.name; });
    if (found == kKinds.end()) {
        return fmt::format("unknown kind '{}' (one of: {})", kind, kReadKindsHelp);
    }
    ReadQuery query;
    query.kind = found->kind;
    query.format = format;
    query.base = base;
    if (args.size() < found->min_args || args.size() > found->max_args) {
        return fmt::format("'{}' takes {} argument{}: {}", kind,
                           found->min_args == found->max_args
                               ? std::to_string(found->min_args)
                               : fmt::format("{} to {}", found->min_args, found->max_args),
                           found->max_args == 1 ? "" : "s", found->usage);
    }
    if (type_given && !is_register_kind(query.kind)) {
        return fmt::format("--type applies to registers (holding, input, fifo, file), not {}",
                           kind);
    }
    std::size_t next = 0;
    if (query.kind == ReadKind::File) {
        auto file = number(args[next++], "FILE", 1, 0xFFFF);
        if (!file) return file.error();
        auto record = number(args[next++], "RECORD", 0, protocol::limits::kMaxFileRecordNumber);
        if (!record) return record.error();
        query.address = *file;
        query.record = *record;
    } else if (found->min_args > 0) {
        query.address_given = args[next++];
        auto address = parse_address(query.address_given, "ADDR", *address_table(query.kind), base);
        if (!address) return address.error();
        query.address = *address;
    }
    if (next < args.size()) {
        auto count = number(args[next], "COUNT", 1, 0xFFFF);
        if (!count) return count.error();
        query.count = *count;
    }
    if (is_register_kind(query.kind) && query.kind != ReadKind::Fifo &&
        query.count * registers_per_value(format.type) > protocol::limits::kMaxReadRegisters) {
        return fmt::format("{} {} values take {} registers; one read takes at most {}", query.count,
                           value_type_name(format.type),
                           query.count * registers_per_value(format.type),
                           protocol::limits::kMaxReadRegisters);
    }
    return query;
}

client::CallResult<Reading> perform_read(client::Client& client, const ReadQuery& query) {
    auto done = [](auto outcome, auto make) -> client::CallResult<Reading> {
        if (!outcome) return outcome.error();
        return make(*outcome);
    };
    auto registers = [&](const std::vector<std::uint16_t>& values) {
        return register_reading(values, query.format, address_label(query.address));
    };
    const auto count = register_count(query);
    switch (query.kind) {
        case ReadKind::Coils:
            return done(client.read_coils(query.address, query.count),
                        [&](const auto& bits) { return bits_reading(bits, query.address); });
        case ReadKind::Discretes:
            return done(client.read_discrete_inputs(query.address, query.count),
                        [&](const auto& bits) { return bits_reading(bits, query.address); });
        case ReadKind::Holding:
            return done(client.read_holding_registers(query.address, count), registers);
        case ReadKind::Input:
            return done(client.read_input_registers(query.address, count), registers);
        case ReadKind::ExceptionStatus:
            return done(client.read_exception_status(), exception_status_reading);
        case ReadKind::EventCounter:
            return done(client.get_comm_event_counter(), event_counter_reading);
        case ReadKind::EventLog:
            return done(client.get_comm_event_log(), event_log_reading);
        case ReadKind::ServerId:
            return done(client.report_server_id(), server_id_reading);
        case ReadKind::Fifo:
            return done(client.read_fifo_queue(query.address), [&](const auto& values) {
                Reading reading = register_reading(values, query.format, [](std::size_t i) {
                    return RowName{fmt::format("entry {}", i), "entry", static_cast<unsigned>(i)};
                });
                reading.json["fifo_count"] = values.size();
                if (values.empty()) reading.notes.push_back("the FIFO queue is empty");
                return reading;
            });
        case ReadKind::File: {
            const protocol::FileRecordRef ref{query.address, query.record, count};
            return done(client.read_file_records(std::span(&ref, 1)), [&](const auto& records) {
                const unsigned first = query.record;
                return register_reading(records.front(), query.format, [first](std::size_t i) {
                    const auto record = static_cast<unsigned>(first + i);
                    return RowName{fmt::format("record {}", record), "record", record};
                });
            });
        }
    }
    return client::ClientError{client::ErrorKind::Invalid, "unknown read kind", std::nullopt};
}

client::ClientError explain_address_error(client::Client& client, const ReadQuery& query,
                                          client::ClientError error, bool probe) {
    const auto table = address_table(query.kind);
    if (error.exception != protocol::ExceptionCode::IllegalDataAddress || !table ||
        query.address_given.empty()) {
        return error;
    }
    if (auto hint = reference_hint(query.address_given, *table, query.base)) {
        error.message += "; " + *hint;
        return error;
    }
    // Only a plain 0-based number can be the off-by-one: a reference and --base 1 already say
    // how they count.
    if (!probe || query.kind == ReadKind::Fifo || query.base != 0 || query.address == 0 ||
        !parse_unsigned(query.address_given, 0xFFFF)) {
        return error;
    }
    ReadQuery before = query;
    before.address = static_cast<std::uint16_t>(query.address - 1);
    if (perform_read(client, before)) {
        error.message += fmt::format(
            "; {} answers: addresses are 0-based PDU offsets, so if {} is 1-based try {} or "
            "--base 1 with {}",
            address_text(before.address), query.address_given, before.address, query.address_given);
    }
    return error;
}

void add_base_option(CLI::App& command, int& base) {
    command
        .add_option("--base", base,
                    "0: addresses are 0-based PDU offsets (default); 1: they are 1-based, as "
                    "many manuals number them (1 is offset 0)")
        ->check(CLI::IsMember({0, 1}));
}

void add_query_arguments(CLI::App& command, QueryOptions& options) {
    options.command = &command;
    command.add_option("kind", options.kind, kReadKindsHelp)->required();
    command.add_option("args", options.args,
                       "ADDR [COUNT], or what KIND takes; ADDR is a 0-based PDU offset (see "
                       "--base), or a Modicon reference such as 4x00001 or 400001");
    add_format_options(command, options.format);
    add_base_option(command, options.base);
}

protocol::Result<ReadQuery, std::string> parse_query(const QueryOptions& options) {
    auto format = parse_format(options.format);
    if (!format) return format.error();
    return parse_read_query(options.kind, options.args, *format,
                            options.command->count("--type") > 0, options.base);
}

void print_reading(const Reading& reading) {
    for (const auto& line : table_lines(reading))
        fmt::print("{}\n", line);
}

std::vector<std::string> table_lines(const Reading& reading) {
    return table_lines(reading, {}, "", "");
}

std::vector<std::string> table_lines(const Reading& reading, const std::vector<bool>& marked,
                                     const std::string& mark_on, const std::string& mark_off) {
    std::array<std::size_t, 3> width{};
    for (std::size_t c = 0; c < 3; ++c)
        width[c] = reading.header[c].size();
    for (const auto& row : reading.rows) {
        for (std::size_t c = 0; c < 3; ++c)
            width[c] = std::max(width[c], row[c].size());
    }
    std::vector<std::string> lines;
    auto line = [&](const std::array<std::string, 3>& cells, bool mark) {
        std::string text =
            fmt::format("{:<{}}  {:<{}}  {}", cells[0], width[0], cells[1], width[1], cells[2]);
        while (!text.empty() && text.back() == ' ')
            text.pop_back();
        if (mark && !cells[2].empty())
            text = text.substr(0, text.size() - cells[2].size()) + mark_on + cells[2] + mark_off;
        lines.push_back(std::move(text));
    };
    line(reading.header, false);
    for (std::size_t i = 0; i < reading.rows.size(); ++i)
        line(reading.rows[i], i < marked.size() && marked[i]);
    for (const auto& note : reading.notes)
        lines.push_back(note);
    return lines;
}

std::string describe_query(const ReadQuery& query) {
    const auto& kind = info(query.kind);
    switch (query.kind) {
        case ReadKind::Coils:
        case ReadKind::Discretes:
            return fmt::format("{} {}, {}", kind.what, address_text(query.address), query.count);
        case ReadKind::Holding:
        case ReadKind::Input:
            return fmt::format("{} {}, {} {} value{}", kind.what, address_text(query.address),
                               query.count, value_type_name(query.format.type),
                               query.count == 1 ? "" : "s");
        case ReadKind::Fifo:
            return fmt::format("{} {}", kind.what, address_text(query.address));
        case ReadKind::File:
            return fmt::format("file {} record {}, {} {} value{}", query.address, query.record,
                               query.count, value_type_name(query.format.type),
                               query.count == 1 ? "" : "s");
        default:
            return kind.what;
    }
}

}  // namespace mblab::cli
