#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

#include "device/sunspec_loader.hpp"

namespace mblab::device {
namespace {

// The official model set is not in the repository (docs/sunspec.md): the tests read the copy
// beside the source tree, or the one MBLAB_SUNSPEC_MODELS names.
std::filesystem::path official_models() {
    if (const char* dir = std::getenv("MBLAB_SUNSPEC_MODELS")) return dir;
    return std::filesystem::path(MBLAB_SOURCE_DIR) / ".." / "shared" / "sunspec-models" / "json";
}

#define REQUIRE_OFFICIAL_MODELS()                                                            \
    if (!std::filesystem::is_directory(official_models())) {                                 \
        GTEST_SKIP() << "the official SunSpec models are not at " << official_models()       \
                     << " (set MBLAB_SUNSPEC_MODELS to the json/ folder of sunspec/models)"; \
    }

const SunSpecPoint& point_of(const SunSpecGroup& group, std::string_view name) {
    const SunSpecPoint* point = group.point(name);
    if (point == nullptr) throw std::runtime_error("no point " + std::string(name));
    return *point;
}

TEST(SunSpecModels, EveryOfficialModelLoads) {
    REQUIRE_OFFICIAL_MODELS();
    std::size_t files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(official_models())) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("model_", 0) != 0) continue;
        ++files;
        const auto model = read_sunspec_model(entry.path());
        ASSERT_TRUE(model) << model.error();
        EXPECT_EQ("model_" + std::to_string(model->id) + ".json", name);
    }
    // The folder's 114 files are 112 models, schema.json and a Makefile.
    EXPECT_EQ(files, 112U);
    const auto all = read_sunspec_models(official_models());
    ASSERT_TRUE(all) << all.error();
    EXPECT_EQ(all->size(), 112U);
}

TEST(SunSpecModels, CommonModelIsSixtySixRegisters) {
    REQUIRE_OFFICIAL_MODELS();
    const auto model = read_sunspec_model(official_models() / "model_1.json");
    ASSERT_TRUE(model) << model.error();
    EXPECT_EQ(model->id, 1);
    EXPECT_EQ(model->fixed_length, 66U);
    const SunSpecPoint& mn = point_of(model->group, "Mn");
    EXPECT_EQ(mn.offset, 2U);
    EXPECT_EQ(mn.size, 16);
    EXPECT_EQ(mn.type, SunSpecType::String);
    EXPECT_TRUE(mn.mandatory);
    EXPECT_TRUE(mn.is_static);
    EXPECT_EQ(point_of(model->group, "Md").offset, 18U);
    EXPECT_EQ(point_of(model->group, "SN").offset, 34U + 16U);
    const SunSpecPoint& da = point_of(model->group, "DA");
    EXPECT_TRUE(da.writable);
    EXPECT_FALSE(mn.writable);
}

TEST(SunSpecModels, InverterPointsHaveOffsetsTypesAndScaleFactors) {
    REQUIRE_OFFICIAL_MODELS();
    const auto model = read_sunspec_model(official_models() / "model_103.json");
    ASSERT_TRUE(model) << model.error();
    EXPECT_EQ(model->fixed_length, 50U);
    const SunSpecPoint& wh = point_of(model->group, "WH");
    EXPECT_EQ(wh.offset, 24U);
    EXPECT_EQ(wh.type, SunSpecType::Acc32);
    EXPECT_EQ(wh.sf, "WH_SF");
    EXPECT_EQ(wh.units, "Wh");
    EXPECT_EQ(point_of(model->group, "W_SF").type, SunSpecType::Sunssf);
    const SunSpecPoint& st = point_of(model->group, "St");
    EXPECT_EQ(st.offset, 38U);
    EXPECT_EQ(st.type, SunSpecType::Enum16);
    EXPECT_FALSE(st.symbols.empty());
    EXPECT_EQ(point_of(model->group, "Evt1").type, SunSpecType::Bitfield32);
}

TEST(SunSpecModels, RepeatingGroupsTakeTheirCountFromTheirCountPoint) {
    REQUIRE_OFFICIAL_MODELS();
    const auto model = read_sunspec_model(official_models() / "model_705.json");
    ASSERT_TRUE(model) << model.error();
    ASSERT_EQ(model->group.groups.size(), 1U);
    const SunSpecGroup& curve = model->group.groups[0];
    EXPECT_EQ(curve.count_point, "NCrv");
    ASSERT_EQ(curve.groups.size(), 1U);
    EXPECT_EQ(curve.groups[0].count_point, "NPt");
    EXPECT_EQ(curve.groups[0].size, 2U);
    // Curves of 10 registers before their points of 2 each.
    EXPECT_EQ(model->length_with({{"NCrv", 3}, {"NPt", 4}}),
              model->fixed_length + 3 * (10 + 4 * 2));
    EXPECT_EQ(model->length_with({{"NCrv", 1}, {"NPt", 1}}), model->fixed_length + 12);
}

