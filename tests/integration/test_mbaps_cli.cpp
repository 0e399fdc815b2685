// Modbus/TCP Security end to end: the reference device behind TLS with its shipped role rules, and
// the real binary's client commands, load and serve against it, with a lab PKI from mblab pki.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "blocking_client.hpp"
#include "client/target.hpp"
#include "device/profile_loader.hpp"
#include "device/reference_device.hpp"
#include "load_cli_support.hpp"
#include "security/pki.hpp"
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

namespace fs = std::filesystem;

class MbapsCli : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        pki_ = new LabPki("mbaps-cli");
        ASSERT_TRUE(pki_->made()) << pki_->error();
    }
    static void TearDownTestSuite() { delete pki_; }

    void SetUp() override {
        auto loaded =
            device::load_profile(std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml");
        ASSERT_TRUE(loaded) << loaded.error();
        device_ = std::move(loaded.value());
        start_server(server::ServerOptions().max_connections);
    }

    void start_server(std::size_t max_connections) {
        server_.reset();
        server::ServerOptions options;
        options.max_connections = max_connections;
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
        target_ = "mbaps://localhost:" + std::to_string(*port);
    }

    static std::string file(const std::string& name) { return pki_->file(name); }
    // --cert/--key/--ca of a client certificate of the lab PKI.
    static std::vector<std::string> as(const std::string& client) {
        return {"--cert", file(client + ".pem"), "--key", file(client + ".key"),
                "--ca",   file("ca.pem")};
    }
    Ran mblab(std::vector<std::string> args, const std::string& client) const {
        args.insert(args.begin() + 1, target_);
        for (auto& arg : as(client))
            args.push_back(arg);
        return run_mblab(args);
    }

    // One second of FC 03 traffic from `connections` connections as `client`.
    LoadRun load_as(const std::string& name, const std::string& client,
                    const std::string& connections) const {
        std::vector<std::string> args = {target_,     "--duration", "1s",    "--connections",
                                         connections, "--no-tests", "--mix", "fc3:10=100"};
        for (auto& arg : as(client))
            args.push_back(arg);
        return mblab_load(name, args);
    }

    static LabPki* pki_;
    std::unique_ptr<device::ReferenceDevice> device_;
    std::unique_ptr<server::BackgroundServer> server_;
    std::uint16_t port_ = 0;
    std::string target_;
};

LabPki* MbapsCli::pki_ = nullptr;

TEST_F(MbapsCli, OperatorReadsAndWritesAndVerboseNamesTheSession) {
    auto wrote = mblab({"write", "register", "30", "4660"}, "client-Operator");
    ASSERT_EQ(wrote.status, 0) << wrote.err;
    auto read = mblab({"read", "holding", "30", "1", "--json", "-v"}, "client-Operator");
    ASSERT_EQ(read.status, 0) << read.err;
    EXPECT_EQ(nlohmann::json::parse(read.out)["values"][0]["value"], 4660);
    EXPECT_THAT(read.err, HasSubstr("TLS: TLSv1.3"));
    EXPECT_THAT(read.err, HasSubstr("we presented role Operator"));
    EXPECT_EQ(server::ServerStats::read(server_->stats().tls_handshakes), 2U);
}

TEST_F(MbapsCli, ReadOnlyRoleIsRefusedAWriteWithException01) {
    auto wrote = mblab({"write", "register", "31", "1"}, "client-ReadOnly");
    EXPECT_EQ(wrote.status, 1);
    EXPECT_THAT(wrote.err, HasSubstr("exception 01"));
    EXPECT_EQ(server::ServerStats::read(server_->stats().denied), 1U);
    auto read = mblab({"read", "holding", "31", "1", "--json"}, "client-ReadOnly");
    ASSERT_EQ(read.status, 0) << read.err;
    EXPECT_EQ(nlohmann::json::parse(read.out)["values"][0]["value"], 0);
    auto diag = mblab({"diag", "0", "0x1234"}, "client-ReadOnly");
    EXPECT_EQ(diag.status, 1) << diag.out << diag.err;
    EXPECT_THAT(diag.err, HasSubstr("exception 01"));
}

