// `mblab scan` against mblab's own device over every framing: the DUT file it writes loads, makes
// `mblab conform` run with fewer N/A cases and no new failure, and the scan changes nothing the
// device holds.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "conformance/dut.hpp"
#include "device/profile_paths.hpp"
#include "security/tls_context.hpp"
#include "serial_test_support.hpp"
#include "support/lab_pki.hpp"
#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

// Every value of every table of the units, as the device holds them.
using Snapshot = std::vector<std::optional<std::vector<std::optional<std::uint16_t>>>>;

Snapshot snapshot(const device::ReferenceDevice& device, std::initializer_list<int> units) {
    Snapshot out;
    for (int unit : units) {
        for (auto kind : {device::BankKind::Coils, device::BankKind::DiscreteInputs,
                          device::BankKind::HoldingRegisters, device::BankKind::InputRegisters})
            out.push_back(device.data().values(static_cast<std::uint8_t>(unit), kind, 0, 65536));
    }
    return out;
}

struct Summary {
    int failed = -1;
    int not_applicable = -1;
};

// `mblab conform TARGET [--dut FILE]`: its summary.
Summary conform(const std::string& target, const TempDir& dir, const std::string& dut) {
    const std::string json = (dir / (dut.empty() ? "bare.json" : "declared.json")).string();
    std::vector<std::string> args = {"conform", target, "--json", json};
    if (!dut.empty()) args.insert(args.end(), {"--dut", dut});
    const auto ran = run_mblab(args);
    EXPECT_NE(ran.status, 2) << ran.out << ran.err;
    const auto report = nlohmann::json::parse(file_text(json), nullptr, false);
    if (report.is_discarded()) return {};
    return {report["summary"]["failed"], report["summary"]["not_applicable"]};
}

// Scans `target` into DIR/dut.toml, then runs conform with and without it.
std::string scan_then_conform(const std::string& target, const TempDir& dir,
                              std::vector<std::string> extra = {}) {
    const std::string dut = (dir / "dut.toml").string();
    std::vector<std::string> args = {"scan", target, "-o", dut};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto ran = run_mblab(args);
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("wrote " + dut + ": check it, then run mblab conform"));
    const auto loaded = conformance::load_dut_file(dut);
    EXPECT_TRUE(loaded) << (loaded ? "" : loaded.error());
    const auto bare = conform(target, dir, "");
    const auto declared = conform(target, dir, dut);
    EXPECT_LT(declared.not_applicable, bare.not_applicable) << file_text(dut);
    EXPECT_EQ(declared.failed, bare.failed) << file_text(dut);
    return file_text(dut);
}

class ScanProfile : public ServerFixture, public ::testing::WithParamInterface<const char*> {};

// Every shipped profile over Modbus/TCP.
TEST_P(ScanProfile, TheFileItWritesMakesConformRunWithFewerNotApplicable) {
    auto loaded =
        device::load_profile(device::profiles_dir() / (std::string(GetParam()) + ".toml"));
    ASSERT_TRUE(loaded) << loaded.error();
    device_ = std::move(loaded.value());
    start_server(*device_);
    // "moving" moves its values by itself: the others hold still unless written.
    const bool still = std::string(GetParam()) != "moving";
    const auto before = snapshot(*device_, {1, 2, 17});
    TempDir dir;
    const std::string dut = (dir / "dut.toml").string();
    const auto ran = run_mblab({"scan", tcp_target(port_), "-o", dut});
    ASSERT_EQ(ran.status, 0) << ran.out << ran.err;
    if (still) {
        EXPECT_EQ(snapshot(*device_, {1, 2, 17}), before) << "the scan changed data";
    }
    EXPECT_THAT(ran.out, HasSubstr("units tried: 1, 255, 0; answering FC 03: 1, 255, 0; "
                                   "scanned: 1\n"));
    EXPECT_THAT(file_text(dut), HasSubstr("unit = 1  # learned by mblab scan: 1 of the 3 units"));
    std::filesystem::remove(dut);
    scan_then_conform(tcp_target(port_), dir);
}

INSTANTIATE_TEST_SUITE_P(Shipped, ScanProfile,
                         ::testing::Values("reference", "rs485-instrument", "multi-unit",
                                           "access-ranges", "moving"));

class ScanCli : public ReferenceCliTest {};

TEST_F(ScanCli, TheReferenceDeviceIsDeclaredWhole) {
    TempDir dir;
    const std::string text = scan_then_conform(target(), dir);
    EXPECT_THAT(text, HasSubstr("registers = 65536  # learned by mblab scan: FC 03 answered "
                                "0..65535, each address read once in whole reads\n"));
    EXPECT_THAT(text, HasSubstr("max_read = 125  # learned by mblab scan: FC 03 of 125 registers"));
    for (const char* key :
         {"coils = 65536", "discrete_inputs = 65536", "input_registers = 65536",
          "object_messaging = true", "alternate_encoding = true", "file_number = 1"})
        EXPECT_THAT(text, HasSubstr(std::string(key) + "  # learned by mblab scan: "));
    EXPECT_THAT(text, HasSubstr("# device identification (FC 2B/0E): vendor name \"mblab\""));
    EXPECT_THAT(text, HasSubstr("# not asked (they write): 05 06 0F 10 15 16 17\n"));
}