TEST(SunSpecModels, NotImplementedValuesFollowTheType) {
    SunSpecPoint point;
    auto words = [&point](SunSpecType type, std::uint16_t size) {
        point.type = type;
        point.size = size;
        return not_implemented_words(point);
    };
    using W = std::vector<std::uint16_t>;
    EXPECT_EQ(words(SunSpecType::Int16, 1), W({0x8000}));
    EXPECT_EQ(words(SunSpecType::Uint16, 1), W({0xFFFF}));
    EXPECT_EQ(words(SunSpecType::Enum16, 1), W({0xFFFF}));
    EXPECT_EQ(words(SunSpecType::Acc32, 2), W({0, 0}));
    EXPECT_EQ(words(SunSpecType::Int32, 2), W({0x8000, 0}));
    EXPECT_EQ(words(SunSpecType::Uint32, 2), W({0xFFFF, 0xFFFF}));
    EXPECT_EQ(words(SunSpecType::Float32, 2), W({0x7FC0, 0}));
    EXPECT_EQ(words(SunSpecType::Sunssf, 1), W({0x8000}));
    EXPECT_EQ(words(SunSpecType::Int64, 4), W({0x8000, 0, 0, 0}));
    // As SunSpec's own pysunspec2 (mb.py) writes them: an EUI-48 of all ones in the low 48 bits
    // under a zero register, IPv4 and IPv6 addresses all zero.
    EXPECT_EQ(words(SunSpecType::Eui48, 4), W({0, 0xFFFF, 0xFFFF, 0xFFFF}));
    EXPECT_EQ(words(SunSpecType::Ipaddr, 2), W({0, 0}));
    EXPECT_EQ(words(SunSpecType::Ipv6addr, 8), W(8, 0));
    EXPECT_EQ(words(SunSpecType::String, 3), W({0, 0, 0}));
    EXPECT_TRUE(is_not_implemented(point, W({0, 0, 0})));
    EXPECT_FALSE(is_not_implemented(point, W({0x4100, 0, 0})));
    EXPECT_EQ(sunspec_raw_value(SunSpecType::Sunssf, W({0xFFFE})), -2.0);
    EXPECT_EQ(sunspec_raw_value(SunSpecType::Int32, W({0xFFFF, 0xFFFF})), -1.0);
    EXPECT_EQ(sunspec_raw_value(SunSpecType::Float32, W({0x3FC0, 0})), 1.5);
    EXPECT_EQ(sunspec_string(W({0x4142, 0x4300, 0x4400})), "ABC");
}

TEST(SunSpecModels, ErrorsNameTheFileAndThePoint) {
    const auto bad_type = parse_sunspec_model(
        R"({"id": 9, "group": {"name": "m", "points": [{"name": "ID", "type": "uint16", "size": 1},
            {"name": "L", "type": "uint16", "size": 1}, {"name": "X", "type": "int12", "size": 1}]}})",
        "m.json");
    ASSERT_FALSE(bad_type);
    EXPECT_EQ(bad_type.error(), "m.json: m.X: unknown type \"int12\"");
    const auto bad_sf = parse_sunspec_model(
        R"({"id": 9, "group": {"name": "m", "points": [{"name": "ID", "type": "uint16", "size": 1},
            {"name": "L", "type": "uint16", "size": 1},
            {"name": "X", "type": "int16", "size": 1, "sf": "Nope"}]}})",
        "m.json");
    ASSERT_FALSE(bad_sf);
    EXPECT_EQ(bad_sf.error(), "m.json: m.X: scale factor \"Nope\" names no point");
    const auto bad_size = parse_sunspec_model(
        R"({"id": 9, "group": {"name": "m", "points": [{"name": "ID", "type": "uint16", "size": 1},
            {"name": "L", "type": "uint32", "size": 1}]}})",
        "m.json");
    ASSERT_FALSE(bad_size);
    EXPECT_EQ(bad_size.error(), "m.json: m.L: size 1 for type uint32, which takes 2");
    EXPECT_FALSE(parse_sunspec_model("[1]", "m.json"));
}