TEST_F(MbapsCli, RefusedCertificatesAreOneLineNamingTheProblem) {
    for (const char* client : {"client-expired", "client-foreign-ca", "client-ia5-role"}) {
        auto read = mblab({"read", "holding", "0", "1"}, client);
        EXPECT_NE(read.status, 0) << client;
        EXPECT_EQ(std::count(read.err.begin(), read.err.end(), '\n'), 1) << read.err;
        EXPECT_THAT(read.err, HasSubstr("TLS")) << client << ": " << read.err;
    }
    EXPECT_EQ(server::ServerStats::read(server_->stats().tls_refused), 3U);
    EXPECT_EQ(server::ServerStats::read(server_->stats().requests), 0U);
}

// The tester over mbaps://: the security suite with the lab PKI, and policy cases inside TLS.
TEST_F(MbapsCli, ConformRunsTheSecuritySuiteAndThePolicyInsideTls) {
    auto ran = run_mblab({"conform", target_, "--pki", pki_->dir().string(), "--read-only-role",
                          "ReadOnly", "--write-role", "Operator", "--suite", "security", "--suite",
                          "policy-2.1", "--case", "sec.*", "--case", "7.*", "--case", "9.*"});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    for (const char* line :
         {"PASS     sec.1 ", "PASS     sec.4 ", "PASS     sec.8 ", "PASS     sec.9 ",
          "PASS     sec.12 ", "PASS     7.8.1 ", "PASS     9.1.1 "}) {
        EXPECT_THAT(ran.out, HasSubstr(line)) << line << "\n" << ran.out;
    }
    EXPECT_EQ(ran.out.find("FAIL"), std::string::npos) << ran.out;
    // Every policy request went over TLS, as client-Administrator, the PKI's default.
    EXPECT_GT(server::ServerStats::read(server_->stats().tls_handshakes), 10U);
    EXPECT_EQ(server::ServerStats::read(server_->stats().denied), 19U + 2U);
}

TEST_F(MbapsCli, ConformWithoutTheRolesOrThePkiSaysWhatIsMissing) {
    auto ran = run_mblab({"conform", target_, "--suite", "security", "--cert",
                          file("client-Administrator.pem"), "--key",
                          file("client-Administrator.key"), "--ca", file("ca.pem")});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("N/A      sec.5   "));
    EXPECT_THAT(ran.out, HasSubstr("the DUT does not declare pki (--pki DIR"));
    EXPECT_THAT(ran.out, HasSubstr("PASS     sec.4 "));
    auto plain = run_mblab({"conform", "tcp://127.0.0.1:1", "--pki", pki_->dir().string()});
    expect_failed(plain, 2, "mblab conform: --pki is for mbaps:// targets only\n");
    auto builtin = run_mblab({"conform", "--cert", "x.pem"});
    EXPECT_EQ(builtin.status, 2);
    EXPECT_EQ(builtin.err,
              "mblab conform: --cert is for mbaps:// targets; the built-in device makes its own "
              "lab PKI\n");
}

TEST(ConformBuiltin, SecuritySuiteRunsAgainstTheBuiltInDeviceOverMbaps) {
    auto ran = run_mblab({"conform", "--suite", "security"});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out,
                HasSubstr("(built-in reference device, profile reference (shipped); over mbaps "
                          "at mbaps://127.0.0.1:"));
    EXPECT_THAT(ran.out, HasSubstr("12 passed, 0 failed"));
}

TEST(ConformBuiltin, ADutFileKeepsTheRunsOwnLabPki) {
    const auto dut = fs::temp_directory_path() / ("mblab-dut-" + std::to_string(::getpid()));
    { std::ofstream(dut) << "unit = 1\nread_only_role = \"ReadOnly\"\n"; }
    auto ran = run_mblab({"conform", "--suite", "security", "--dut", dut.string()});
    fs::remove(dut);
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("PASS     sec.5 "));
    EXPECT_THAT(ran.out, HasSubstr("PASS     sec.9 "));
    // The file declares no write role, and replaces what the profile said.
    EXPECT_THAT(ran.out, HasSubstr("N/A      sec.10 "));
}

