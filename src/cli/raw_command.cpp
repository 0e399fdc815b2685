#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <cctype>
#include <memory>
#include <string>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/pdu_text.hpp"
#include "client/answer_check.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"

// `mblab raw TARGET HEX...`: sends any PDU as given, unchecked, and prints the answer decoded.
namespace mblab::cli {

namespace {

struct RawOptions {
    ClientOptions client;
    std::vector<std::string> hex;
};

protocol::Result<std::vector<std::uint8_t>, std::string> parse_hex(
    const std::vector<std::string>& tokens) {
    std::string digits;
    for (auto token : tokens) {
        if (token.starts_with("0x") || token.starts_with("0X")) token.erase(0, 2);
        for (char c : token) {
            if (c == ' ' || c == ':') continue;
            if (!std::isxdigit(static_cast<unsigned char>(c))) {
                return fmt::format(
                    "'{}' is not hex: give the PDU as hex bytes, e.g. 03 00 00 00 0A", token);
            }
            digits += c;
        }
    }
    if (digits.size() % 2 != 0) return std::string("odd number of hex digits: give whole bytes");
    std::vector<std::uint8_t> bytes;
    for (std::size_t i = 0; i < digits.size(); i += 2) {
        bytes.push_back(static_cast<std::uint8_t>(std::stoul(digits.substr(i, 2), nullptr, 16)));
    }
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
        document["request"] = hex_bytes(*pdu);
        document["request_fields"] = describe_request_pdu(*pdu);
        document["answer"] = hex_bytes(*answer);
        document["answer_fields"] = describe_response_pdu(*answer);
        if (!out.json()) {
            fmt::print("request  {}\n         {}\n", hex_bytes(*pdu), describe_request_pdu(*pdu));
            fmt::print("answer   {}\n         {}\n", hex_bytes(*answer),
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

}  // namespace

void add_raw_command(CLI::App& app, CommandRunner& runner) {
    auto [cmd, options] = add_client_command<RawOptions>(
        app, runner, "raw", "Send any PDU (hex, function code first) and print the answer decoded",
        "The PDU goes out as given, without the checks the other commands make, framed for the\n"
        "target (MBAP header, or address and CRC). The answer is printed as hex and as fields.\n"
        "Exit status 1 when the device answers an exception or something that does not decode.\n"
        "Example: mblab raw tcp://127.0.0.1:502 03 00 00 00 0A",
        run_raw);
    cmd->add_option("hex", options->hex, "the PDU as hex bytes: 03 00 00 00 0A or 030000000A")
        ->required();
}

}  // namespace mblab::cli
