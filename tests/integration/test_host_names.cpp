// Targets and listen addresses by DNS name. Each test runs the real binary in a private mount
// namespace whose /etc/hosts (and resolv.conf, pointing at a resolver that is not there) are the
// test's own, so names resolve the way the system resolves them, without touching the machine's
// files or any network but loopback.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <asio.hpp>
#include <filesystem>
#include <fstream>

#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

namespace fs = std::filesystem;

class HostNames : public ServerFixture {
  protected:
    void SetUp() override {
        if (::geteuid() != 0) GTEST_SKIP() << "a private /etc/hosts needs root (unshare -m)";
        if (run_program({"/usr/bin/unshare", "-m", "/bin/true"}).status != 0) {
            GTEST_SKIP() << "unshare -m is not permitted here";
        }
        dir_ = fs::temp_directory_path() / ("mblab-hosts-" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        // Names only in this file: plc-01 has an IPv4 address only, plc-v6 an IPv6 address
        // only, and plc-both has both, IPv6 first.
        std::ofstream(dir_ / "hosts") << "127.0.0.1 localhost plc-01.plant.lan plc-both\n"
                                         "::1 plc-v6.plant.lan plc-both\n";
        std::ofstream(dir_ / "resolv.conf")
            << "nameserver 127.0.0.1\noptions timeout:1 attempts:1\n";
        std::ofstream(dir_ / "gai.conf") << "precedence ::1/128 100\n";
    }
    void TearDown() override {
        if (!dir_.empty()) fs::remove_all(dir_);
    }

    // Runs `script` under sh with the test's hosts file in place; "$M" is the binary.
    Ran in_private_hosts(const std::string& script) const {
        const std::string d = dir_.string();
        return run_program(
            {"/usr/bin/unshare", "-m", "/bin/sh", "-c",
             "{ mount --bind " + d + "/hosts /etc/hosts && mount --bind " + d +
                 "/resolv.conf /etc/resolv.conf && touch /etc/gai.conf && " + "mount --bind " + d +
                 "/gai.conf /etc/gai.conf; } || exit 99; M=" + MBLAB_BINARY + "; " + script});
    }

    // Runs `mblab serve --listen LISTEN`, waits until `probe` reads from it, then runs `script`;
    // the script's status is the result.
    Ran with_serve(const std::string& listen, const std::string& probe,
                   const std::string& script) const {
        return in_private_hosts("$M serve --listen " + listen + " >/dev/null 2>&1 & S=$!; " +
                                "for i in $(seq 50); do $M read " + probe +
                                " holding 0 >/dev/null 2>&1 && break; sleep 0.1; done; " + script +
                                "; R=$?; kill $S; exit $R");
    }

    static std::string free_port(const asio::ip::address& address) {
        asio::io_context io;
        asio::ip::tcp::acceptor probe(io, {address, 0});
        return std::to_string(probe.local_endpoint().port());
    }

    fs::path dir_;
};

TEST_F(HostNames, AnIpv4OnlyNameIsReadLikeItsAddress) {
    start_reference_server();
    auto ran = in_private_hosts("$M read tcp://plc-01.plant.lan:" + std::to_string(port_) +
                                " holding 0 2");
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("0 (0x0000)"));
}

TEST_F(HostNames, AnIpv6OnlyNameIsReadOverIpv6) {
    auto loaded = device::load_profile(device::default_profile_path());
    ASSERT_TRUE(loaded) << loaded.error();
    device_ = std::move(loaded.value());
    server_ = std::make_unique<server::BackgroundServer>(*device_, server::ServerOptions{});
    auto port = server_->start(asio::ip::tcp::endpoint(asio::ip::address_v6::loopback(), 0));
    ASSERT_TRUE(port) << port.error();
    auto ran = in_private_hosts("$M read tcp://plc-v6.plant.lan:" + std::to_string(*port) +
                                " holding 0 --timeout 2s");
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("0 (0x0000)"));
}

// plc-both resolves to ::1 first, where nothing listens on the port: the client goes on to
// 127.0.0.1, as every address is tried in order.
TEST_F(HostNames, EveryAddressOfANameIsTriedInTurn) {
    start_reference_server();
    const auto port = std::to_string(port_);
    auto ran = in_private_hosts(
        "getent ahosts plc-both | head -1 && $M read tcp://plc-both:" + port + " holding 0");
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.out.rfind("::1", 0), 0u) << "the test's premise, IPv6 first: " << ran.out;
    EXPECT_THAT(ran.out, HasSubstr("0 (0x0000)"));

    ran = in_private_hosts("$M load tcp://plc-both:" + port + " --duration 1s --connections 2");
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
}

TEST_F(HostNames, ServeListensOnANameAndConformRunsAgainstIt) {
    const auto port = free_port(asio::ip::address_v6::loopback());
    auto ran = with_serve("tcp://plc-v6.plant.lan:" + port, "tcp://[::1]:" + port,
                          "$M conform tcp://plc-v6.plant.lan:" + port + " --case 7.3.1");
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_NE(ran.out.find("tcp://plc-v6.plant.lan:" + port), std::string::npos) << ran.out;
}

TEST_F(HostNames, ANameThatDoesNotResolveIsOneLineAndAUsageError) {
    auto ran = in_private_hosts("$M read tcp://no-such-plc.plant.lan:502 holding 0");
    EXPECT_EQ(ran.status, 2) << ran.out << ran.err;
    EXPECT_THAT(ran.err, HasSubstr("bad address 'tcp://no-such-plc.plant.lan:502': cannot resolve "
                                   "'no-such-plc.plant.lan'"));
    EXPECT_EQ(std::count(ran.err.begin(), ran.err.end(), '\n'), 1) << ran.err;

    ran = in_private_hosts("$M read 'tcp://plc 01:502' holding 0");
    EXPECT_EQ(ran.status, 2) << ran.err;
    EXPECT_THAT(ran.err, HasSubstr("host must be a name or an IP address"));
}

TEST_F(HostNames, RtuOverTcpIsServedAndReadByName) {
    const auto port = free_port(asio::ip::address_v4::loopback());
    auto ran = with_serve("rtu+tcp://plc-01.plant.lan:" + port, "rtu+tcp://127.0.0.1:" + port,
                          "$M read rtu+tcp://plc-01.plant.lan:" + port + " holding 0");
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("0 (0x0000)"));
}

}  // namespace
}  // namespace mblab::test
