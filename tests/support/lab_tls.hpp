#pragma once

#include <gtest/gtest.h>

#include <string>

#include "security/tls_context.hpp"
#include "support/lab_pki.hpp"

// TLS contexts made from one lab PKI per test binary, for the tests that run Modbus/TCP Security
// over memory: making keys is the slow part.
namespace mblab::test {

inline const LabPki& shared_lab_pki() {
    static const LabPki pki("memory-tls");
    return pki;
}

inline security::TlsFiles lab_files(const std::string& name) {
    const auto& pki = shared_lab_pki();
    EXPECT_TRUE(pki.made()) << pki.error();
    return {pki.file(name + ".pem"), pki.file(name + ".key"), pki.file("ca.pem")};
}

inline security::SharedContext lab_server_context() {
    auto context = security::make_server_context(lab_files("server"));
    EXPECT_TRUE(context) << (context ? "" : context.error());
    return context ? *context : nullptr;
}

// A client with the certificate of `name` ("client-Operator", ...).
inline security::SharedContext lab_client_context(const std::string& name) {
    auto context = security::make_client_context(lab_files(name), {});
    EXPECT_TRUE(context) << (context ? "" : context.error());
    return context ? *context : nullptr;
}

}  // namespace mblab::test
