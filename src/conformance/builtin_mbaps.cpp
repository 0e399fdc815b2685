#include "conformance/builtin_mbaps.hpp"

#include <fmt/format.h>

#include <memory>
#include <utility>

#include "conformance/procedures.hpp"
#include "device/profile_loader.hpp"
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

std::string BuiltinMbaps::start(const std::filesystem::path& profile, Dut& dut,
                                client::Target& secure) {
    if (auto error = pki_.make("conform-pki"); !error.empty()) return error;
    const auto file = [&](const char* name) { return pki_.file(name); };
    auto context =
        security::make_server_context({file("server.pem"), file("server.key"), file("ca.pem")});
    if (!context) return context.error();
    auto loaded = device::read_profile(profile);
    if (!loaded) return loaded.error();
    server::ServerOptions options;
    options.tls = std::move(context.value());
    options.roles = std::make_shared<const device::RoleRules>(loaded->roles);
    auto port = device_.serve(std::move(loaded.value()), std::move(options));
    if (!port) return "cannot start the reference device over mbaps: " + port.error();
    dut.security.pki = pki_.dir().string();
    dut.security.client = {file("client-Administrator.pem"), file("client-Administrator.key"),
                           file("ca.pem")};
    auto parsed = client::parse_target(fmt::format("mbaps://127.0.0.1:{}", *port));
    if (!parsed) return parsed.error();
    secure = std::move(parsed.value());
    return client::attach_tls(secure, dut.security.client);
}

}  // namespace mblab::conformance
