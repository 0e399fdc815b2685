// `mblab serve sunspec-inverter` as a user runs it, its behaviours on the server's clock: two
// `mblab sunspec` scans show 103 W moving in watts (stored in tens, W_SF = 1) and the energy WH
// never going back; `conform --suite sunspec --sunspec-models DIR` judges it by the folder given.
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <thread>

#include "child_process.hpp"
#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using namespace std::chrono_literals;

class ServedInverter : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto banner = serve_.read_stdout_line(10s);
        ASSERT_TRUE(banner.has_value());
        std::smatch port;
        ASSERT_TRUE(std::regex_search(*banner, port, std::regex(R"(tcp://127\.0\.0\.1:(\d+))")))
            << *banner;
        target_ = "tcp://127.0.0.1:" + port[1].str();
    }
    void TearDown() override {
        serve_.signal(SIGTERM);
        EXPECT_EQ(serve_.wait_exit(10s), 0);
    }

    // Model 103's point `name` in a `mblab sunspec --json` scan.
    nlohmann::json inverter_point(const std::string& name) {
        const auto ran = run_mblab({"sunspec", target_, "--json"});
        EXPECT_EQ(ran.status, 0) << ran.err;
        const auto scan = nlohmann::json::parse(ran.out);
        for (const auto& model : scan["sunspec"]["models"]) {
            if (model["id"] != 103) continue;
            for (const auto& point : model["points"]) {
                if (point["name"] == name) return point;
            }
        }
        ADD_FAILURE() << "no 103 " << name << " in " << ran.out;
        return {};
    }

    ChildProcess serve_{
        {MBLAB_BINARY, "serve", "sunspec-inverter", "--listen", "tcp://127.0.0.1:0"}};
    std::string target_;
};

TEST_F(ServedInverter, PowerMovesInWattsAndEnergyOnlyGrows) {
    const auto first_w = inverter_point("W");
    const auto first_wh = inverter_point("WH");
    auto w = first_w;
    // The sine updates every second; it is polled, never timed (at most 20 s).
    for (int i = 0; i < 100 && w["value"] == first_w["value"]; ++i) {
        std::this_thread::sleep_for(200ms);
        w = inverter_point("W");
    }
    EXPECT_NE(w["value"], first_w["value"]);
    for (const auto& seen : {first_w, w}) {
        // Engineering units: 2000..9000 W, the register holding tens of watts.
        const double watts = seen["value"];
        EXPECT_GE(watts, 2000);
        EXPECT_LE(watts, 9000);
        EXPECT_EQ(seen["scale"], 1);
        EXPECT_EQ(static_cast<double>(std::stoul(seen["raw"].get<std::string>(), nullptr, 16) * 10),
                  watts);
        EXPECT_EQ(seen["units"], "W");
    }
    const double energy = first_wh["value"];
    EXPECT_GE(energy, 1000000);
    EXPECT_GE(inverter_point("WH")["value"].get<double>(), energy);
}

// The official set of model definitions (beside the source tree, never in it) judges the served
// device as mblab's own do; a folder without them leaves every case N/A, saying why.
TEST_F(ServedInverter, ConformTakesTheModelsFolder) {
    const auto official =
        std::filesystem::path(MBLAB_SOURCE_DIR) / ".." / "shared" / "sunspec-models" / "json";
    TempDir empty;
    const auto none = run_mblab(
        {"conform", target_, "--suite", "sunspec", "--sunspec-models", empty.path().string()});
    EXPECT_EQ(none.status, 0) << none.out << none.err;
    EXPECT_NE(none.out.find("0 passed, 0 failed, 16 N/A"), std::string::npos) << none.out;
    EXPECT_NE(none.out.find("no model_*.json files"), std::string::npos) << none.out;
    if (!std::filesystem::is_directory(official)) {
        GTEST_SKIP() << "the official SunSpec models are not at " << official;
    }
    const auto ran = run_mblab(
        {"conform", target_, "--suite", "sunspec", "--sunspec-models", official.string()});
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_NE(ran.out.find("15 passed, 0 failed, 1 N/A"), std::string::npos) << ran.out;
}

}  // namespace
}  // namespace mblab::test
