// `mblab serve --durable` as a process under kill -9: on a disk that is full, nearly full, or
// full and then freed (a tmpfs of its own, when the test runs as root), with a writer killed at
// random points, and with writes over REST. Each counts the acknowledged writes lost: none may be.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "blocking_client.hpp"
#include "child_process.hpp"
#include "support/hex.hpp"
#include "support/small_tmpfs.hpp"
#include "support/temp_dir.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr int kRegisters = 200;

// A profile of one unit with kRegisters holding registers: its state file is a few KB, so a
// small tmpfs can hold it once the space returns.
fs::path write_profile(const TempDir& dir) {
    const auto path = dir / "durable.toml";
    std::ofstream(path) << "name = \"durable\"\n\n[[unit]]\nid = 1\n\n[[unit.holding_registers]]\n"
                        << "start = 0\ncount = " << kRegisters << "\n";
    return path;
}

class Serve {
  public:
    explicit Serve(std::vector<std::string> args) : child_(with_binary(std::move(args))) {
        std::smatch match;
        for (int i = 0; i < 2; ++i) {
            auto line = child_.read_stdout_line(10s);
            if (!line) break;
            if (std::regex_search(*line, match, std::regex("tcp://127\\.0\\.0\\.1:([0-9]+)"))) {
                port_ = static_cast<std::uint16_t>(std::stoi(match[1]));
            }
            if (std::regex_search(*line, match, std::regex("http://127\\.0\\.0\\.1:[0-9]+"))) {
                http_ = match[0];
            }
            if (args_have_http_ != (i == 0)) break;
        }
    }
    std::uint16_t port() const { return port_; }
    const std::string& http() const { return http_; }
    ChildProcess& process() { return child_; }
    void kill9() {
        child_.signal(SIGKILL);
        child_.wait_exit(10s);
    }

  private:
    std::vector<std::string> with_binary(std::vector<std::string> args) {
        for (const auto& arg : args)
            args_have_http_ = args_have_http_ || arg == "--http";
        args.insert(args.begin(), {MBLAB_BINARY, "serve"});
        return args;
    }
    bool args_have_http_ = false;
    ChildProcess child_;
    std::uint16_t port_ = 0;
    std::string http_;
};

std::vector<std::string> durable_args(const fs::path& profile, const fs::path& state,
                                      const std::string& save_interval = "0.02") {
    return {profile.string(), "--listen",  "tcp://127.0.0.1:0", "--state",
            state.string(),   "--durable", "--save-interval",   save_interval};
}

std::string word(int value) {
    return to_hex(std::vector<std::uint8_t>{static_cast<std::uint8_t>(value >> 8),
                                            static_cast<std::uint8_t>(value)});
}

// What the writer knows: per register, the last value acknowledged and the values written after
// it without an acknowledgement (answered 04, or cut off by the kill), which may or may not have
// been kept. A register restored to anything else lost an acknowledged write.
class Ledger {
  public:
    enum class Answer { Acknowledged, Refused, None };

    Answer write(BlockingClient& client, int address, int value) {
        const auto tid = word(++tid_);
        const auto request = tid + " 00 00 00 06 01 06 " + word(address) + " " + word(value);
        maybe_[address].insert(value);
        const auto answer = client.transact(request);
        if (answer == request) {
            acknowledged_[address] = value;
            maybe_[address] = {value};
            ++acks_;
            return Answer::Acknowledged;
        }
        if (answer == tid + " 00 00 00 03 01 86 04") {
            ++refused_;
            return Answer::Refused;
        }
        EXPECT_EQ(answer, "") << "neither an echo nor exception 04";
        return Answer::None;
    }
    // Registers whose restored value lost an acknowledged write.
    int lost(std::uint16_t port) const {
        BlockingClient client(port);
        int lost = 0;
        for (const auto& [address, value] : acknowledged_) {
            const auto answer =
                client.transact("00 01 00 00 00 06 01 03 " + word(address) + " 00 01");
            bool found = false;
            for (int maybe : maybe_.at(address))
                found = found || answer == "00 01 00 00 00 05 01 03 02 " + word(maybe);
            if (!found) ++lost;
        }
        return lost;
    }
    int acks() const { return acks_; }
    int refused() const { return refused_; }