TEST_F(MbapsCli, MissingOrMisplacedFilesAreUsageErrors) {
    auto none = run_mblab({"read", target_, "holding", "0", "1"});
    EXPECT_EQ(none.status, 2);
    EXPECT_THAT(none.err, HasSubstr("--cert FILE is required for mbaps://"));
    auto missing = run_mblab({"read", target_, "holding", "0", "1", "--cert", "/nonexistent.pem",
                              "--key", file("client-Operator.key"), "--ca", file("ca.pem")});
    expect_failed(missing, 2, "mblab read: --cert /nonexistent.pem: No such file or directory\n");
    auto plain = run_mblab({"read", "tcp://127.0.0.1:1", "holding", "0", "1", "--cert", "x"});
    expect_failed(plain, 2, "mblab read: --cert, --key and --ca are for mbaps:// targets only\n");
}

TEST_F(MbapsCli, LoadOverTlsCountsHandshakesAndPasses) {
    auto run = load_as("mbaps_load", "client-Administrator", "4");
    ASSERT_EQ(run.status, 0) << run.out << run.err;
    const auto& node = run.report["nodes"][0];
    expect_clean(node);
    EXPECT_EQ(node["tls_handshakes"], 4);
    EXPECT_GT(node["answers"].get<std::uint64_t>(), 0U);
    EXPECT_THAT(run.out, HasSubstr("4 TLS handshakes"));
}

TEST_F(MbapsCli, LoadWithARoleThatMayNotReadFails) {
    auto run = load_as("mbaps_load_norole", "client-norole", "1");
    EXPECT_EQ(run.status, 1) << run.out << run.err;
    EXPECT_GT(failures(run.report["nodes"][0], "exception"), 0U) << run.report.dump();
}

// The robustness tester inside TLS: every case on a TLS connection of its own, the checks too.
TEST_F(MbapsCli, FuzzRunsItsCasesInsideTls) {
    auto ran = mblab({"fuzz", "--cases", "60", "--rate", "0"}, "client-Operator");
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("mblab fuzz mbaps://"));
    EXPECT_THAT(ran.out, HasSubstr("no finding"));
    // Reconnaissance, then at least a case and a check each on connections of their own.
    EXPECT_GT(server::ServerStats::read(server_->stats().tls_handshakes), 120U);
    // A role that may not read leaves nothing to check liveness with: one line, status 2.
    auto norole = mblab({"fuzz", "--cases", "10"}, "client-norole");
    EXPECT_EQ(norole.status, 2) << norole.out << norole.err;
    EXPECT_THAT(norole.err, HasSubstr("answers FC 03 with unit 1"));
    EXPECT_EQ(std::count(norole.err.begin(), norole.err.end(), '\n'), 1) << norole.err;
    auto no_certificate = run_mblab({"fuzz", target_, "--cases", "10"});
    EXPECT_EQ(no_certificate.status, 2) << no_certificate.err;
    EXPECT_EQ(std::count(no_certificate.err.begin(), no_certificate.err.end(), '\n'), 1)
        << no_certificate.err;
}

