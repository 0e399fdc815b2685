#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "child_process.hpp"
#include "test_client_support.hpp"

// `mblab sunspec` against the shipped sunspec-inverter profile served in-process.
namespace mblab::test {
namespace {

class SunspecCli : public ClientCliTest {
  protected:
    void SetUp() override {
        auto loaded = device::load_profile(device::profiles_dir() / "sunspec-inverter.toml");
        ASSERT_TRUE(loaded) << loaded.error();
        device_ = std::move(loaded.value());
        start_server(*device_);
    }
};

TEST_F(SunspecCli, PrintsEachModelAndPointScaled) {
    auto ran = mblab("sunspec", {});
    ASSERT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.out.rfind("SunSpec marker at 40000, 7 models, end model at 40361\n\n"
                            "model 1 common (Common) at 40002, length 66\n"
                            "  40002  ID                       1\n"
                            "  40003  L                        66\n"
                            "  40004  Mn                       \"mblab\"\n",
                            0),
              0U)
        << ran.out;
    for (const char* line : {"  40036  Opt                      (not implemented)\n",
                             "model 103 inverter (Inverter (Three Phase)) at 40070, length 50\n",
                             "  40072  A                        12.34 A\n",
                             "  40080  PhVphA                   230.1 V\n",
                             "  40094  WH                       1000000 Wh\n",
                             "  40108  St                       4 (MPPT)\n",
                             "  40090  VAr                      (not implemented)\n",
                             "model 123 controls (Immediate Controls) at 40228, length 24\n",
                             "  40232  Conn                     1 (CONNECT)\n",
                             "model 203 ac_meter_abcn (Meter (Three Phase Wye)) at 40254, "
                             "length 105\n"}) {
        EXPECT_NE(ran.out.find(line), std::string::npos) << line << ran.out;
    }
}

TEST_F(SunspecCli, JsonHasEveryPoint) {
    auto ran = mblab("sunspec", {"--json"});
    ASSERT_EQ(ran.status, 0) << ran.err;
    const auto document = nlohmann::json::parse(ran.out);
    const auto& sunspec = document["sunspec"];
    EXPECT_EQ(sunspec["base"], 40000);
    ASSERT_EQ(sunspec["models"].size(), 7U);
    const auto& inverter = sunspec["models"][1];
    EXPECT_EQ(inverter["id"], 103);
    EXPECT_EQ(inverter["points"].size(), 45U);
    const auto& hz = inverter["points"][16];
    EXPECT_EQ(hz["name"], "Hz");
    EXPECT_EQ(hz["value"], 50.0);
    EXPECT_EQ(hz["scale"], -2);
    EXPECT_EQ(hz["units"], "Hz");
    EXPECT_EQ(hz["raw"], "0x1388");
}

// The official set, when it is beside the source tree, decodes the device the same way.
TEST_F(SunspecCli, ReadsWithTheOfficialModels) {
    const auto official =
        std::filesystem::path(MBLAB_SOURCE_DIR) / ".." / "shared" / "sunspec-models" / "json";
    if (!std::filesystem::is_directory(official)) {
        GTEST_SKIP() << "the official SunSpec models are not at " << official;
    }
    auto ran = mblab("sunspec", {"--sunspec-models", official.string()});
    ASSERT_EQ(ran.status, 0) << ran.err;
    EXPECT_NE(ran.out.find("  40072  A                        12.34 A\n"), std::string::npos)
        << ran.out;
    EXPECT_NE(ran.out.find("  40108  St                       4 (MPPT)\n"), std::string::npos);
}

// `conform --suite sunspec` scans the built-in device as `mblab sunspec` does; every case passes
// (the line case is N/A over TCP), and its capture reads back in tshark as Modbus/TCP: the first
// FC 03 request reads the 2 registers of the marker at 40000.
TEST_F(SunspecCli, TheSuitePassesAndItsCaptureReadsInTshark) {
    const std::string pcap = (std::filesystem::temp_directory_path() /
                              ("mblab-sunspec-" + std::to_string(::getpid()) + ".pcap"))
                                 .string();
    auto ran = mblab("conform", {"--suite", "sunspec", "--pcap", pcap});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_NE(ran.out.find("15 passed"), std::string::npos) << ran.out;
    if (!std::filesystem::exists("/usr/bin/tshark")) {
        std::filesystem::remove(pcap);
        GTEST_SKIP() << "tshark is not installed (scripts/install-deps.sh installs it)";
    }
    ChildProcess tshark({"/usr/bin/tshark", "-r", pcap, "-Y",
                         "modbus.func_code == 3 && mbtcp.len == 6", "-T", "fields", "-e",
                         "modbus.reference_num", "-e", "modbus.word_cnt"});
    std::vector<std::string> reads;
    while (auto line = tshark.read_stdout_line(std::chrono::seconds(60)))
        reads.push_back(*line);
    EXPECT_EQ(tshark.wait_exit(std::chrono::seconds(60)), 0);
    ASSERT_FALSE(reads.empty());
    EXPECT_EQ(reads.front(), "40000\t2");
    EXPECT_GT(reads.size(), 100U);
    std::filesystem::remove(pcap);
}

TEST_F(SunspecCli, NoMarkerIsAFailure) {
    // The reference device has no marker anywhere; the server goes before its device.
    server_.reset();
    auto reference = device::load_profile(device::default_profile_path());
    ASSERT_TRUE(reference) << reference.error();
    device_ = std::move(reference.value());
    start_server(*device_);
    auto ran = mblab("sunspec", {});
    EXPECT_EQ(ran.status, 1);
    EXPECT_EQ(ran.err,
              "mblab sunspec: no SunSpec marker (\"SunS\", 0x5375 0x6E53) at 40000, 0, 50000\n");
}

}  // namespace
}  // namespace mblab::test
