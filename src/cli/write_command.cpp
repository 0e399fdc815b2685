#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/modbus_address.hpp"
#include "cli/number_text.hpp"
#include "cli/read_query.hpp"
#include "protocol/limits.hpp"

// `mblab write TARGET KIND ARGS...`: every write function code, with register values typed the
// same way `read` shows them.
namespace mblab::cli {

namespace {

struct WriteOptions {
    ClientOptions client;
    FormatOptions format;
    std::string kind;
    std::vector<std::string> args;
    int base = 0;
    CLI::App* command = nullptr;
};

constexpr const char* kWriteKinds =
    "coil ADDR VALUE, coils ADDR VALUE..., register ADDR VALUE, registers ADDR VALUE..., mask ADDR "
    "AND OR, readwrite READ_ADDR READ_COUNT WRITE_ADDR VALUE..., file FILE RECORD VALUE...";

// A parsed command line: what to send and how to report it.
struct Plan {
    std::function<client::CallResult<Reading>(client::Client&)> run;
    std::string summary;  // "wrote 2 registers at 0 (0x0000)"
    nlohmann::json json;
    // ADDR as typed and its table, for the hint after an exception 02.
    std::string address_given;
    DataTable table = DataTable::Holding;
};

using Planned = protocol::Result<Plan, std::string>;
using Number = protocol::Result<std::uint16_t, std::string>;

Number number(const std::string& text, const char* name, std::uint64_t max = 0xFFFF) {
    auto value = parse_unsigned(text, max);
    if (!value) {
        return fmt::format("{} must be a number from 0 to {} (decimal or 0x hex), got '{}'", name,
                           max, text);
    }
    return static_cast<std::uint16_t>(*value);
}

protocol::Result<bool, std::string> bit(const std::string& text) {
    if (text == "1" || text == "on" || text == "true") return true;
    if (text == "0" || text == "off" || text == "false") return false;
    return fmt::format("a coil value is 1, 0, on, off, true or false, got '{}'", text);
}

std::string plural(std::size_t count, const char* one, const char* many) {
    return fmt::format("{} {}", count, count == 1 ? one : many);
}

// Wraps a call that answers nothing but success into a plan step.
template <class Call>
std::function<client::CallResult<Reading>(client::Client&)> no_reading(Call call) {
    return [call](client::Client& c) -> client::CallResult<Reading> {
        auto done = call(c);
        if (!done) return done.error();
        Reading nothing;
        return nothing;
    };
}

Planned plan_coils(const std::vector<std::string>& args, bool single, int base) {
    auto address = parse_address(args[0], "ADDR", DataTable::Coils, base);
    if (!address) return address.error();
    std::vector<bool> values;
    for (std::size_t i = 1; i < args.size(); ++i) {
        auto value = bit(args[i]);
        if (!value) return value.error();
        values.push_back(*value);
    }
    Plan plan;
    plan.address_given = args[0];
    plan.table = DataTable::Coils;
    plan.json = {{"address", *address}, {"values", values}};
    if (single) {
        const bool on = values.front();
        plan.run = no_reading(
            [a = *address, on](client::Client& c) { return c.write_single_coil(a, on); });
        plan.summary = fmt::format("wrote coil {}: {}", address_text(*address), on ? "on" : "off");
    } else {
        plan.run = no_reading([a = *address, values](client::Client& c) {
            return c.write_multiple_coils(a, values);
        });
        plan.summary = fmt::format("wrote {} at {}", plural(values.size(), "coil", "coils"),
                                   address_text(*address));
    }
    return plan;
}

Planned plan_registers(const std::vector<std::string>& args, const ValueFormat& format, bool single,
                       int base) {
    auto address = parse_address(args[0], "ADDR", DataTable::Holding, base);
    if (!address) return address.error();
    auto values = encode_values({args.begin() + 1, args.end()}, format);
    if (!values) return values.error();
    Plan plan;
    plan.address_given = args[0];
    plan.json = {{"address", *address}, {"registers", *values}};
    if (single) {
        if (values->size() != 1) {
            return fmt::format("'{}' takes {} registers: use 'registers' to write more than one",
                               args[1], values->size());
        }
        const std::uint16_t value = values->front();
        plan.run = no_reading(
            [a = *address, value](client::Client& c) { return c.write_single_register(a, value); });
        plan.summary =
            fmt::format("wrote register {}: 0x{:04X} ({})", address_text(*address), value, value);
    } else {
        plan.run = no_reading([a = *address, v = *values](client::Client& c) {
            return c.write_multiple_registers(a, v);
        });
        plan.summary =
            fmt::format("wrote {} at {}", plural(values->size(), "register", "registers"),
                        address_text(*address));
    }
    return plan;
}

Planned plan_mask(const std::vector<std::string>& args, int base) {
    auto address = parse_address(args[0], "ADDR", DataTable::Holding, base);
    auto and_mask = number(args[1], "AND");
    auto or_mask = number(args[2], "OR");
    for (const auto* part : {&address, &and_mask, &or_mask}) {
        if (!*part) return part->error();
    }
    Plan plan;
    plan.address_given = args[0];
    plan.json = {{"address", *address}, {"and_mask", *and_mask}, {"or_mask", *or_mask}};
    plan.run = no_reading([a = *address, m = *and_mask, o = *or_mask](client::Client& c) {
        return c.mask_write_register(a, m, o);
    });
    plan.summary = fmt::format("masked register {}: and 0x{:04X}, or 0x{:04X}",
                               address_text(*address), *and_mask, *or_mask);
    return plan;
}

Planned plan_read_write(const std::vector<std::string>& args, const ValueFormat& format, int base) {
    auto read_address = parse_address(args[0], "READ_ADDR", DataTable::Holding, base);
    if (!read_address) return read_address.error();
    auto read_count = number(args[1], "READ_COUNT");
    if (!read_count) return read_count.error();
    auto write_address = parse_address(args[2], "WRITE_ADDR", DataTable::Holding, base);
    if (!write_address) return write_address.error();
    auto values = encode_values({args.begin() + 3, args.end()}, format);
    if (!values) return values.error();
    const auto registers =
        static_cast<std::uint16_t>(*read_count * registers_per_value(format.type));
    Plan plan;
    plan.json = {
        {"read_address", *read_address}, {"write_address", *write_address}, {"registers", *values}};
    plan.run = [r = *read_address, registers, w = *write_address, v = *values,
                format](client::Client& c) -> client::CallResult<Reading> {
        auto read = c.read_write_multiple_registers(r, registers, w, v);
        if (!read) return read.error();
        return register_reading(*read, format, address_label(r));
    };
    plan.summary =
        fmt::format("wrote {} at {}, then read:", plural(values->size(), "register", "registers"),
                    address_text(*write_address));
    return plan;
}

Planned plan_file(const std::vector<std::string>& args, const ValueFormat& format) {
    auto file = number(args[0], "FILE");
    if (!file) return file.error();
    auto record = number(args[1], "RECORD", protocol::limits::kMaxFileRecordNumber);
    if (!record) return record.error();
    auto values = encode_values({args.begin() + 2, args.end()}, format);
    if (!values) return values.error();
    Plan plan;
    plan.json = {{"file", *file}, {"record", *record}, {"registers", *values}};
    const client::FileRecordWrite write{*file, *record, *values};
    plan.run = no_reading(
        [write](client::Client& c) { return c.write_file_records(std::span(&write, 1)); });
    plan.summary = fmt::format("wrote {} to file {} from record {}",
                               plural(values->size(), "register", "registers"), *file, *record);
    return plan;
}

struct KindRule {
    const char* name;
    std::size_t min_args;
    std::size_t max_args;  // 0: no limit
    const char* usage;
    bool typed;
};

constexpr std::array<KindRule, 7> kKinds = {{
    {"coil", 2, 2, "coil ADDR VALUE", false},
    {"coils", 2, 0, "coils ADDR VALUE...", false},
    {"register", 2, 2, "register ADDR VALUE", true},
    {"registers", 2, 0, "registers ADDR VALUE...", true},
    {"mask", 3, 3, "mask ADDR AND OR", false},
    {"readwrite", 4, 0, "readwrite READ_ADDR READ_COUNT WRITE_ADDR VALUE...", true},
    {"file", 3, 0, "file FILE RECORD VALUE...", true},
}};

Planned plan_write(const WriteOptions& options, const ValueFormat& format) {
    const auto& args = options.args;
    const KindRule* rule = nullptr;
    for (const auto& k : kKinds) {
        if (options.kind == k.name) rule = &k;
    }
    if (rule == nullptr)
        return fmt::format("unknown kind '{}' (one of: {})", options.kind, kWriteKinds);
    if (args.size() < rule->min_args || (rule->max_args != 0 && args.size() > rule->max_args)) {
        return fmt::format("wrong number of arguments: {}", rule->usage);
    }
    if (!rule->typed && options.command->count("--type") > 0) {
        return fmt::format("--type applies to register values, not {}", options.kind);
    }
    const std::string kind = options.kind;
    const int base = options.base;
    if (kind == "coil" || kind == "coils") return plan_coils(args, kind == "coil", base);
    if (kind == "register" || kind == "registers") {
        return plan_registers(args, format, kind == "register", base);
    }
    if (kind == "mask") return plan_mask(args, base);
    if (kind == "readwrite") return plan_read_write(args, format, base);
    return plan_file(args, format);
}

int run_write(const WriteOptions& options) {
    CommandOutput output("write", options.client);
    auto format = parse_format(options.format);
    if (!format) return output.usage(format.error());
    auto plan = plan_write(options, *format);
    if (!plan) return output.usage(plan.error());
    return with_client(options.client, output, [&](client::Client& client, CommandOutput& out) {
        auto reading = plan->run(client);
        if (!reading) {
            auto error = reading.error();
            // No probe as `read` makes: a write at another address would change the device.
            if (error.exception == protocol::ExceptionCode::IllegalDataAddress) {
                if (auto hint = reference_hint(plan->address_given, plan->table, options.base))
                    error.message += "; " + *hint;
            }
            return out.fail(error);
        }
        auto& document = out.document();
        document["write"] = options.kind;
        document.update(plan->json);
        if (!reading->rows.empty()) document["read"] = reading->json;
        return out.done([&] {
            fmt::print("{}\n", plan->summary);
            if (!reading->rows.empty()) print_reading(*reading);
        });
    });
}

// What `mblab --help` says of the command.
constexpr std::string_view kSummary =
    "Write to a device: coils, registers (typed), mask write, read/write registers, file "
    "records";
constexpr std::string_view kHelp = R"(
KIND and its arguments:
  coil ADDR VALUE                 FC 05; VALUE is 1, 0, on, off, true or false
  coils ADDR VALUE...             FC 0F
  register ADDR VALUE             FC 06; a 16-bit --type (u16, i16, hex, 2 ascii chars)
  registers ADDR VALUE...         FC 10; each VALUE as --type says (f32: 2 registers)
  mask ADDR AND OR                FC 16; result = (current AND and) OR (or AND NOT and)
  readwrite READ_ADDR READ_COUNT WRITE_ADDR VALUE...
                                  FC 17; writes, then reads READ_COUNT values of --type
  file FILE RECORD VALUE...       FC 15; registers from RECORD of FILE
Values are encoded the way `mblab read` decodes them with the same --type, --word-order
and --byte-order. Numbers are decimal or hex (0x2A).
ADDR is a 0-based PDU offset (register 0 is the one manuals call 40001 or 1). With
--base 1 it is 1-based; a Modicon reference is 1-based too: 4x00001 or 400001 for
holding registers, 000001 for coils (0x is hex). A negative VALUE follows --, which
ends the options: mblab write TARGET register 7 --type i16 -- -5.
Exit status: 0 written, 1 the device answered an exception or no proper answer, 2
usage error or unreachable target.
Example: mblab write tcp://127.0.0.1:502 registers 100 3.5 -1e3 --type f32)";

}  // namespace

void add_write_command(CLI::App& app, CommandRunner& runner) {
    auto [cmd, options] = add_client_command<WriteOptions>(
        app, runner, "write", std::string(kSummary), help_text(kHelp), run_write);
    options->command = cmd;
    cmd->add_option("kind", options->kind,
                    "coil, coils, register, registers, mask, readwrite, file")
        ->required();
    cmd->add_option("args", options->args,
                    "ADDR VALUE..., or what KIND takes; ADDR is a 0-based PDU offset (see --base), "
                    "or a Modicon reference such as 4x00001 or 400001");
    add_format_options(*cmd, options->format);
    add_base_option(*cmd, options->base);
}

}  // namespace mblab::cli
