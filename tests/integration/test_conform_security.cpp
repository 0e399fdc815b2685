// The security suite against the reference device behind TLS, and against devices made wrong on
// purpose: each defect must fail the case that is about it, and only that case.
#include <gtest/gtest.h>
#include <openssl/ssl.h>
#include <openssl/x509_vfy.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <functional>

#include "client/target.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/device_dut.hpp"
#include "conformance/engine.hpp"
#include "device/profile_loader.hpp"
#include "device/reference_device.hpp"
#include "protocol/function_table.hpp"
#include "security/pki.hpp"
#include "security/tls_context.hpp"
#include "server/background_server.hpp"
#include "support/lab_pki.hpp"
#include "support/rewriting_handler.hpp"

namespace mblab::conformance {
namespace {

namespace fs = std::filesystem;
using test::LabPki;

const std::string kProfile = std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml";

// How a device is made wrong: in its TLS settings, or in how it authorizes requests.
enum class Wrong {
    Nothing,
    AcceptsTls11,         // TLS 1.1 and 1.2+ (R-34 forbids the fallback)
    NoCertificateNeeded,  // asks for a client certificate but goes on without one
    TrustsForeignCa,      // the foreign CA is trusted beside the lab's
    IgnoresRoles,         // every role may do everything
    DeniesWith02,         // refuses writes with exception 02, not 01 (and ignores roles)
};

// Answers every write with exception 02, whoever asks: from the client's side, a device that
// refuses a role's write with the wrong exception code.
std::optional<std::vector<std::uint8_t>> write_answered_02(std::span<const std::uint8_t> request) {
    const auto* row = protocol::find_function(request.front());
    if (row == nullptr || row->writes != protocol::Writes::Yes) return std::nullopt;
    return std::vector<std::uint8_t>{static_cast<std::uint8_t>(request.front() | 0x80), 0x02};
}

class ConformSecurity : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        pki_ = new LabPki("conform-security");
        ASSERT_TRUE(pki_->made()) << pki_->error();
    }
    static void TearDownTestSuite() { delete pki_; }
    static std::string file(const std::string& name) { return pki_->file(name); }

    // Starts the device made wrong as `wrong` says and runs the security suite against it.
    RunResult run(Wrong wrong) {
        auto profile = device::read_profile(kProfile);
        EXPECT_TRUE(profile.ok());
        Dut dut = dut_from_profile(profile.value(), "test");
        auto roles = profile->roles;
        device_ = std::make_unique<device::ReferenceDevice>(std::move(profile.value()));
        device::RequestHandler* handler = device_.get();

        auto context =
            security::make_server_context({file("server.pem"), file("server.key"), file("ca.pem")});
        EXPECT_TRUE(context.ok()) << context.error();
        SSL_CTX* ctx = context->get();
        switch (wrong) {
            case Wrong::AcceptsTls11:
                SSL_CTX_set_min_proto_version(ctx, TLS1_1_VERSION);
                SSL_CTX_set_cipher_list(ctx, "DEFAULT:@SECLEVEL=0");
                break;
            case Wrong::NoCertificateNeeded:
                SSL_CTX_set_verify(ctx, SSL_VERIFY_PEER, nullptr);
                break;
            case Wrong::TrustsForeignCa:
                EXPECT_EQ(X509_STORE_load_file(SSL_CTX_get_cert_store(ctx),
                                               file("foreign-ca.pem").c_str()),
                          1);
                break;
            case Wrong::DeniesWith02:
                wrapper_ = std::make_unique<test::RewritingHandler>(*device_, write_answered_02);
                handler = wrapper_.get();
                [[fallthrough]];
            case Wrong::IgnoresRoles:
                roles.clear();
                for (const char* name : {"ReadOnly", "Operator", "Administrator"}) {
                    device::RoleRule everything;  // no limits: every code, unit and address
                    everything.role = name;
                    roles.push_back(everything);
                }
                break;
            case Wrong::Nothing:
                break;
        }
        server::ServerOptions options;
        options.tls = *context;
        options.roles = std::make_shared<const device::RoleRules>(roles);
        server_ = std::make_unique<server::BackgroundServer>(*handler, options);
        auto port = server_->start();
        EXPECT_TRUE(port.ok());

        dut.security.pki = pki_->dir().string();
        dut.security.client = {file("client-Administrator.pem"), file("client-Administrator.key"),
                               file("ca.pem")};
        auto target = client::parse_target("mbaps://127.0.0.1:" + std::to_string(*port));
        EXPECT_TRUE(target.ok());
        EXPECT_EQ(client::attach_tls(*target, dut.security.client), "");
        auto suite = load_suite_file(std::string(MBLAB_SOURCE_DIR) + "/catalogue/security.toml");
        EXPECT_TRUE(suite.ok());
        EngineOptions engine;
        engine.timeout = std::chrono::milliseconds(500);
        Session session(*target, dut, engine);
        Engine runner(session);
        return runner.run({suite.value()}, target->name);
    }

