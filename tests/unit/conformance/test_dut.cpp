#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "conformance/dut.hpp"
#include "support/hex.hpp"
#include "support/temp_path.hpp"

namespace mblab::conformance {
namespace {

std::string write_temp(const std::string& text) {
    std::string path = test::temp_path("dut.toml");
    std::ofstream(path) << text;
    return path;
}

TEST(DutFile, LoadsEveryKey) {
    auto path = write_temp(
        "unit = 7\nregisters = 4096\nmax_read = 100\nobject_messaging = true\n"
        "alternate_encoding = true\ncoils = 2000\ndiscrete_inputs = 16\ninput_registers = 10\n"
        "read_only_register = 0x20\nread_only_coil = 3\nfifo_address = 0x4DE\nfile_number = 2\n"
        "echo_max_words = 100\n");
    auto dut = load_dut_file(path);
    ASSERT_TRUE(dut.ok()) << dut.error();
    EXPECT_EQ(dut->unit, 7);
    EXPECT_EQ(dut->registers, 4096U);
    EXPECT_EQ(dut->max_read, 100);
    EXPECT_TRUE(dut->object_messaging);
    EXPECT_TRUE(dut->alternate_encoding);
    EXPECT_EQ(dut->read_only_register, 0x20);
    EXPECT_EQ(dut->fifo_address, 0x4DE);
    EXPECT_EQ(dut->echo_max_words, 100);
    EXPECT_EQ(dut->declared_by, path);
}

TEST(DutFile, RefusesBadValuesWithLine) {
    auto path = write_temp("unit = 1\nregisters = 70000\n");
    auto dut = load_dut_file(path);
    ASSERT_FALSE(dut.ok());
    EXPECT_EQ(dut.error(), path + ":2: 'registers' must be an integer from 1 to 65536");
    path = write_temp("unit = 1\nregister = 10\n");
    dut = load_dut_file(path);
    ASSERT_FALSE(dut.ok());
    EXPECT_EQ(dut.error().rfind(path + ":2: unknown key 'register' (known keys: unit, ", 0), 0U)
        << dut.error();
}

TEST(DutFacts, OutOfRangeReadFollowsSeed000Note) {
    Dut dut;
    DutFacts facts(dut);
    EXPECT_EQ(facts.fact("out_of_range_registers"), test::hex("80 01 00 01"));  // undeclared
    dut.registers = 0x8001;
    EXPECT_EQ(facts.fact("out_of_range_registers"), test::hex("80 01 00 01"));
    dut.registers = 0x9000;
    EXPECT_EQ(facts.fact("out_of_range_registers"), test::hex("90 00 00 01"));
    dut.registers = 65536;
    EXPECT_EQ(facts.fact("out_of_range_registers"), test::hex("FF FF 00 02"));
}

TEST(DutFacts, EchoDataAndPlainFacts) {
    Dut dut;
    dut.unit = 9;
    DutFacts facts(dut);
    EXPECT_EQ(facts.fact("unit"), test::hex("09"));
    EXPECT_FALSE(facts.fact("echo_max_data").has_value());
    EXPECT_FALSE(facts.fact("fifo_address").has_value());
    dut.echo_max_words = 2;
    dut.fifo_address = 0x04DE;
    EXPECT_EQ(facts.fact("echo_max_data"), test::hex("A0 00 A0 01"));
    EXPECT_EQ(facts.fact("echo_over_data"), test::hex("A0 00 A0 01 A0 02"));
    EXPECT_EQ(facts.fact("fifo_address"), test::hex("04 DE"));
}

TEST(Requirements, SayWhyTheyAreUnmet) {
    Dut dut;
    auto needs_coils = parse_requirement("coils >= 2000");
    ASSERT_TRUE(needs_coils.ok());
    EXPECT_EQ(unmet(needs_coils.value(), dut)->reason, "the DUT does not declare coils");
    EXPECT_EQ(unmet(needs_coils.value(), dut)->undeclared, "coils");
    dut.coils = 100;
    EXPECT_EQ(unmet(needs_coils.value(), dut)->reason,
              "needs coils >= 2000; the DUT declares coils = 100");
    EXPECT_EQ(unmet(needs_coils.value(), dut)->undeclared, "");
    dut.coils = 2000;
    EXPECT_FALSE(unmet(needs_coils.value(), dut).has_value());
    auto needs_5b = parse_requirement("object_messaging");
    ASSERT_TRUE(needs_5b.ok());
    EXPECT_EQ(unmet(needs_5b.value(), dut)->reason, "the DUT does not declare object_messaging");
    dut.object_messaging = true;
    EXPECT_FALSE(unmet(needs_5b.value(), dut).has_value());
    EXPECT_FALSE(parse_requirement("coils 5").ok());
}

}  // namespace
}  // namespace mblab::conformance
