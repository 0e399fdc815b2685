#include "conformance/client_exam_tls.hpp"

namespace mblab::conformance {

namespace {

constexpr const char* kGoodCertificate = "server";

const std::string& certificate_of(const ClientCase& scenario) {
    static const std::string good = kGoodCertificate;
    return scenario.certificate.empty() ? good : scenario.certificate;
}

}  // namespace

protocol::Result<std::unique_ptr<ExamTls>, std::string> ExamTls::open(const std::string& pki) {
    std::unique_ptr<ExamTls> tls(new ExamTls());
    if (pki.empty()) {
        if (auto error = tls->made_.make("conform-client-pki"); !error.empty()) return error;
        tls->dir_ = tls->made_.dir().string();
    } else {
        tls->dir_ = pki;
    }
    for (const auto& scenario : client_mbaps_cases()) {
        const auto& name = certificate_of(scenario);
        if (tls->contexts_.contains(name)) continue;
        // The CA verifies the client's certificate; a foreign-CA server certificate is the
        // examiner's own and needs no verifying here.
        auto context = security::make_server_context(
            {tls->file(name + ".pem"), tls->file(name + ".key"), tls->ca()});
        if (!context) return "--pki " + tls->dir_ + ": " + context.error();
        tls->contexts_.emplace(name, std::move(context.value()));
    }
    return tls;
}

const security::SharedContext& ExamTls::context(const ClientCase& scenario) const {
    return contexts_.at(certificate_of(scenario));
}

}  // namespace mblab::conformance
