#include "conformance/declaration_sources.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <functional>

#include "conformance/session.hpp"

namespace mblab::conformance {

void DeclarationSources::reset(std::string base) {
    base_ = std::move(base);
    sources_.clear();
}

void DeclarationSources::set(std::string_view key, std::string source) {
    sources_[std::string(key)] = std::move(source);
}

std::string DeclarationSources::operator()(std::string_view key) const {
    const auto found = sources_.find(std::string(key));
    return found == sources_.end() ? base_ : found->second;
}

void take_client_files_from_pki(Dut& dut, DeclarationSources& sources) {
    if (dut.security.pki.empty()) return;
    security::TlsFiles& client = dut.security.client;
    const std::filesystem::path dir = dut.security.pki;
    const std::string from_pki = fmt::format("the PKI directory ({})", sources("pki"));
    if (client.cert.empty() && client.key.empty()) {
        client.cert = (dir / "client-Administrator.pem").string();
        client.key = (dir / "client-Administrator.key").string();
        sources.set("client_cert", from_pki);
        sources.set("client_key", from_pki);
    }
    if (client.ca.empty()) {
        client.ca = (dir / "ca.pem").string();
        sources.set("ca", from_pki);
    }
}

Provenance make_provenance(const ToolIdentity& tool, Session& session,
                           const DeclarationSources& sources,
                           std::chrono::system_clock::time_point started, bool interrupted) {
    Provenance provenance;
    provenance.version = tool.version;
    provenance.commit = tool.commit;
    provenance.command_line = tool.argv;
    provenance.started = iso8601_utc(started);
    provenance.declared_by = session.dut().declared_by;
    provenance.declarations = declarations_of(session.dut(), std::cref(sources));
    if (interrupted) {
        provenance.device.reason = "not asked: the run was interrupted";
    } else {
        provenance.device = ask_device_identity(session);
    }
    provenance.finished = iso8601_utc(std::chrono::system_clock::now());
    return provenance;
}

}  // namespace mblab::conformance