TEST_F(ScanCli, AnExistingFileIsKeptUnlessForcedAndNothingIsSent) {
    TempDir dir;
    const std::string dut = (dir / "mine.toml").string();
    std::ofstream(dut) << "unit = 3\n";
    const auto ran = run_mblab({"scan", target(), "-o", dut});
    expect_failed(ran, 2,
                  "mblab scan: " + dut +
                      " exists: give --force to replace it, or -o another "
                      "file\n");
    EXPECT_EQ(file_text(dut), "unit = 3\n");
    EXPECT_EQ(server::ServerStats::read(stats().requests), 0U);
    const auto forced = run_mblab({"scan", target(), "-o", dut, "--force"});
    EXPECT_EQ(forced.status, 0) << forced.err;
    EXPECT_THAT(file_text(dut), HasSubstr("unit = 1  # learned by mblab scan"));
}

TEST_F(ScanCli, DashWritesTheFileOnStdoutAndTheTableOnStderr) {
    const auto ran = run_mblab({"scan", target(), "-o", "-", "--units", "7,1"});
    ASSERT_EQ(ran.status, 0) << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("\nunit = 1  # learned by mblab scan: the only unit that "
                                   "answered FC 03\n"));
    EXPECT_THAT(ran.err, HasSubstr("units tried: 7, 1; answering FC 03: 1; scanned: 1\n"));
    EXPECT_THAT(ran.err, HasSubstr("  registers = 65536  "));
    EXPECT_THAT(ran.out, Not(HasSubstr("wrote")));
}

TEST_F(ScanCli, AMuteDeviceStopsAtOnceWithOneLine) {
    // A listening socket nobody accepts from: connections open, requests go unanswered.
    const int listener = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    ASSERT_EQ(::bind(listener, reinterpret_cast<sockaddr*>(&address), length), 0);
    ASSERT_EQ(::listen(listener, 16), 0);
    ASSERT_EQ(::getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length), 0);
    const std::string mute = tcp_target(ntohs(address.sin_port));
    const auto started = std::chrono::steady_clock::now();
    const auto ran = run_mblab({"scan", mute, "--timeout", "300ms", "-o", "-"});
    const auto took = std::chrono::steady_clock::now() - started;
    ::close(listener);
    expect_failed(ran, 2,
                  "mblab scan: " + mute +
                      ": no answer on unit 1, 255 or 0 to 3 requests (FC 03, holding register "
                      "0): check the port and --units\n");
    EXPECT_LT(took, std::chrono::seconds(5));
    EXPECT_EQ(ran.out, "");
}

TEST_F(ScanCli, BadUnitsAreRefusedBeforeAnythingIsSent) {
    expect_failed(run_mblab({"scan", target(), "--units", "9-3"}), 2,
                  "mblab scan: --units '9-3' is not a list of unit ids and ranges from 0 to 255 "
                  "(1,255,0 or 1-247)\n");
    EXPECT_EQ(server::ServerStats::read(stats().requests), 0U);
}

// rtu:// on a pseudo-terminal: the instrument's smaller map, its read limit and its echo limit.
TEST(ScanLine, TheRs485InstrumentOverRtu) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("rs485-instrument", "rtu", 19200, false), "");
    const std::string url = "rtu://" + line.pty().client_end() + "?baud=19200&data=8";
    TempDir dir;
    const std::string text = scan_then_conform(url, dir);
    EXPECT_THAT(text, HasSubstr("\nregisters = 64  # learned by mblab scan: FC 03 answered 0..63"));
    EXPECT_THAT(text, HasSubstr("\necho_max_words = 100  # learned by mblab scan: FC 08/00 echoed "
                                "100 data words; 101 answered exception 03\n"));
    EXPECT_THAT(text, HasSubstr("# coils: FC 01 is not served (exception 01)\n"));
    EXPECT_THAT(text, HasSubstr("units tried: 1; answering FC 03: 1; scanned: 1\n"));
    // The conform runs write; the scan alone is checked on a fresh device.
    DeviceOnLine fresh;
    ASSERT_EQ(fresh.start("rs485-instrument", "rtu", 19200, false), "");
    const auto held = snapshot(fresh.device(), {1});
    const auto ran =
        run_mblab({"scan", "rtu://" + fresh.pty().client_end() + "?baud=19200&data=8", "-o", "-"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(snapshot(fresh.device(), {1}), held) << "the scan changed data";
}

// mbaps://: the scan runs inside TLS, and learns what the certificate's role may do.
TEST(ScanTls, AReadOnlyRoleLearnsTheReads) {
    LabPki pki("scan-cli");
    ASSERT_TRUE(pki.made()) << pki.error();
    auto loaded = device::load_profile(device::default_profile_path());
    ASSERT_TRUE(loaded) << loaded.error();
    auto device = std::move(loaded.value());
    server::ServerOptions options;
    auto context = security::make_server_context(
        {pki.file("server.pem"), pki.file("server.key"), pki.file("ca.pem")});
    ASSERT_TRUE(context) << context.error();
    options.tls = *context;
    options.roles =
        std::make_shared<const device::RoleRules>(device->declarations().profile().roles);
    server::BackgroundServer server(*device, options);
    const auto port = server.start();
    ASSERT_TRUE(port) << port.error();
    const auto ran = run_mblab({"scan", "mbaps://localhost:" + std::to_string(*port), "-o", "-",
                                "--cert", pki.file("client-ReadOnly.pem"), "--key",
                                pki.file("client-ReadOnly.key"), "--ca", pki.file("ca.pem")});
    ASSERT_EQ(ran.status, 0) << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("\nregisters = 65536  # learned by mblab scan"));
    EXPECT_THAT(ran.out, HasSubstr("# function codes served: 01 02 03 04 14 18\n"));
    EXPECT_THAT(ran.out, HasSubstr("# echo_max_words: FC 08 is not served (exception 01)\n"));
    EXPECT_GT(server::ServerStats::read(server.stats().tls_handshakes), 0U);
}

}  // namespace
}  // namespace mblab::test
