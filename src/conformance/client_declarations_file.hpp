#pragma once

#include <string>
#include <string_view>

#include "conformance/client_exam_scenarios.hpp"
#include "protocol/result.hpp"

// What a client declares about itself, from a TOML file: the keys are named as
// `mblab conform-client`'s flags are (client-unit, client-timeout in milliseconds,
// client-retries, client-pipelining, client-broadcast, error-pattern, value-pattern, address,
// count). Keys the file leaves out keep the values of `base`.
namespace mblab::conformance {

// One line naming the file, the line and what is wrong on error.
protocol::Result<ClientDeclarations, std::string> read_client_declarations(
    const std::string& path, ClientDeclarations base = {});
// The same from text, `name` standing for the file in errors (tests).
protocol::Result<ClientDeclarations, std::string> parse_client_declarations(
    std::string_view text, const std::string& name, ClientDeclarations base = {});

}  // namespace mblab::conformance
