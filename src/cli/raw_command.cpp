#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <cctype>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/pdu_text.hpp"
#include "client/answer_check.hpp"
#include "client/hex_text.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"

// `mblab raw TARGET HEX...`: sends any PDU as given, unchecked, and prints the answer decoded.
namespace mblab::cli {

namespace {

struct RawOptions {
    ClientOptions client;
    std::vector<std::string> hex;
};

// Each token is one byte (one or two hex digits: `0` is 0x00, `A` is 0x0A) or a run of whole
// bytes (an even number of digits: 030000000A); spaces and colons inside a token separate
// pieces the same way. An odd run longer than two digits is refused: `raw P 03 0 0 0 1` once
// became 03 00 01 without a word, and a PDU one byte short is worse than no PDU.
protocol::Result<std::vector<std::uint8_t>, std::string> parse_hex(
    const std::vector<std::string>& tokens) {
    std::vector<std::uint8_t> bytes;
    for (std::size_t position = 0; position < tokens.size(); ++position) {
        const std::string& token = tokens[position];
        std::string_view rest = token;
        while (!rest.empty()) {
            const auto cut = rest.find_first_of(" :");
            std::string_view piece = rest.substr(0, cut);
            rest = cut == std::string_view::npos ? std::string_view{} : rest.substr(cut + 1);
            if (piece.starts_with("0x") || piece.starts_with("0X")) piece.remove_prefix(2);
            if (piece.empty()) continue;
            for (char c : piece) {
                if (!std::isxdigit(static_cast<unsigned char>(c))) {
                    return fmt::format(
                        "'{}' is not hex: give the PDU as hex bytes, e.g. 03 00 00 00 0A", token);
                }
            }
            if (piece.size() == 1) {
                bytes.push_back(
                    static_cast<std::uint8_t>(std::stoul(std::string(piece), nullptr, 16)));
                continue;
            }
            if (piece.size() % 2 != 0) {
                return fmt::format(
                    "PDU token {} '{}' has an odd number of hex digits: give each byte as 1 or 2 "
                    "digits, or whole bytes run together (03 00 00 00 0A or 030000000A)",
                    position + 1, token);
            }
            for (std::size_t i = 0; i < piece.size(); i += 2) {
                bytes.push_back(static_cast<std::uint8_t>(
                    std::stoul(std::string(piece.substr(i, 2)), nullptr, 16)));
            }
        }
    }
    if (bytes.empty()) return std::string("no PDU: give at least the function code");
    return bytes;
}

// The stderr line for an answer that is no success; empty when the answer is one.
std::string answer_problem(std::span<const std::uint8_t> request,
                           std::span<const std::uint8_t> answer) {
    auto decoded = protocol::decode_response(answer);
    if (!decoded) {
        return fmt::format("bad answer: {}: {}: {}", protocol::function_name(answer[0]),
                           decoded.error().field, decoded.error().reason);
    }
    const auto* exception = std::get_if<protocol::ExceptionResponse>(&*decoded);
    if (exception == nullptr) return {};
    if (auto sent = protocol::decode_request(request)) {
        return client::describe_exception(*sent, exception->code);
    }
    return fmt::format("exception {:02X} {}: {}", static_cast<unsigned>(exception->code),
                       protocol::exception_name(exception->code),
                       protocol::exception_meaning(exception->code));
}

int run_raw(const RawOptions& options) {
    CommandOutput output("raw", options.client);
    auto pdu = parse_hex(options.hex);
    if (!pdu) return output.usage(pdu.error());
    return with_client(options.client, output, [&](client::Client& client, CommandOutput& out) {
        auto answer = client.raw(*pdu);
        if (!answer) return out.fail(answer.error());
        auto& document = out.document();
        document["request"] = client::hex_bytes(*pdu);
        document["request_fields"] = describe_request_pdu(*pdu);
        document["answer"] = client::hex_bytes(*answer);
        document["answer_fields"] = describe_response_pdu(*answer);
        if (!out.json()) {
            fmt::print("request  {}\n         {}\n", client::hex_bytes(*pdu),
                       describe_request_pdu(*pdu));
            fmt::print("answer   {}\n         {}\n", client::hex_bytes(*answer),
                       describe_response_pdu(*answer));
        }
        const std::string problem = answer_problem(*pdu, *answer);
        if (problem.empty()) return out.done();
        const bool exception = (answer->front() & protocol::kExceptionBit) != 0;
        return out.fail({exception ? client::ErrorKind::Exception : client::ErrorKind::BadAnswer,
                         problem,
                         exception && answer->size() == 2
                             ? std::optional(static_cast<protocol::ExceptionCode>((*answer)[1]))
                             : std::nullopt});
    });
}

// What `mblab --help` says of the command.
constexpr std::string_view kSummary =
    "Send any PDU (hex, function code first) and print the answer decoded";
constexpr std::string_view kHelp = R"(
The PDU goes out as given, without the checks the other commands make, framed for the
target (MBAP header, or address and CRC). The answer is printed as hex and as fields.
Each HEX token is one byte (1 or 2 digits: 0 is 00) or whole bytes run together (an even
number of digits); 123 is refused, being neither.
An address inside the PDU is the 0-based PDU offset: register 40001 is 00 00.
Exit status: 0 answered, 1 the device answered an exception or something that does not
decode, 2 usage error or unreachable target.
Example: mblab raw tcp://127.0.0.1:502 03 00 00 00 0A)";

}  // namespace

void add_raw_command(CLI::App& app, CommandRunner& runner) {
    auto [cmd, options] = add_client_command<RawOptions>(app, runner, "raw", std::string(kSummary),
                                                         help_text(kHelp), run_raw);
    cmd->add_option("hex", options->hex, "the PDU as hex bytes: 03 00 00 00 0A or 030000000A")
        ->required();
}

}  // namespace mblab::cli
