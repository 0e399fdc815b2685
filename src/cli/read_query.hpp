#pragma once

#include <CLI/CLI.hpp>
#include <array>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/value_format.hpp"
#include "client/client.hpp"
#include "protocol/result.hpp"

// What `mblab read` and `mblab watch` read: the kind, its arguments, and the typed table of the
// answer. Every read function code is one kind:
//   coils|discretes ADDR [COUNT]            FC 01, 02
//   holding|input ADDR [COUNT]              FC 03, 04 (COUNT values of --type)
//   exception-status                        FC 07
//   event-counter | event-log               FC 0B, 0C
//   server-id                               FC 11
//   fifo ADDR                               FC 18
//   file FILE RECORD [COUNT]                FC 14 (COUNT values of --type)
namespace mblab::cli {

enum class ReadKind : std::uint8_t {
    Coils,
    Discretes,
    Holding,
    Input,
    ExceptionStatus,
    EventCounter,
    EventLog,
    ServerId,
    Fifo,
    File,
};

struct ReadQuery {
    ReadKind kind = ReadKind::Holding;
    std::uint16_t address = 0;  // FILE: the file number
    std::uint16_t count = 1;    // bits, or values of format.type
    std::uint16_t record = 0;   // FILE only
    ValueFormat format;
    std::string address_given;  // ADDR as typed, for hints after an exception 02
    int base = 0;               // --base
};

inline constexpr const char* kReadKindsHelp =
    "coils|discretes|holding|input ADDR [COUNT], exception-status, event-counter, event-log, "
    "server-id, fifo ADDR, file FILE RECORD [COUNT]";

// `type_given`: --type was on the command line (it only makes sense for registers). `base`: 1
// when addresses are given 1-based (--base 1).
protocol::Result<ReadQuery, std::string> parse_read_query(const std::string& kind,
                                                          const std::vector<std::string>& args,
                                                          const ValueFormat& format,
                                                          bool type_given, int base);

// --base 0|1, as read, write and watch take it.
void add_base_option(CLI::App& command, int& base);

// KIND, its arguments and the typed-value flags, as `read` and `watch` take them.
struct QueryOptions {
    std::string kind;
    std::vector<std::string> args;
    FormatOptions format;
    int base = 0;
    CLI::App* command = nullptr;
};
void add_query_arguments(CLI::App& command, QueryOptions& options);
protocol::Result<ReadQuery, std::string> parse_query(const QueryOptions& options);

// A three-column table (first column: an address or a field name) and its JSON twin.
struct Reading {
    std::array<std::string, 3> header;
    std::vector<std::array<std::string, 3>> rows;
    std::vector<std::string> notes;  // lines after the table
    nlohmann::json json = nlohmann::json::object();
};

client::CallResult<Reading> perform_read(client::Client& client, const ReadQuery& query);

// An exception 02 to a read whose ADDR looks 1-based gets a hint added to its message: a 5-digit
// Modicon reference given as a plain address (40001), or, when `probe` allows one more read, an
// address one past the last that answers (the device answers the same read at ADDR - 1).
client::ClientError explain_address_error(client::Client& client, const ReadQuery& query,
                                          client::ClientError error, bool probe);

// Registers as typed values, one row per value; `label` names the row of the value at `index`
// (the register offset from the first): its text, and its JSON key and number.
struct RowName {
    std::string text;
    const char* key = "address";
    unsigned number = 0;
};
using RowLabel = std::function<RowName(std::size_t index)>;
Reading register_reading(std::span<const std::uint16_t> registers, const ValueFormat& format,
                         const RowLabel& label);
// Labels rows with the address `first + index`.
RowLabel address_label(std::uint16_t first);

// The table as aligned lines. `marked`, when given, has one flag per row: a marked row's value
// cell is put between `mark_on` and `mark_off` (escapes that take no columns).
std::vector<std::string> table_lines(const Reading& reading);
std::vector<std::string> table_lines(const Reading& reading, const std::vector<bool>& marked,
                                     const std::string& mark_on, const std::string& mark_off);
void print_reading(const Reading& reading);

// "holding registers 0 (0x0000), 10 u16 values" for headers and JSON.
std::string describe_query(const ReadQuery& query);

}  // namespace mblab::cli
