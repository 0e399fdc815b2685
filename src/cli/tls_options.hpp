#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "security/tls_channel.hpp"
#include "security/tls_context.hpp"

// The three files every command that speaks Modbus/TCP Security (mbaps://) takes.
namespace mblab::cli {

// --cert FILE, --key FILE, --ca FILE. `side` says whose certificate --cert is, for the help.
void add_tls_options(CLI::App& command, security::TlsFiles& files, const char* side);

// "TLSv1.3 TLS_AES_256_GCM_SHA384, server /CN=..., our role Operator": what -v prints.
std::string describe_tls(const security::TlsPeer& peer);

}  // namespace mblab::cli