    static const CaseResult& find(const RunResult& run, const std::string& id) {
        for (const auto& c : run.suites.at(0).cases) {
            if (c.id == id) return c;
        }
        throw std::runtime_error("no case " + id);
    }

    // Every case but `failing` passes.
    static void expect_only_failures(const RunResult& run,
                                     const std::vector<std::string>& failing) {
        for (const auto& c : run.suites.at(0).cases) {
            const bool fails = std::count(failing.begin(), failing.end(), c.id) > 0;
            EXPECT_EQ(c.outcome.verdict, fails ? Verdict::Fail : Verdict::Pass)
                << c.id << ": " << c.outcome.reason;
        }
    }

    static LabPki* pki_;
    std::unique_ptr<device::ReferenceDevice> device_;
    std::unique_ptr<test::RewritingHandler> wrapper_;
    std::unique_ptr<server::BackgroundServer> server_;
};

LabPki* ConformSecurity::pki_ = nullptr;

TEST_F(ConformSecurity, ReferenceDevicePassesEveryCase) {
    auto result = run(Wrong::Nothing);
    ASSERT_EQ(result.suites.at(0).cases.size(), 12U);
    expect_only_failures(result, {});
    EXPECT_NE(find(result, "sec.1").outcome.reason.find("TLSv1.3"), std::string::npos)
        << find(result, "sec.1").outcome.reason;
    EXPECT_NE(find(result, "sec.2").outcome.reason.find("protocol version"), std::string::npos)
        << find(result, "sec.2").outcome.reason;
    EXPECT_EQ(find(result, "sec.8").outcome.reason,
              "19 function codes, each answered exception 01");
    EXPECT_NE(find(result, "sec.9").outcome.reason.find("role ReadOnly"), std::string::npos);
}

TEST_F(ConformSecurity, DeviceAcceptingTls11FailsTheTls11Case) {
    auto result = run(Wrong::AcceptsTls11);
    expect_only_failures(result, {"sec.3"});
    EXPECT_NE(find(result, "sec.3").outcome.reason.find("completed a TLS 1.1 handshake"),
              std::string::npos)
        << find(result, "sec.3").outcome.reason;
}

TEST_F(ConformSecurity, DeviceGoingOnWithoutACertificateFailsTheNoCertificateCase) {
    auto result = run(Wrong::NoCertificateNeeded);
    expect_only_failures(result, {"sec.4"});
    EXPECT_NE(find(result, "sec.4").outcome.reason.find("accepted a client with no certificate"),
              std::string::npos)
        << find(result, "sec.4").outcome.reason;
}

TEST_F(ConformSecurity, DeviceTrustingAForeignCaFailsTheForeignCaCase) {
    auto result = run(Wrong::TrustsForeignCa);
    expect_only_failures(result, {"sec.6"});
    EXPECT_NE(find(result, "sec.6").outcome.reason.find("a certificate from another CA"),
              std::string::npos)
        << find(result, "sec.6").outcome.reason;
}

TEST_F(ConformSecurity, DeviceIgnoringRolesFailsTheReadOnlyRoleCase) {
    auto result = run(Wrong::IgnoresRoles);
    expect_only_failures(result, {"sec.9"});
    EXPECT_NE(find(result, "sec.9").outcome.reason.find("function 06 write got answered"),
              std::string::npos)
        << find(result, "sec.9").outcome.reason;
}

TEST_F(ConformSecurity, DeviceRefusingWithException02FailsTheRoleCases) {
    auto result = run(Wrong::DeniesWith02);
    // The read-only role's write must be 01; the write role's write must be answered at all.
    expect_only_failures(result, {"sec.9", "sec.10"});
    EXPECT_NE(find(result, "sec.9").outcome.reason.find("got exception 02"), std::string::npos)
        << find(result, "sec.9").outcome.reason;
}

}  // namespace
}  // namespace mblab::conformance