// An attack run opened more TLS handshakes than --max-connections and never finished them: each
// newcomer evicted the oldest idle connection, the authenticated session, before every poll. A
// connection still in its handshake is now the one to go.
TEST_F(MbapsCli, UnfinishedHandshakesDoNotEvictAnAuthenticatedSession) {
    constexpr std::size_t kMaxConnections = 4;
    start_server(kMaxConnections);
    auto target = client::parse_target(target_);
    ASSERT_TRUE(target) << target.error();
    ASSERT_EQ(client::attach_tls(*target, {file("client-Operator.pem"), file("client-Operator.key"),
                                           file("ca.pem")}),
              "");
    auto link = client::open_link(*target, std::chrono::seconds(5));
    ASSERT_TRUE(link) << link.error().message;
    auto& session = *link.value();
    auto poll = [&](std::uint8_t id) {
        const std::vector<std::uint8_t> read = {0, id, 0, 0, 0, 6, 1, 0x03, 0, 0, 0, 1};
        client::LinkError error;
        if (!session.send(read, error)) return "send: " + error.message;
        const auto answer = session.receive_frame(std::chrono::seconds(5));
        return answer.status == client::ReceiveStatus::Frame ? std::string("answered")
                                                             : "no answer: " + answer.detail;
    };
    ASSERT_EQ(poll(1), "answered");
    // Twice the table each round, half silent, half a ClientHello's first bytes.
    std::vector<BlockingClient> handshakes;
    std::uint64_t admitted = server_->listener_counters().accepted.load();
    for (std::uint8_t round = 2; round < 7; ++round) {
        for (std::size_t i = 0; i < 2 * kMaxConnections; ++i) {
            handshakes.emplace_back(port_);
            ASSERT_TRUE(handshakes.back().connected());
            if (i % 2 == 1) handshakes.back().send_hex("16 03 01 00 F0 01 00 00");
        }
        // The poll follows the newcomers' admission, and so any eviction.
        admitted += 2 * kMaxConnections;
        for (int wait = 0; wait < 500 && server_->listener_counters().accepted.load() < admitted;
             ++wait)
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        ASSERT_EQ(server_->listener_counters().accepted.load(), admitted);
        EXPECT_EQ(poll(round), "answered") << "round " << int(round);
    }
    EXPECT_EQ(server_->listener_counters().evicted_idle.load(), 0U);
    EXPECT_GT(server_->listener_counters().evicted_handshaking.load(), 0U);
}

// A plain tcp:// client that reaches the TLS port is told so in one line; over mbaps:// an
// exception 01 that the certificate's role may explain says that too.
// The one line a client command prints for a TLS server at 127.0.0.1:`port`.
void expect_told_to_use_mbaps(const Ran& ran, const std::string& command, std::uint16_t port) {
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.err, StartsWith("mblab " + command + ": the server at 127.0.0.1:" +
                                    std::to_string(port) + " answered with TLS bytes (16 03 03 "));
    EXPECT_THAT(ran.err, EndsWith("): use mbaps://\n"));
    EXPECT_EQ(std::count(ran.err.begin(), ran.err.end(), '\n'), 1) << ran.err;
}

TEST_F(MbapsCli, PlainClientCommandsOfAnMbapsPortAreToldToUseMbaps) {
    const std::string target = "tcp://127.0.0.1:" + std::to_string(port_);
    expect_told_to_use_mbaps(run_mblab({"read", target, "holding", "0", "1"}), "read", port_);
    expect_told_to_use_mbaps(run_mblab({"write", target, "register", "0", "1"}), "write", port_);
    expect_told_to_use_mbaps(run_mblab({"raw", target, "03 00 00 00 01"}), "raw", port_);
    EXPECT_EQ(server::ServerStats::read(server_->stats().requests), 0U);
}

TEST_F(MbapsCli, ConformOverTcpToAnMbapsPortSaysUseMbaps) {
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
TEST_F(MbapsCli, AnException01OverMbapsNamesTheCertificatesRole) {
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

TEST_F(MbapsCli, APlainClientOfOpensslsServerIsToldToUseMbaps) {
    if (::access("/usr/bin/openssl", X_OK) != 0) GTEST_SKIP() << "the openssl CLI is not installed";
    const std::uint16_t port = closed_port();
    ChildProcess openssl({"/usr/bin/openssl", "s_server", "-quiet", "-accept", std::to_string(port),
                          "-cert", file("server.pem"), "-key", file("server.key")});
    ASSERT_TRUE(openssl.started());
    for (int wait = 0; wait < 100 && !BlockingClient(port).connected(); ++wait)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    expect_told_to_use_mbaps(
        run_mblab({"read", "tcp://127.0.0.1:" + std::to_string(port), "holding", "0", "1"}), "read",
        port);
}

TEST(MbapsServe, ServesTlsFromTheCommandLineAndRefusesBadFiles) {
    auto no_files = run_mblab({"serve", "--listen", "mbaps://127.0.0.1:0"});
    expect_failed(no_files, 2, "mblab serve: --cert FILE is required\n");
    auto plain = run_mblab({"serve", "--listen", "tcp://127.0.0.1:0", "--ca", "x"});
    expect_failed(plain, 2, "mblab serve: --cert, --key and --ca are for an mbaps:// --listen\n");
}

}  // namespace
}  // namespace mblab::test
