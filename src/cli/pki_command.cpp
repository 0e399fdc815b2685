#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cli/commands.hpp"
#include "security/pki.hpp"

// `mblab pki DIR`: a lab PKI for Modbus/TCP Security (mbaps): a CA, a server certificate, one
// client certificate per role, and the client certificates a conformant server must refuse.
namespace mblab::cli {

namespace {

namespace fs = std::filesystem;

struct PkiOptions {
    std::string dir;
    std::vector<std::string> roles;
    std::vector<std::string> server_names;
    int days = 365;
    std::string key_type = "ec";
    bool force = false;
};

int usage_error(const std::string& message) {
    fmt::print(stderr, "mblab pki: {}\n", message);
    return kExitUsage;
}

// A path as it can be pasted into a shell: quoted when it holds anything a shell would split
// or expand.
std::string shell_word(const std::string& text) {
    const bool plain = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) != 0 ||
               std::string_view("/._-+,:@%").find(c) != std::string_view::npos;
    });
    if (plain) return text;
    std::string quoted = "'";
    for (const char c : text) {
        quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return quoted + "'";
}

int run_pki(const PkiOptions& options) {
    security::PkiRequest request;
    if (!options.roles.empty()) request.roles = options.roles;
    if (!options.server_names.empty()) request.server_names = options.server_names;
    request.days = options.days;
    request.key_type = options.key_type == "rsa" ? security::PkiRequest::KeyType::Rsa
                                                 : security::PkiRequest::KeyType::Ec;
    request.overwrite = options.force;
    auto written = security::make_lab_pki(options.dir, request);
    if (!written) {
        if (!options.force && written.error().ends_with(" exists already")) {
            return usage_error(written.error() + "; --force replaces the files");
        }
        return usage_error(written.error());
    }
    for (const auto& path : *written)
        fmt::print("{}\n", path.string());

    // The role a reader most likely wants to try first: Operator when there is one.
    const auto& roles = request.roles;
    const std::string client =
        roles.empty()
            ? "client-norole"
            : "client-" + (std::find(roles.begin(), roles.end(), "Operator") != roles.end()
                               ? std::string("Operator")
                               : roles.front());
    const auto file = [&](const std::string& name) {
        return shell_word((fs::path(options.dir) / name).string());
    };
    fmt::print(
        "next: serve with the server certificate, then read as a client (docs/security.md)\n");
    fmt::print("  mblab serve --listen mbaps://127.0.0.1:8802 --cert {} --key {} --ca {} &\n",
               file("server.pem"), file("server.key"), file("ca.pem"));
    fmt::print("  mblab read mbaps://127.0.0.1:8802 holding 0 4 --cert {} --key {} --ca {}\n",
               file(client + ".pem"), file(client + ".key"), file("ca.pem"));
    return kExitOk;
}

// What `mblab --help` says of the command.
constexpr std::string_view kSummary =
    "Make a lab PKI for Modbus/TCP Security (mbaps): a CA, a server certificate, a client "
    "certificate per role, and client certificates a conformant server must refuse";
constexpr std::string_view kHelp = R"(
Writes NAME.pem and NAME.key (mode 0600) into DIR (made mode 0700 when missing):
ca, server, client-ROLE for each role, client-norole (no role: the NULL role),
client-expired, client-foreign-ca (signed by foreign-ca), client-self-signed,
client-two-roles and client-ia5-role (the role not a UTF8String), and the server
certificates a client must refuse: server-expired, server-foreign-ca and
server-wrong-name (named wrong-name.invalid only). The role is in
extension 1.3.6.1.4.1.50316.802.1. Keys are unencrypted: test material only.
Exit status: 0 written, 2 usage error, a file exists (without --force) or cannot be
written; nothing is written then.
Example: mblab pki lab-pki --role Operator --role Engineer)";

}  // namespace

void add_pki_command(CLI::App& app, CommandRunner& runner) {
    auto [cmd, options] = add_command<PkiOptions>(app, runner, "pki", std::string(kSummary),
                                                  help_text(kHelp), run_pki);
    cmd->add_option("dir", options->dir, "directory to write into")->required();
    cmd->add_option("--role", options->roles,
                    "a role to make client-ROLE.pem for: printable UTF-8, no '/'; repeatable "
                    "(default: ReadOnly, Operator, Administrator)")
        ->allow_extra_args(false);
    cmd->add_option("--server-name", options->server_names,
                    "a DNS name or IP address for the server certificate's subjectAltName; "
                    "repeatable (default: localhost, 127.0.0.1, ::1)")
        ->allow_extra_args(false);
    cmd->add_option("--days", options->days, "days the certificates are valid for")
        ->check(CLI::Range(1, security::kMaxPkiDays))
        ->capture_default_str();
    cmd->add_option("--key-type", options->key_type,
                    "ec (ECDSA P-256, the [SEC] minimum) or rsa (RSA 2048)")
        ->check(CLI::IsMember({"ec", "rsa"}))
        ->capture_default_str();
    cmd->add_flag("--force", options->force, "replace files an earlier run wrote");
}

}  // namespace mblab::cli