void expect_same_layout(const SunSpecGroup& ours, const SunSpecGroup& official,
                        const std::string& where) {
    ASSERT_EQ(ours.points.size(), official.points.size()) << where;
    for (std::size_t i = 0; i < ours.points.size(); ++i) {
        const SunSpecPoint& mine = ours.points[i];
        const SunSpecPoint& theirs = official.points[i];
        const std::string at = where + "." + theirs.name;
        EXPECT_EQ(mine.name, theirs.name) << at;
        EXPECT_EQ(mine.offset, theirs.offset) << at;
        EXPECT_EQ(mine.type, theirs.type) << at;
        EXPECT_EQ(mine.size, theirs.size) << at;
        EXPECT_EQ(mine.sf, theirs.sf) << at;
        EXPECT_EQ(mine.writable, theirs.writable) << at;
        EXPECT_EQ(mine.mandatory, theirs.mandatory) << at;
        EXPECT_EQ(mine.is_static, theirs.is_static) << at;
        EXPECT_EQ(mine.units, theirs.units) << at;
        if (mine.type == SunSpecType::Enum16 || mine.type == SunSpecType::Enum32) {
            ASSERT_EQ(mine.symbols.size(), theirs.symbols.size()) << at;
            for (std::size_t s = 0; s < mine.symbols.size(); ++s) {
                EXPECT_EQ(mine.symbols[s].name, theirs.symbols[s].name) << at;
                EXPECT_EQ(mine.symbols[s].value, theirs.symbols[s].value) << at;
            }
        }
    }
    ASSERT_EQ(ours.groups.size(), official.groups.size()) << where;
    for (std::size_t i = 0; i < ours.groups.size(); ++i) {
        EXPECT_EQ(ours.groups[i].count_point, official.groups[i].count_point) << where;
        expect_same_layout(ours.groups[i], official.groups[i], where + "." + ours.groups[i].name);
    }
}

// The project's own definitions (sunspec/, written from the public model descriptions) must lay
// out every point where the official ones do.
TEST(SunSpecModels, OwnDefinitionsAgreeWithTheOfficialOnes) {
    REQUIRE_OFFICIAL_MODELS();
    const auto ours = read_sunspec_models(std::filesystem::path(MBLAB_SOURCE_DIR) / "sunspec");
    ASSERT_TRUE(ours) << ours.error();
    for (std::uint16_t id : {1, 103, 120, 121, 122, 123, 203})
        EXPECT_EQ(ours->count(id), 1U) << "model " << id;
    for (const auto& [id, model] : *ours) {
        const auto official =
            read_sunspec_model(official_models() / ("model_" + std::to_string(id) + ".json"));
        ASSERT_TRUE(official) << official.error();
        EXPECT_EQ(model.fixed_length, official->fixed_length) << "model " << id;
        expect_same_layout(model.group, official->group, "model " + std::to_string(id));
    }
}

// An accumulator that rolls over at its maximum went forward; one read lower by a small step, or
// by more than half its range forward, went back.
TEST(SunSpecModels, AnAccumulatorRollingOverIsNoStepBack) {
    using Words = std::vector<std::uint16_t>;
    EXPECT_FALSE(sunspec_accumulator_went_back(Words{10}, Words{10}));
    EXPECT_FALSE(sunspec_accumulator_went_back(Words{10}, Words{11}));
    EXPECT_FALSE(sunspec_accumulator_went_back(Words{0xFFFE}, Words{0x0003}));  // acc16 wraps
    EXPECT_TRUE(sunspec_accumulator_went_back(Words{11}, Words{10}));
    EXPECT_TRUE(sunspec_accumulator_went_back(Words{0x0003}, Words{0xFFFE}));
    EXPECT_FALSE(sunspec_accumulator_went_back(Words{0xFFFF, 0xFFF0}, Words{0x0000, 0x0010}));
    EXPECT_TRUE(sunspec_accumulator_went_back(Words{0x0001, 0x0000}, Words{0x0000, 0xFFFF}));
    EXPECT_FALSE(sunspec_accumulator_went_back(Words{0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF},
                                               Words{0, 0, 0, 5}));  // acc64 wraps
    EXPECT_TRUE(sunspec_accumulator_went_back(Words{0, 0, 1, 0}, Words{0, 0, 0, 9}));
}

}  // namespace
}  // namespace mblab::device
