// Register maps from CSV: the TOML made from a good file loads and moves; a bad file is refused
// with its line and column.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "device/register_map_csv.hpp"
#include "device_harness.hpp"

namespace mblab::test {
namespace {

using namespace std::chrono_literals;

std::string import(std::string_view csv) {
    auto made = device::register_map_to_profile(csv, {"map.csv", "map", 3});
    return made ? made->toml : "ERROR " + made.error();
}

TEST(RegisterMapCsv, MakesRangesAndBehavioursThatLoad) {
    const auto toml = import(
        "address,bank,type,name,behaviour,value,min,max,period_ms,interval_ms,order\n"
        "# a comment line and a blank one are skipped\n"
        "\n"
        "0,input,u16,\"level, tank 1\",sine,,0,1000,10000,100,\n"
        "2,input,f32,temperature,constant,21.5,,,,,CDAB\n"
        "10,holding,i32,setpoint,,,,,,,\n"
        "0,coil,bit,pump,,,,,,,\n");
    ASSERT_EQ(toml.substr(0, 6), "# Impo") << toml;
    EXPECT_NE(toml.find("name = \"level, tank 1\""), std::string::npos) << toml;
    EXPECT_NE(toml.find("id = 3"), std::string::npos) << toml;
    auto device = device_from(toml);
    ASSERT_TRUE(device);
    const auto start = std::chrono::steady_clock::time_point{} + 1h;
    device->behaviours().advance(start, {});
    EXPECT_EQ(ask(*device, "04 00 00 00 01", 3), "04 02 01 F4");
    device->behaviours().advance(start + 2500ms, {});
    EXPECT_EQ(ask(*device, "04 00 00 00 01", 3), "04 02 03 E8");
    EXPECT_EQ(ask(*device, "04 00 02 00 02", 3), "04 04 00 00 41 AC");  // 21.5, words swapped
    EXPECT_EQ(ask(*device, "03 00 0A 00 02", 3), "03 04 00 00 00 00");
    EXPECT_EQ(ask(*device, "01 00 00 00 01", 3), "01 01 00");
}

// A spreadsheet's "CSV UTF-8" starts with a byte order mark; old Mac ones end lines in CR alone,
// Windows ones in CRLF. Line numbers in messages count each kind of line end once.
TEST(RegisterMapCsv, TakesAByteOrderMarkAndEveryKindOfLineEnd) {
    for (const std::string_view end : {"\n", "\r", "\r\n"}) {
        const std::string rows = "address,type,name" + std::string(end) + "0,u16,a" +
                                 std::string(end) + "1,u16,b" + std::string(end);
        const auto toml = import("\xEF\xBB\xBF" + rows);
        ASSERT_EQ(toml.substr(0, 6), "# Impo") << toml;
        EXPECT_NE(toml.find("name = \"b\""), std::string::npos) << toml;
        EXPECT_EQ(toml.find('\r'), std::string::npos) << toml;
        const std::string bad = "address,type" + std::string(end) + "0,u16" + std::string(end) +
                                std::string(end) + "1,u24" + std::string(end);
        EXPECT_EQ(import(bad),
                  "ERROR map.csv:4: type: expected one of u16, i16, u32, i32, u64, i64, f32, f64, "
                  "got \"u24\"");
    }
}

// Every address of every bank, 262,144 rows, a behaviour on each register: checking each row
// (and each behaviour) against every earlier one took minutes. The time is printed, not judged.
TEST(RegisterMapCsv, AMapOfEveryAddressImports) {
    std::string csv = "address,bank,type,name,behaviour,value\n";
    for (const char* bank : {"holding", "input", "coil", "discrete"}) {
        const bool bits = bank[0] == 'c' || bank[0] == 'd';
        for (int address = 0; address < 0x10000; ++address)
            csv += std::to_string(address) + "," + bank + (bits ? ",bit,p" : ",u16,p") +
                   std::to_string(address) + (bits ? ",,\n" : ",constant,1\n");
    }
    const auto started = std::chrono::steady_clock::now();
    const auto toml = import(csv);
    const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(
        std::chrono::steady_clock::now() - started);
    std::printf("262144 rows, 131072 behaviours imported in %lld ms\n",
                static_cast<long long>(took.count()));
    ASSERT_EQ(toml.substr(0, 6), "# Impo") << toml.substr(0, 500);
    EXPECT_NE(toml.find("[[unit.discrete_inputs]]\nstart = 65535\n"), std::string::npos);
    EXPECT_NE(toml.find("kind = \"constant\"\nbank = \"input_registers\"\naddress = 65535\n"),
              std::string::npos);
    // The last row overlaps the first: the message still names the earlier row.
    EXPECT_EQ(import(csv + "0,holding,u32,again,,\n"),
              "ERROR map.csv:262146: address: holding_registers 0 overlaps line 2 (0..0)");
}

struct BadCsv {
    std::string_view csv;
    std::string_view error;
};

class RegisterMapCsvErrors : public ::testing::TestWithParam<BadCsv> {};

TEST_P(RegisterMapCsvErrors, NameTheLineAndColumn) {
    EXPECT_EQ(import(GetParam().csv), "ERROR " + std::string(GetParam().error));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, RegisterMapCsvErrors,
    ::testing::Values(
        BadCsv{"address,kind\n0,sine\n",
               "map.csv:1: unknown column \"kind\"; expected some of address, bank, type, name, "
               "description, behaviour, value, min, max, step, start, scale, offset, period_ms, "
               "interval_ms, lag_ms, source, source_bank, order"},
        BadCsv{"name,type\nx,u16\n",
               "map.csv:1: no address column; the first line names the columns, e.g. "
               "address,type,name,behaviour,min,max,period_ms"},
        BadCsv{"address,type\n0,u16\n1,u24\n",
               "map.csv:3: type: expected one of u16, i16, u32, i32, u64, i64, f32, f64, got "
               "\"u24\""},
        BadCsv{"address,type\n70000,u16\n",
               "map.csv:2: address: expected an address from 0 to 65535, got \"70000\""},
        BadCsv{"address,behaviour,min\n0,random,low\n",
               "map.csv:2: min: expected a number, got \"low\""},
        BadCsv{"address,type\n0,u32\n1,u16\n",
               "map.csv:3: address: holding_registers 1 overlaps line 2 (0..1)"},
        BadCsv{"address,behaviour,min,max\n0,sine,0,10\n",
               "map.csv:2: period_ms: missing key; the time of one cycle, e.g. period_ms = "
               "60000"},
        BadCsv{"address,behaviour,min,max\n0,random,10,0\n",
               "map.csv:2: max: expected a number above min (10)"},
        BadCsv{"address,min\n0,5\n",
               "map.csv:2: min: a behaviour parameter without a behaviour; give the behaviour "
               "column, e.g. sine"},
        BadCsv{"address,name\n0,\"open\n", "map.csv:2: a quoted cell is not closed"},
        BadCsv{"address,name\n",
               "map.csv:1: no points; after the header line, give one point "
               "per line"},
        // The loader's errors are traced back to the CSV line that made the table.
        BadCsv{"address,type\n0,u16\n4,i16\n5,u16,x\n",
               "map.csv:4: 3 cells, but the header names 2 columns"},
        BadCsv{"address,type,behaviour\n0,u16,\n4,f32,constant\n",
               "map.csv:3: value: missing key; the value to hold, e.g. value = 42"},
        BadCsv{"address,behaviour\n0,wave\n",
               "map.csv:2: kind: expected one of constant, ramp, sine, random-walk, random, "
               "counter, uptime, timestamp, follow, got \"wave\""}));

}  // namespace
}  // namespace mblab::test
