#pragma once

#include <map>
#include <memory>
#include <string>

#include "conformance/client_exam_scenarios.hpp"
#include "protocol/result.hpp"
#include "security/temporary_pki.hpp"
#include "security/tls_context.hpp"

// The examiner's side of Modbus/TCP Security: a lab PKI (one made for the run, or one `mblab pki`
// wrote), a TLS server context for each server certificate the scenarios present, and the files
// the client is given in {ca}, {cert} and {key}.
namespace mblab::conformance {

class ExamTls {
  public:
    // `pki`: a directory in mblab pki's layout; empty: a lab PKI made for the run and removed
    // afterwards.
    static protocol::Result<std::unique_ptr<ExamTls>, std::string> open(const std::string& pki);
    ExamTls(const ExamTls&) = delete;
    ExamTls& operator=(const ExamTls&) = delete;

    // The context that presents the scenario's certificate (the good one when it names none).
    const security::SharedContext& context(const ClientCase& scenario) const;
    const std::string& dir() const { return dir_; }
    std::string ca() const { return file("ca.pem"); }
    // The client's certificate: the PKI's client-norole, which every mblab pki writes and whose
    // NULL role the examiner does not judge.
    std::string cert() const { return file("client-norole.pem"); }
    std::string key() const { return file("client-norole.key"); }

  private:
    ExamTls() = default;
    std::string file(const std::string& name) const { return dir_ + "/" + name; }

    security::TemporaryPki made_;
    std::string dir_;
    std::map<std::string, security::SharedContext> contexts_;  // by certificate name
};

}  // namespace mblab::conformance