  private:
    int tid_ = 0;
    int acks_ = 0;
    int refused_ = 0;
    std::map<int, int> acknowledged_;
    std::map<int, std::set<int>> maybe_;
};

// Writes rounds over every register until `stop` says so or `max` writes are made.
template <class Stop>
int write_rounds(Ledger& ledger, BlockingClient& client, int first_value, int max, Stop stop) {
    int value = first_value;
    for (int i = 0; i < max && !stop(); ++i) {
        if (ledger.write(client, i % kRegisters, value++) == Ledger::Answer::None) break;
    }
    return value;
}

// A state file on a small tmpfs the test fills and frees; skipped where no tmpfs can be mounted.
class ServeDurableOnASmallDisk : public ::testing::Test {
  protected:
    void SetUp() override {
        if (!disk.mounted()) GTEST_SKIP() << disk.why_not();
    }

    // serve starts again on the state and has every write `ledger` saw acknowledged.
    void expect_restart_loses_none() const {
        Serve again(durable_args(profile, state));
        ASSERT_NE(again.port(), 0) << again.process().drain_stderr();
        EXPECT_EQ(ledger.lost(again.port()), 0);
    }

    SmallTmpfs disk{"512k"};
    TempDir dir;
    fs::path profile = write_profile(dir);
    fs::path state = disk / "s.json";
    Ledger ledger;
};

// The disk is full before the first write: every write is answered 04, none is lost, and serve
// starts again once there is room.
TEST_F(ServeDurableOnASmallDisk, AFullDiskAnswers04AndServeStartsAgainOnceItHasRoom) {
    {
        Serve serve(durable_args(profile, state));
        ASSERT_NE(serve.port(), 0);
        ASSERT_GT(disk.fill(), 0U);
        BlockingClient client(serve.port());
        write_rounds(ledger, client, 1, 300, [] { return false; });
        EXPECT_EQ(ledger.acks(), 0);
        EXPECT_EQ(ledger.refused(), 300);
        serve.kill9();
    }
    disk.free_space();
    expect_restart_loses_none();
}

// Room for part of the journal, not for a state save: acknowledged writes until the disk is
// full (the rotations and saves failing on the way), 04 after. Then kill -9 and room again.
TEST_F(ServeDurableOnASmallDisk, ANearlyFullDiskLosesNoAcknowledgedWrite) {
    {
        Serve serve(durable_args(profile, state));
        ASSERT_NE(serve.port(), 0);
        ASSERT_GT(disk.fill(), 0U);
        // Three pages: the journal, PATH.old and one state file; a save's new file finds none.
        fs::resize_file(disk / "FILL", fs::file_size(disk / "FILL") - 12 * 1024);
        BlockingClient client(serve.port());
        write_rounds(ledger, client, 1, 20000, [&] { return ledger.refused() > 200; });
        EXPECT_GT(ledger.acks(), 100);
        EXPECT_GT(ledger.refused(), 0);
        serve.kill9();
    }
    disk.free_space();
    expect_restart_loses_none();
    std::printf("nearly full: %d acknowledged, %d answered 04, 0 lost\n", ledger.acks(),
                ledger.refused());
}

// Attack run: a record cut short by the full disk, the next ones appended on its line once the
// space returned, and after kill -9 serve refused to start.
TEST_F(ServeDurableOnASmallDisk, AFullDiskThenFreedLosesNoneAndStartsAgain) {
    {
        Serve serve(durable_args(profile, state));
        ASSERT_NE(serve.port(), 0);
        BlockingClient client(serve.port());
        int value = write_rounds(ledger, client, 1, 1000, [] { return false; });
        ASSERT_GT(disk.fill(), 0U);
        const int before = ledger.refused();
        value = write_rounds(ledger, client, value, 2000, [&] { return ledger.refused() > 100; });
        EXPECT_GT(ledger.refused(), before);
        disk.free_space();
        const int acks = ledger.acks();
        write_rounds(ledger, client, value, 2000, [] { return false; });
        EXPECT_GT(ledger.acks(), acks + 1000);
        serve.kill9();
    }
    expect_restart_loses_none();
}

