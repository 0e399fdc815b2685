#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/number_text.hpp"
#include "cli/pdu_text.hpp"
#include "client/hex_text.hpp"
#include "protocol/function_code.hpp"

// `mblab diag TARGET SUBFUNCTION [DATA...]`: FC 08 by sub-function name or number, counters
// printed by name; `counters` reads every counter sub-function in turn.
namespace mblab::cli {

namespace {

using protocol::DiagnosticSub;

struct DiagOptions {
    ClientOptions client;
    std::string sub_function;
    std::vector<std::string> data;
};

struct SubName {
    const char* name;
    DiagnosticSub sub;
    bool counter;
};

constexpr std::array<SubName, 15> kSubs = {{
    {"query-data", DiagnosticSub::ReturnQueryData, false},
    {"restart-communications", DiagnosticSub::RestartCommunications, false},
    {"diagnostic-register", DiagnosticSub::ReturnDiagnosticRegister, false},
    {"change-ascii-delimiter", DiagnosticSub::ChangeAsciiDelimiter, false},
    {"force-listen-only", DiagnosticSub::ForceListenOnly, false},
    {"clear-counters", DiagnosticSub::ClearCounters, false},
    {"bus-message-count", DiagnosticSub::BusMessageCount, true},
    {"bus-communication-error-count", DiagnosticSub::BusCommunicationErrorCount, true},
    {"bus-exception-error-count", DiagnosticSub::BusExceptionErrorCount, true},
    {"server-message-count", DiagnosticSub::ServerMessageCount, true},
    {"server-no-response-count", DiagnosticSub::ServerNoResponseCount, true},
    {"server-nak-count", DiagnosticSub::ServerNakCount, true},
    {"server-busy-count", DiagnosticSub::ServerBusyCount, true},
    {"bus-character-overrun-count", DiagnosticSub::BusCharacterOverrunCount, true},
    {"clear-overrun-counter", DiagnosticSub::ClearOverrunCounter, false},
}};

constexpr const char* kCounters = "counters";

const SubName* find_sub(std::uint16_t sub) {
    for (const auto& s : kSubs) {
        if (static_cast<std::uint16_t>(s.sub) == sub) return &s;
    }
    return nullptr;
}

std::optional<std::uint16_t> parse_sub(const std::string& text) {
    for (const auto& s : kSubs) {
        if (text == s.name) return static_cast<std::uint16_t>(s.sub);
    }
    if (auto number = parse_unsigned(text, 0xFFFF)) return static_cast<std::uint16_t>(*number);
    return std::nullopt;
}

std::string sub_names() {
    std::string names;
    for (const auto& s : kSubs)
        names += fmt::format("  {:02X}  {}\n", static_cast<unsigned>(s.sub), s.name);
    return names;
}

protocol::Result<std::vector<std::uint8_t>, std::string> data_words(
    const std::vector<std::string>& words) {
    std::vector<std::uint8_t> bytes;
    for (const auto& word : words) {
        auto value = parse_unsigned(word, 0xFFFF);
        if (!value) {
            return fmt::format("DATA is 16-bit words (decimal or 0x hex), got '{}'", word);
        }
        bytes.push_back(static_cast<std::uint8_t>(*value >> 8));
        bytes.push_back(static_cast<std::uint8_t>(*value & 0xFF));
    }
    if (bytes.empty()) bytes = {0x00, 0x00};
    return bytes;
}

std::uint16_t word_of(const std::vector<std::uint8_t>& data) {
    return data.size() >= 2 ? static_cast<std::uint16_t>((data[0] << 8) | data[1]) : 0;
}

// What the answer of `sub` says, in words.
std::string answer_text(std::uint16_t sub, const client::DiagnosticsAnswer& answer) {
    const auto* named = find_sub(sub);
    if (named != nullptr && named->counter) {
        return fmt::format("{}: {}", named->name, word_of(answer.data));
    }
    switch (static_cast<DiagnosticSub>(sub)) {
        case DiagnosticSub::ReturnQueryData:
            return fmt::format("echoed {} bytes: {}", answer.data.size(),
                               client::hex_bytes(answer.data));
        case DiagnosticSub::RestartCommunications:
            return "communications restarted";
        case DiagnosticSub::ReturnDiagnosticRegister:
            return fmt::format("diagnostic register: 0x{:04X}", word_of(answer.data));
        case DiagnosticSub::ChangeAsciiDelimiter:
            return fmt::format("ASCII input delimiter set to 0x{:02X}",
                               answer.data.empty() ? 0 : answer.data[0]);
        case DiagnosticSub::ClearCounters:
            return "counters and diagnostic register cleared";
        case DiagnosticSub::ClearOverrunCounter:
            return "overrun counter and flag cleared";
        default:
            return fmt::format("answer data: {}", client::hex_bytes(answer.data));
    }
}

int read_counters(client::Client& client, CommandOutput& out) {
    std::vector<std::string> lines;
    auto& counters = out.document()["counters"] = nlohmann::json::object();
    for (const auto& s : kSubs) {
        if (!s.counter) continue;
        static constexpr std::uint8_t kZero[] = {0, 0};
        auto answer = client.diagnostics(static_cast<std::uint16_t>(s.sub), kZero);
        if (!answer) return out.fail(answer.error());
        counters[s.name] = word_of(answer->data);
        lines.push_back(answer_text(static_cast<std::uint16_t>(s.sub), *answer));
    }
    return out.done([&] {
        for (const auto& line : lines)
            fmt::print("{}\n", line);
    });
}

int run_diag(const DiagOptions& options) {
    CommandOutput output("diag", options.client);
    if (options.sub_function == kCounters) {
        if (!options.data.empty()) return output.usage("'counters' takes no DATA");
        return with_client(options.client, output, read_counters);
    }
    auto sub = parse_sub(options.sub_function);
    if (!sub) {
        return output.usage(
            fmt::format("unknown sub-function '{}' (a number, or a name: see mblab diag --help)",
                        options.sub_function));
    }
    auto data = data_words(options.data);
    if (!data) return output.usage(data.error());
    return with_client(options.client, output, [&](client::Client& client, CommandOutput& out) {
        auto& document = out.document();
        document["sub_function"] = *sub;
        document["name"] = protocol::diagnostic_sub_name(*sub);
        if (*sub == static_cast<std::uint16_t>(DiagnosticSub::ForceListenOnly)) {
            auto sent = client.send_listen_only();
            if (!sent) return out.fail(sent.error());
            if (!out.json()) {
                fmt::print(
                    "sent force listen only mode (never answered): the device now answers nothing "
                    "until restart-communications\n");
            }
            return out.done();
        }
        auto answer = client.diagnostics(*sub, *data);
        if (!answer) {
            auto error = answer.error();
            if (error.kind == client::ErrorKind::Timeout &&
                *sub == static_cast<std::uint16_t>(DiagnosticSub::RestartCommunications)) {
                // [APP] 6.8.1: a port in listen only mode restarts without answering. Whether
                // that is what happened shows in the next request: it is answered now.
                const std::uint8_t echo[] = {0x00, 0x00};
                auto probe = client.diagnostics(
                    static_cast<std::uint16_t>(DiagnosticSub::ReturnQueryData), echo);
                if (probe || probe.error().kind == client::ErrorKind::Exception) {
                    document["answered"] = false;
                    document["was_listen_only"] = true;
                    if (!out.json()) {
                        fmt::print(
                            "communications restarted: no answer, as a device in listen only mode "
                            "gives none (Modbus Application Protocol 6.8.1); it answers again\n");
                    }
                    return out.done();
                }
                error.message +=
                    " (a device in listen only mode restarts without answering, but "
                    "this one did not answer the next request either)";
            }
            return out.fail(error);
        }
        document["data"] = client::hex_bytes(answer->data);
        if (const auto* named = find_sub(*sub); named != nullptr && named->counter) {
            document["value"] = word_of(answer->data);
        }
        return out.done([&] { fmt::print("{}\n", answer_text(*sub, *answer)); });
    });
}

// What `mblab --help` says of the command.
constexpr std::string_view kSummary =
    "Diagnostics (FC 08): any sub-function by name or number, counters by name";

}  // namespace

void add_diag_command(CLI::App& app, CommandRunner& runner) {
    auto [cmd, options] = add_client_command<DiagOptions>(
        app, runner, "diag", std::string(kSummary),
        "SUBFUNCTION is a number (decimal or 0x hex) or one of:\n" + sub_names() + help_text(R"(
  counters: reads every counter (0B..12) and prints them by name
DATA is 16-bit words (default 0x0000); query-data echoes any number of them,
restart-communications takes 0xFF00 to clear the event log, change-ascii-delimiter
takes the character in the high byte (0x0A00). force-listen-only is never answered.
Exit status: 0 answered, 1 the device answered an exception or no proper answer, 2
usage error or unreachable target.
Example: mblab diag tcp://127.0.0.1:502 bus-message-count)"),
        run_diag);
    cmd->add_option("sub-function", options->sub_function, "sub-function name or number")
        ->required();
    cmd->add_option("data", options->data, "data words (decimal or 0x hex)");
}

}  // namespace mblab::cli
