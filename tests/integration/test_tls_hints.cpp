// What a vendor is told about TLS: a plain tcp:// client that reaches a TLS port (our own mbaps
// server, OpenSSL's s_server) says so in one line, and over mbaps:// an exception 01 that the
// certificate's role may explain says that too.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "device/profile_loader.hpp"
#include "device/reference_device.hpp"
#include "security/tls_context.hpp"
#include "server/background_server.hpp"
#include "support/lab_pki.hpp"
#include "support/ports.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::EndsWith;
using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

class TlsHints : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        pki_ = new LabPki("tls-hints");
        ASSERT_TRUE(pki_->made()) << pki_->error();
    }
    static void TearDownTestSuite() { delete pki_; }

    void SetUp() override {
        auto loaded =
            device::load_profile(std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml");
        ASSERT_TRUE(loaded) << loaded.error();
        device_ = std::move(loaded.value());
        server::ServerOptions options;
        auto context =
            security::make_server_context({file("server.pem"), file("server.key"), file("ca.pem")});
        ASSERT_TRUE(context) << context.error();
        options.tls = *context;
        options.roles =
            std::make_shared<const device::RoleRules>(device_->declarations().profile().roles);
        server_ = std::make_unique<server::BackgroundServer>(*device_, options);
        auto port = server_->start();
        ASSERT_TRUE(port) << port.error();
        port_ = *port;
    }

    static std::string file(const std::string& name) { return pki_->file(name); }

    static LabPki* pki_;
    std::unique_ptr<device::ReferenceDevice> device_;
    std::unique_ptr<server::BackgroundServer> server_;
    std::uint16_t port_ = 0;
};

LabPki* TlsHints::pki_ = nullptr;

// The one line a client command prints for a TLS server at 127.0.0.1:`port`.
void expect_told_to_use_mbaps(const Ran& ran, const std::string& command, std::uint16_t port) {
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.err, StartsWith("mblab " + command + ": the server at 127.0.0.1:" +
                                    std::to_string(port) + " answered with TLS bytes (16 03 03 "));
    EXPECT_THAT(ran.err, EndsWith("): use mbaps://\n"));
    EXPECT_EQ(std::count(ran.err.begin(), ran.err.end(), '\n'), 1) << ran.err;
}

TEST_F(TlsHints, PlainClientCommandsOfAnMbapsPortAreToldToUseMbaps) {
    const std::string target = "tcp://127.0.0.1:" + std::to_string(port_);
    expect_told_to_use_mbaps(run_mblab({"read", target, "holding", "0", "1"}), "read", port_);
    expect_told_to_use_mbaps(run_mblab({"write", target, "register", "0", "1"}), "write", port_);
    expect_told_to_use_mbaps(run_mblab({"raw", target, "03 00 00 00 01"}), "raw", port_);
    EXPECT_EQ(server::ServerStats::read(server_->stats().requests), 0U);
}

TEST_F(TlsHints, ConformOverTcpToAnMbapsPortSaysUseMbaps) {
    auto ran = run_mblab({"conform", "tcp://127.0.0.1:" + std::to_string(port_), "--suite",
                          "function-codes", "--case", "fc01.1"});
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("FAIL     fc01.1  Read coils, quantity 1  (the server at "
                                   "127.0.0.1:" +
                                   std::to_string(port_) + " answered with TLS bytes (16 03 03 "));
    EXPECT_THAT(ran.out, HasSubstr("): use mbaps://)\n"));
}

// Over mbaps:// as the read-only role, the reference device's role rules refuse writes with 01:
// the reason says the role may be why, next to the function not being served.
TEST_F(TlsHints, AnException01OverMbapsNamesTheCertificatesRole) {
    auto ran = run_mblab({"conform", "mbaps://127.0.0.1:" + std::to_string(port_), "--cert",
                          file("client-ReadOnly.pem"), "--key", file("client-ReadOnly.key"), "--ca",
                          file("ca.pem"), "--suite", "function-codes", "--case", "fc10.3"});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("N/A      fc10.3  Write multiple registers, quantity 0 answers "
                                   "03  (the device answered exception 01: function 10 is not "
                                   "supported, or the certificate's role ReadOnly may not write "
                                   "([SEC] R-31))"));
    // As the administrator, nothing is refused and no role is blamed.
    auto admin =
        run_mblab({"conform", "mbaps://127.0.0.1:" + std::to_string(port_), "--cert",
                   file("client-Administrator.pem"), "--key", file("client-Administrator.key"),
                   "--ca", file("ca.pem"), "--suite", "function-codes", "--case", "fc10.3"});
    EXPECT_EQ(admin.status, 0) << admin.out << admin.err;
    EXPECT_THAT(admin.out, HasSubstr("PASS     fc10.3 "));
    EXPECT_THAT(admin.out, Not(HasSubstr("certificate's role")));
}

bool accepts(std::uint16_t port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(port);
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const bool connected =
        ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
    ::close(fd);
    return connected;
}

TEST_F(TlsHints, APlainClientOfOpensslsServerIsToldToUseMbaps) {
    if (::access("/usr/bin/openssl", X_OK) != 0) GTEST_SKIP() << "the openssl CLI is not installed";
    const std::uint16_t port = closed_port();
    ChildProcess openssl({"/usr/bin/openssl", "s_server", "-quiet", "-accept", std::to_string(port),
                          "-cert", file("server.pem"), "-key", file("server.key")});
    ASSERT_TRUE(openssl.started());
    for (int wait = 0; wait < 100 && !accepts(port); ++wait)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    expect_told_to_use_mbaps(
        run_mblab({"read", "tcp://127.0.0.1:" + std::to_string(port), "holding", "0", "1"}), "read",
        port);
}

}  // namespace
}  // namespace mblab::test