// A writer, and kill -9 at a random moment, several times over on the same state: saves every
// 20 ms, so the kills land in appends, rotations and saves.
TEST(ServeDurable, Kill9AtRandomPointsUnderAWriterLosesNoAcknowledgedWrite) {
    TempDir dir;
    const auto profile = write_profile(dir);
    const auto state = dir / "s.json";
    const auto seed = std::random_device{}();
    std::mt19937 random(seed);
    Ledger ledger;
    int value = 1;
    for (int round = 0; round < 6; ++round) {
        Serve serve(durable_args(profile, state));
        ASSERT_NE(serve.port(), 0)
            << "seed " << seed << ", round " << round << ": " << serve.process().drain_stderr();
        EXPECT_EQ(ledger.lost(serve.port()), 0) << "seed " << seed << ", round " << round;
        const auto after =
            std::chrono::milliseconds(std::uniform_int_distribution(20, 400)(random));
        std::thread killer([&] {
            std::this_thread::sleep_for(after);
            serve.process().signal(SIGKILL);
        });
        BlockingClient client(serve.port());
        value = write_rounds(ledger, client, value, 1'000'000, [] { return false; });
        killer.join();
        serve.process().wait_exit(10s);
    }
    Serve last(durable_args(profile, state));
    ASSERT_NE(last.port(), 0);
    EXPECT_EQ(ledger.lost(last.port()), 0) << "seed " << seed;
    std::printf("kill -9 x6 (seed %u): %d acknowledged, 0 lost\n", seed, ledger.acks());
}

// Attack run: 50 of 50 REST writes lost on kill -9, and an older Modbus write replayed over
// them.
TEST(ServeDurable, RestWritesAreJournaledInOrderWithModbusWrites) {
    if (::access("/usr/bin/curl", X_OK) != 0) GTEST_SKIP() << "no curl";
    TempDir dir;
    const auto profile = write_profile(dir);
    const auto state = dir / "s.json";
    auto args = durable_args(profile, state, "0");
    args.insert(args.end(), {"--http", "127.0.0.1:0", "--http-token", "t"});
    {
        Serve serve(args);
        ASSERT_NE(serve.port(), 0);
        ASSERT_FALSE(serve.http().empty());
        BlockingClient client(serve.port());
        for (int i = 0; i < 50; ++i) {
            const auto request = word(i) + " 00 00 00 06 01 06 " + word(i) + " " + word(1000 + i);
            ASSERT_EQ(client.transact(request), request);
            const auto put =
                run_program({"/usr/bin/curl", "-s", "-w", "\n%{http_code}\n", "-X", "PUT", "-H",
                             "Authorization: Bearer t", "-H", "Content-Type: application/json",
                             "-d", "{\"values\":[" + std::to_string(2000 + i) + "]}",
                             serve.http() + "/api/units/1/holding_registers/" + std::to_string(i)});
            ASSERT_NE(put.out.find("\n200\n"), std::string::npos) << put.out;
        }
        serve.kill9();
    }
    Serve again(durable_args(profile, state));
    ASSERT_NE(again.port(), 0);
    BlockingClient client(again.port());
    int lost = 0;
    for (int i = 0; i < 50; ++i) {
        lost += client.transact("00 01 00 00 00 06 01 03 " + word(i) + " 00 01") !=
                "00 01 00 00 00 05 01 03 02 " + word(2000 + i);
    }
    EXPECT_EQ(lost, 0);
}

}  // namespace
}  // namespace mblab::test
