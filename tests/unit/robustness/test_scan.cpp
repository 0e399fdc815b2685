#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "conformance/dut.hpp"
#include "protocol/request_template.hpp"
#include "robustness/scan.hpp"
#include "robustness/scan_report.hpp"

namespace mblab::robustness {
namespace {

using ::testing::HasSubstr;
using Bytes = std::vector<std::uint8_t>;

Bytes exception(std::uint8_t function, std::uint8_t code) {
    return {static_cast<std::uint8_t>(function | 0x80), code};
}

// A device at unit 7: holding registers 100..349 (at most 60 a read, the SEMI signature at 200),
// coils 0..99 (with a hole at `coil_hole` when set), FC 02 not served, FC 04 never answered, the
// FC 08/00 echo up to 20 words (03 beyond), FC 5B answered, a FIFO at 0. It notes every function
// code and unit it is asked.
struct FakeDevice {
    std::set<std::uint8_t> functions;
    std::set<std::uint8_t> units;
    std::optional<unsigned> coil_hole;

    std::optional<Bytes> operator()(std::uint8_t unit, std::span<const std::uint8_t> pdu) {
        units.insert(unit);
        functions.insert(pdu[0]);
        if (unit != 7) return std::nullopt;
        const std::uint8_t function = pdu[0];
        const unsigned address = pdu.size() >= 3 ? pdu[1] << 8 | pdu[2] : 0;
        const unsigned quantity = pdu.size() >= 5 ? pdu[3] << 8 | pdu[4] : 0;
        switch (function) {
            case 0x01: {
                if (quantity == 0 || address + quantity > 100) return exception(function, 0x02);
                if (coil_hole && address <= *coil_hole && *coil_hole < address + quantity)
                    return exception(function, 0x02);
                Bytes answer{0x01, static_cast<std::uint8_t>((quantity + 7) / 8)};
                answer.resize(2 + answer[1], 0);
                return answer;
            }
            case 0x03: {
                if (quantity == 0 || quantity > 60) return exception(function, 0x03);
                if (address < 100 || address + quantity > 350) return exception(function, 0x02);
                Bytes answer{0x03, static_cast<std::uint8_t>(2 * quantity)};
                for (unsigned a = address; a < address + quantity; ++a) {
                    const std::uint16_t word = a == 200   ? 0x5345
                                               : a == 201 ? 0x4D49
                                               : a == 202 ? 0x5F72
                                                          : static_cast<std::uint16_t>(a);
                    answer.push_back(static_cast<std::uint8_t>(word >> 8));
                    answer.push_back(static_cast<std::uint8_t>(word));
                }
                return answer;
            }
            case 0x04:
                return std::nullopt;
            case 0x08: {
                const std::size_t words = (pdu.size() - 3) / 2;
                if (words == 0 || words > 20) return exception(function, 0x03);
                return Bytes(pdu.begin(), pdu.end());
            }
            case 0x18:
                if (address != 0) return exception(function, 0x02);
                return Bytes{0x18, 0x00, 0x02, 0x00, 0x00};
            case 0x5B:
                return Bytes{0x5B, 0x09, 0x00, 0x00, 0x01, 0x00, 0x01, 0x00, 0x08, 0x00, 0x00};
            default:
                return exception(function, 0x01);
        }
    }
};

ScanOptions tcp_units() {
    ScanOptions options;
    options.units = {1, 255, 0, 7};
    return options;
}

TEST(Scan, LearnsTablesLimitsAndFunctionsWithoutAWrite) {
    FakeDevice device;
    const auto scan = scan_device(std::ref(device), tcp_units());
    ASSERT_TRUE(scan) << scan.error();
    EXPECT_EQ(scan->tried, (Bytes{1, 255, 0, 7}));
    EXPECT_EQ(scan->answering, (Bytes{7}));
    EXPECT_EQ(scan->recon.unit, 7);
    EXPECT_EQ(scan->tables[0], (AddressRange{0, 99}));
    EXPECT_FALSE(scan->tables[1]);  // FC 02 answers 01
    EXPECT_EQ(scan->tables[2], (AddressRange{100, 349}));
    EXPECT_FALSE(scan->tables[3]);  // FC 04 is never answered
    EXPECT_EQ(scan->recon.max_read, 60);
    EXPECT_EQ(scan->echo.echoed, 20);
    EXPECT_EQ(scan->echo.refusal, 0x03);
    EXPECT_TRUE(scan->object_messaging);
    EXPECT_EQ(scan->semi_signature, 200);
    EXPECT_EQ(scan->fifo_address, 0);
    EXPECT_FALSE(scan->file_number);
    for (auto function : device.functions)
        EXPECT_FALSE(protocol::writes(function)) << "function " << int(function) << " was sent";
    EXPECT_EQ(scan->recon.not_asked, (Bytes{0x05, 0x06, 0x0F, 0x10, 0x15, 0x16, 0x17}));
}

TEST(Scan, TheDutFileLoadsAndSaysWhereEachValueCameFrom) {
    FakeDevice device;
    const auto scan = scan_device(std::ref(device), tcp_units());
    ASSERT_TRUE(scan);
    const std::string text = scan_dut_toml(*scan, {"tcp://192.0.2.1:502", "9.9", "2026-01-01"});
    EXPECT_THAT(
        text, HasSubstr("unit = 7  # learned by mblab scan: the only unit that answered FC 03\n"));
    EXPECT_THAT(text, HasSubstr("coils = 100  # learned by mblab scan: FC 01 answered 0..99"));
    EXPECT_THAT(text, HasSubstr("max_read = 60  # learned by mblab scan: FC 03 of 60 registers "
                                "answered at 100, of 61 did not\n"));
    EXPECT_THAT(text, HasSubstr("# registers: FC 03 answered 100..349, not from 0"));
    EXPECT_THAT(text, HasSubstr("echo_max_words = 20  # learned by mblab scan: FC 08/00 echoed 20 "
                                "data words; 21 answered exception 03"));
    EXPECT_THAT(text, HasSubstr("alternate_encoding = true  # learned by mblab scan: SEMI "
                                "signature 5345 4D49 5F72 at holding register 200"));
    EXPECT_THAT(text, HasSubstr("# input_registers: FC 04 got no answer"));
    EXPECT_THAT(text, HasSubstr("# discrete_inputs: FC 02 is not served (exception 01)"));
    EXPECT_THAT(text, HasSubstr("# not asked (they write): 05 06 0F 10 15 16 17"));
    EXPECT_THAT(text, HasSubstr("# device identification (FC 2B/0E): not answered (not asked)"));

    const auto path = std::filesystem::temp_directory_path() /
                      ("mblab-scan-test-" + std::to_string(::getpid()) + ".toml");
    std::ofstream(path) << text;
    const auto dut = conformance::load_dut_file(path.string());
    std::filesystem::remove(path);
    ASSERT_TRUE(dut) << dut.error();
    EXPECT_EQ(dut->unit, 7);
    EXPECT_EQ(dut->coils, 100U);
    EXPECT_FALSE(dut->registers);
    EXPECT_FALSE(dut->input_registers);
    EXPECT_EQ(dut->max_read, 60);
    EXPECT_EQ(dut->echo_max_words, 20);
    EXPECT_TRUE(dut->object_messaging);
    EXPECT_TRUE(dut->alternate_encoding);
    EXPECT_EQ(dut->fifo_address, 0);
    EXPECT_FALSE(dut->file_number);
}

TEST(Scan, AHoleEndsTheRunAtTheLastAddressReadWhole) {
    FakeDevice device;
    device.coil_hole = 70;
    const auto scan = scan_device(std::ref(device), tcp_units());
    ASSERT_TRUE(scan);
    // Halving from 0 steps over the hole (it reads 64, 96, 98, 99); reading the run whole does
    // not.
    EXPECT_EQ(scan->tables[0], (AddressRange{0, 69}));
}

TEST(Scan, AMuteDeviceIsOneLineNamingWhatWasTried) {
    FakeDevice device;
    ScanOptions options;
    options.units = {1, 255, 0};
    const auto scan = scan_device(std::ref(device), options);
    ASSERT_FALSE(scan);
    EXPECT_EQ(scan.error(),
              "no answer on unit 1, 255 or 0 to 3 requests (FC 03, holding register 0): check the "
              "port and --units");
}

TEST(Scan, OnALineNoRequestGoesToTheBroadcastOrAReservedAddress) {
    FakeDevice device;
    ScanOptions options;
    options.units = {0, 7, 250};
    options.line = true;
    const auto scan = scan_device(std::ref(device), options);
    ASSERT_TRUE(scan);
    EXPECT_EQ(scan->tried, (Bytes{7}));
    EXPECT_EQ(device.units, (std::set<std::uint8_t>{7}));
}

TEST(Scan, UnitsTextJoinsRuns) {
    EXPECT_EQ(units_text({1, 2, 3, 5, 7, 8}, " or "), "1-3, 5, 7 or 8");
    EXPECT_EQ(units_text({1, 255, 0}, " or "), "1, 255 or 0");
    EXPECT_EQ(units_text({9}, ", "), "9");
}

}  // namespace
}  // namespace mblab::robustness
