#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/read_query.hpp"

// `mblab read TARGET KIND ARGS...`: one read of any read function code, printed as a table of
// address, raw registers and typed value.
namespace mblab::cli {

namespace {

struct ReadOptions {
    ClientOptions client;
    QueryOptions query;
};

int run_read(const ReadOptions& options) {
    CommandOutput output("read", options.client);
    auto query = parse_query(options.query);
    if (!query) return output.usage(query.error());
    return with_client(options.client, output, [&](client::Client& client, CommandOutput& out) {
        auto reading = perform_read(client, *query);
        if (!reading) return out.fail(explain_address_error(client, *query, reading.error(), true));
        auto& document = out.document();
        document["read"] = describe_query(*query);
        document.update(reading->json);
        return out.done([&] { print_reading(*reading); });
    });
}

// What `mblab --help` says of the command.
constexpr std::string_view kSummary =
    "Read from a device: coils, discrete inputs, holding or input registers (typed), the "
    "exception status, comm event counter and log, server id, a FIFO queue or a file record";
constexpr std::string_view kHelp = R"(
KIND and its arguments:
  coils ADDR [COUNT]          FC 01, COUNT bits (default 1)
  discretes ADDR [COUNT]      FC 02
  holding ADDR [COUNT]        FC 03, COUNT values of --type (default 1)
  input ADDR [COUNT]          FC 04
  exception-status            FC 07
  event-counter               FC 0B
  event-log                   FC 0C
  server-id                   FC 11
  fifo ADDR                   FC 18, the queue whose count register is at ADDR
  file FILE RECORD [COUNT]    FC 14, COUNT values of --type from RECORD
ADDR is a 0-based PDU offset (holding 0 is the register manuals call 40001 or 1).
With --base 1 it is 1-based (1 is offset 0); a Modicon reference is 1-based too:
4x00001 or 400001 (holding), 3x/300001 (input), 1x/100001 (discretes), 000001
(coils; 0x is hex). Numbers are decimal or hex (0x2A).
Exit status: 0 read, 1 the device answered an exception or no proper answer, 2 usage
error or unreachable target.
Example: mblab read tcp://127.0.0.1:502 holding 0x10 2 --type f32)";

}  // namespace

void add_read_command(CLI::App& app, CommandRunner& runner) {
    auto [cmd, options] = add_client_command<ReadOptions>(
        app, runner, "read", std::string(kSummary), help_text(kHelp), run_read);
    add_query_arguments(*cmd, options->query);
}

}  // namespace mblab::cli
