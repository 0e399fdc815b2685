#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "conformance/sunspec_scan.hpp"
#include "device/sunspec_loader.hpp"

namespace mblab::conformance {
namespace {

using Words = std::vector<std::uint16_t>;

// Holding registers that answer exception 02 outside what was written; counts every read.
struct Registers {
    std::map<std::uint32_t, std::uint16_t> cells;
    std::vector<std::pair<std::uint16_t, std::uint16_t>> reads;

    void put(std::uint32_t address, const Words& words) {
        for (std::uint16_t word : words)
            cells[address++] = word;
    }

    RegisterReader reader() {
        return [this](std::uint16_t address,
                      std::uint16_t count) -> client::CallResult<std::vector<std::uint16_t>> {
            reads.emplace_back(address, count);
            Words words;
            for (std::uint32_t a = address; a < address + count; ++a) {
                const auto found = cells.find(a);
                if (found == cells.end()) {
                    return client::ClientError{client::ErrorKind::Exception, "exception 02",
                                               protocol::ExceptionCode::IllegalDataAddress};
                }
                words.push_back(found->second);
            }
            return words;
        };
    }
};

std::map<std::uint16_t, device::SunSpecModel> own_models() {
    auto models = device::read_sunspec_models(std::filesystem::path(MBLAB_SOURCE_DIR) / "sunspec");
    if (!models) throw std::runtime_error(models.error());
    return std::move(models).value();
}

Words text(const std::string& value, std::size_t registers) {
    Words words(registers, 0);
    for (std::size_t i = 0; i < value.size() && i / 2 < registers; ++i) {
        words[i / 2] |= static_cast<std::uint16_t>(static_cast<unsigned char>(value[i])
                                                   << (i % 2 == 0 ? 8 : 0));
    }
    return words;
}

// SunS, common (66), inverter 103 (50) with a few points set, the end model.
Registers small_chain(std::uint32_t base) {
    Registers device;
    device.put(base, {0x5375, 0x6E53});
    device.put(base + 2, {1, 66});
    device.put(base + 4, text("mblab", 16));
    device.put(base + 20, text("test inverter", 16));
    device.put(base + 36, text("", 8));
    device.put(base + 44, text("1.0", 8));
    device.put(base + 52, text("SN-1", 16));
    device.put(base + 68, {1, 0x8000});
    const std::uint32_t inverter = base + 70;
    Words registers(52, 0xFFFF);
    registers[0] = 103;
    registers[1] = 50;
    registers[2] = 123;     // A
    registers[6] = 0xFFFE;  // A_SF -2
    registers[14] = 2500;   // W
    registers[15] = 1;      // W_SF
    registers[24] = 0;      // WH
    registers[25] = 4321;
    registers[26] = 0;       // WH_SF
    registers[38] = 4;       // St MPPT
    registers[13] = 0x8000;  // V_SF not implemented
    device.put(inverter, registers);
    device.put(inverter + 52, {0xFFFF, 0});
    return device;
}

const SunSpecPointReading& point_named(const SunSpecModelReading& model, const std::string& name) {
    for (const SunSpecPointReading& point : model.points) {
        if (point.point->name == name) return point;
    }
    throw std::runtime_error("no point " + name);
}

TEST(SunSpecScan, ReadsTheChainAndScalesEachPoint) {
    const auto models = own_models();
    Registers device = small_chain(40000);
    const auto scan = scan_sunspec(device.reader(), models);
    ASSERT_TRUE(scan) << scan.error();
    EXPECT_EQ(scan->base, 40000);
    ASSERT_EQ(scan->models.size(), 2U);
    EXPECT_EQ(scan->end_address, 40000U + 2 + 68 + 52);
    const SunSpecModelReading& common = scan->models[0];
    EXPECT_EQ(common.id, 1);
    EXPECT_EQ(common.problem, "");
    EXPECT_EQ(device::sunspec_string(point_named(common, "Md").words), "test inverter");
    EXPECT_FALSE(point_named(common, "Opt").implemented);
    const SunSpecModelReading& inverter = scan->models[1];
    EXPECT_EQ(inverter.address, 40070U);
    EXPECT_EQ(inverter.problem, "");
    EXPECT_DOUBLE_EQ(*point_named(inverter, "A").value, 1.23);
    EXPECT_DOUBLE_EQ(*point_named(inverter, "W").value, 25000.0);
    EXPECT_DOUBLE_EQ(*point_named(inverter, "WH").value, 4321.0);
    EXPECT_EQ(symbol_name(*point_named(inverter, "St").point, *point_named(inverter, "St").value),
              "MPPT");
    EXPECT_FALSE(point_named(inverter, "PhVphA").implemented);
    EXPECT_FALSE(point_named(inverter, "V_SF").implemented);
    for (const auto& [address, count] : device.reads)
        EXPECT_LE(count, kMaxRegistersPerRead);
}

TEST(SunSpecScan, LooksAtZeroAfterFortyThousand) {
    Registers device = small_chain(0);
    const auto scan = scan_sunspec(device.reader(), own_models());
    ASSERT_TRUE(scan) << scan.error();
    EXPECT_EQ(scan->base, 0);
    EXPECT_EQ(device.reads.front(), std::make_pair(std::uint16_t{40000}, std::uint16_t{2}));
}

TEST(SunSpecScan, NoMarkerNamesTheBasesTried) {
    Registers device;
    device.put(40000, {0x5375, 0x6E54});
    const auto scan = scan_sunspec(device.reader(), own_models());
    ASSERT_FALSE(scan);
    EXPECT_EQ(scan.error(), "no SunSpec marker (\"SunS\", 0x5375 0x6E53) at 40000, 0, 50000");
}

TEST(SunSpecScan, UnknownModelsAndWrongLengthsAreNoted) {
    Registers device = small_chain(50000);
    device.put(50000 + 70, {64999, 50});  // the inverter's place, an id nobody defines
    auto scan = scan_sunspec(device.reader(), own_models());
    ASSERT_TRUE(scan) << scan.error();
    EXPECT_EQ(scan->models[1].problem, "no definition of model 64999");
    EXPECT_EQ(scan->models[1].definition, nullptr);

    device = small_chain(40000);
    device.put(40000 + 70, {103, 48});
    device.put(40000 + 70 + 50, {0xFFFF, 0});
    scan = scan_sunspec(device.reader(), own_models());
    ASSERT_TRUE(scan) << scan.error();
    EXPECT_EQ(scan->models[1].problem, "the model ends inside point EvtVnd4");
}

TEST(SunSpecScan, AChainWithoutEndStopsAtTheAddressSpace) {
    Registers device;
    device.put(50000, {0x5375, 0x6E53});
    for (std::uint32_t address = 50002; address + 2 <= 0x10000; address += 2) {
        device.put(address, {64998, 0});
    }
    const auto scan = scan_sunspec(device.reader(), own_models());
    ASSERT_TRUE(scan) << scan.error();
    EXPECT_EQ(scan->chain_problem,
              "the chain runs past the last register (65535) without the end model 0xFFFF");
    EXPECT_EQ(scan->models.size(), (0x10000U - 50002U) / 2U);
}

TEST(SunSpecScan, RepeatingGroupsRepeatAsTheirCountSays) {
    auto curve = device::parse_sunspec_model(
        R"({"id": 64900, "group": {"name": "curves", "points": [
            {"name": "ID", "type": "uint16", "size": 1}, {"name": "L", "type": "uint16", "size": 1},
            {"name": "NPt", "type": "uint16", "size": 1},
            {"name": "V_SF", "type": "sunssf", "size": 1}],
          "groups": [{"name": "pt", "count": "NPt", "points": [
            {"name": "V", "type": "uint16", "size": 1, "sf": "V_SF", "units": "V"}]}]}})",
        "curves.json");
    ASSERT_TRUE(curve) << curve.error();
    std::map<std::uint16_t, device::SunSpecModel> models{{64900, std::move(curve).value()}};
    Registers device;
    device.put(40000, {0x5375, 0x6E53, 64900, 5, 3, 0xFFFF, 2300, 2310, 2320, 0xFFFF, 0});
    const auto scan = scan_sunspec(device.reader(), models);
    ASSERT_TRUE(scan) << scan.error();
    ASSERT_EQ(scan->models.size(), 1U);
    const SunSpecModelReading& model = scan->models[0];
    EXPECT_EQ(model.problem, "");
    ASSERT_EQ(model.points.size(), 4U + 3U);
    EXPECT_EQ(model.points[6].group, "pt[3]");
    EXPECT_EQ(model.points[6].address, 40008U);
    EXPECT_DOUBLE_EQ(*model.points[6].value, 232.0);
}

}  // namespace
}  // namespace mblab::conformance
