#include "conformance/builtin_mbaps.hpp"

#include <fmt/format.h>
#include <stdlib.h>

#include <cerrno>
#include <cstring>

#include "conformance/procedures.hpp"
#include "device/profile_loader.hpp"
#include "security/pki.hpp"
#include "security/tls_context.hpp"

namespace mblab::conformance {

bool uses_mbaps(const std::vector<Suite>& suites) {
    for (const auto& suite : suites) {
        for (const auto& c : suite.cases) {
            if (is_security_procedure(c.procedure)) return true;
        }
    }
    return false;
}

BuiltinMbaps::~BuiltinMbaps() {
    server_.reset();
    if (!dir_.empty()) {
        std::error_code ignored;
        std::filesystem::remove_all(dir_, ignored);
    }
}

std::string BuiltinMbaps::start(const std::filesystem::path& profile, Dut& dut,
                                client::Target& secure) {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "mblab-conform-pki-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) {
        return fmt::format("cannot make a directory for the lab PKI: {}", std::strerror(errno));
    }
    dir_ = pattern;
    security::PkiRequest request;
    request.overwrite = true;  // the directory is new, and mkdtemp made it
    if (auto made = security::make_lab_pki(dir_, request); !made) return made.error();
    const auto file = [&](const char* name) { return (dir_ / name).string(); };
    auto context =
        security::make_server_context({file("server.pem"), file("server.key"), file("ca.pem")});
    if (!context) return context.error();
    auto loaded = device::read_profile(profile);
    if (!loaded) return loaded.error();
    server::ServerOptions options;
    options.tls = std::move(context.value());
    options.roles = std::make_shared<const device::RoleRules>(loaded->roles);
    device_ = std::make_unique<device::ReferenceDevice>(std::move(loaded.value()));
    server_ = std::make_unique<server::BackgroundServer>(*device_, options);
    auto port = server_->start();
    if (!port) return "cannot start the reference device over mbaps: " + port.error();
    dut.security.pki = dir_.string();
    dut.security.client = {file("client-Administrator.pem"), file("client-Administrator.key"),
                           file("ca.pem")};
    auto parsed = client::parse_target(fmt::format("mbaps://127.0.0.1:{}", *port));
    if (!parsed) return parsed.error();
    secure = std::move(parsed.value());
    return client::attach_tls(secure, dut.security.client);
}

}  // namespace mblab::conformance
