#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "conformance/catalogue.hpp"
#include "conformance/dut.hpp"
#include "conformance/procedures.hpp"
#include "support/hex.hpp"

namespace mblab::conformance {
namespace {

constexpr const char* kHeader = R"([suite]
name = "t"
)";

std::string load_error(const std::string& body) {
    auto suite = load_suite_text(kHeader + body, "bad.toml");
    EXPECT_FALSE(suite.ok()) << body;
    return suite.ok() ? std::string() : suite.error();
}

TEST(CatalogueLoader, LoadsShorthandStepsAlternativesAndProcedures) {
    auto suite = load_suite_text(std::string(kHeader) + R"(
[[case]]
id = "a"
source = "CTP 9.1.4"
title = "alternatives"
request = "00 00 00 00 {len} {unit} 03 00 00 FF FF"
expect = "00 00 00 00 00 03 {unit} 83 03"
accept = [{ expect = "00 00 00 00 00 03 {unit} 83 02", remark = "02 is not preferred" }]
timeout_ms = 2000

[[case]]
id = "b"
source = "s"
title = "steps"
depends_on = ["a"]
requires = ["coils >= 64", "file_number"]
pipeline = true
[[case.step]]
request = "00 01 00 00 00 02 {unit} 07"
expect = "00 01 00 00 00 03 {unit} 07 XX"
[[case.step]]
request = "00 02 00 01 00 02 {unit} 07"
silence_ms = 100
split = [3, 6]

[[case]]
id = "c"
source = "s"
title = "procedure"
procedure = "ping"
params = { count = 3 }
)",
                                 "good.toml");
    ASSERT_TRUE(suite.ok()) << suite.error();
    ASSERT_EQ(suite->cases.size(), 3U);
    const Case& a = suite->cases[0];
    EXPECT_EQ(a.line, 4U);
    ASSERT_EQ(a.steps.size(), 1U);
    ASSERT_EQ(a.steps[0].expect.size(), 2U);
    EXPECT_EQ(a.steps[0].expect[1].remark, "02 is not preferred");
    EXPECT_EQ(a.steps[0].timeout, std::chrono::milliseconds(2000));
    const Case& b = suite->cases[1];
    EXPECT_TRUE(b.pipeline);
    EXPECT_EQ(b.depends_on, std::vector<std::string>{"a"});
    ASSERT_EQ(b.requirements.size(), 2U);
    EXPECT_EQ(b.requirements[0].fact, "coils");
    EXPECT_EQ(b.requirements[0].op, ">=");
    EXPECT_EQ(b.requirements[0].value, 64);
    ASSERT_EQ(b.steps.size(), 2U);
    EXPECT_EQ(b.steps[1].silence, std::chrono::milliseconds(100));
    EXPECT_EQ(b.steps[1].split, (std::vector<std::size_t>{3, 6}));
    EXPECT_EQ(suite->cases[2].params.at("count"), 3);
}

TEST(CatalogueLoader, RefusesMalformedSuitesWithFileLineAndReason) {
    const std::string case_head = "[[case]]\nid = \"x\"\nsource = \"s\"\ntitle = \"t\"\n";
    struct Bad {
        std::string body;
        std::string error;
    };
    const std::vector<Bad> cases = {
        {"[[case]]\nid = \"x\"\n", "bad.toml:3: a case needs 'source'"},
        {case_head + "request = \"00 0G\"\nexpect = \"00\"\n",
         "bad.toml:7: request: column 4: '0G': expected hex bytes, XX, {placeholder} or ..."},
        {case_head + "request = \"00 XX\"\nexpect = \"00\"\n",
         "bad.toml:7: request: XX and ... are for expected patterns; a request is exact bytes"},
        {case_head + "request = \"00\"\nexpect = \"00 {foo}\"\n",
         "bad.toml:8: expected pattern: unknown placeholder {foo}"},
        {case_head + "request = \"00\"\nexpected = \"00\"\n",
         "bad.toml:8: unknown key 'expected' (known keys: id, source, title, procedure, params, "
         "step, requires, depends_on, pipeline, isolated, unsupported_is_na, request, expect, "
         "accept, silence_ms, accept_close, accept_silence, timeout_ms, split, split_delay_ms)"},
        {case_head + "request = \"00\"\n",
         "bad.toml:3: case x: a step gives either 'expect' or "
         "'silence_ms'"},
        {case_head + "request = \"00\"\nexpect = \"00\"\nsilence_ms = 5\n",
         "bad.toml:3: case x: a step gives either 'expect' or 'silence_ms'"},
        {case_head + "procedure = \"sweep\"\n",
         "bad.toml:7: unknown procedure 'sweep' (known: ping, register_sweep, "
         "semi_signature_scan, out_of_range_read, other_address_read, "
         "other_address_write, broadcast_write, broadcast_unanswered, wrong_checksum, "
         "answer_frame, "
         "ascii_lower_case, broken_request, answer_timing, tls_handshake, tls10_refused, "
         "tls11_refused, "
         "no_certificate_refused, expired_certificate_refused, foreign_ca_certificate_refused, "
         "self_signed_certificate_refused, null_role_denied, read_only_role, write_role, "
         "tls_renegotiation, tls_close_notify, sunspec_marker, sunspec_common, sunspec_chain_end, "
         "sunspec_lengths, sunspec_unknown, sunspec_mandatory, sunspec_sentinels, "
         "sunspec_scale_factors, sunspec_enums, sunspec_strings, sunspec_accumulators, "
         "sunspec_chunks, sunspec_rw_points, sunspec_read_only, sunspec_bad_enum, sunspec_line)"},
        {case_head + "procedure = \"ping\"\nparams = { cnt = 1 }\n",
         "bad.toml:8: unknown key 'cnt' (known keys: count, payload, timeout_ms)"},
        {case_head + "procedure = \"ping\"\nrequest = \"00\"\n",
         "bad.toml:3: case x: a procedure case has no request, expect or steps"},
        {case_head + "requires = [\"colis >= 2\"]\nrequest = \"00\"\nexpect = \"00\"\n",
         "bad.toml:7: requirement 'colis >= 2' names no DUT fact"},
        {case_head + "requires = [\"coils >> 2\"]\nrequest = \"00\"\nexpect = \"00\"\n",
         "bad.toml:7: requirement 'coils >> 2' is not 'fact' or 'fact OP number'"},
        {case_head + "depends_on = [\"y\"]\nrequest = \"00\"\nexpect = \"00\"\n",
         "bad.toml:3: depends_on names 'y', which is not an earlier case of this suite"},
        {case_head + "request = \"00 01\"\nexpect = \"00\"\nsplit = [2]\n",
         "bad.toml:9: case x: 'split' is a rising list of byte offsets inside the request"},
        {case_head + "request = \"00\"\nexpect = \"00\"\ntimeout_ms = -1\n",
         "bad.toml:9: 'timeout_ms' must be an integer from 0 to 60000"},
        {case_head + "request = \"00\"\naccept = [{ expect = \"01\" }]\n",
         "bad.toml:8: case x: 'accept' adds to an 'expect'"},
        {case_head + "request = \"00\"\nexpect = \"00\"\n" + case_head +
             "request = \"00\"\nexpect = \"00\"\n",
         "bad.toml:9: case id 'x' is used twice"},
        {"", "bad.toml:1: the suite has no [[case]] tables"},
    };
    for (const auto& bad : cases)
        EXPECT_EQ(load_error(bad.body), bad.error) << bad.body;
}

TEST(CatalogueLoader, RefusesASuiteWithoutHeaderOrWithBrokenToml) {
    auto missing = load_suite_text("[[case]]\nid = \"x\"\n", "bad.toml");
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error(), "bad.toml:1: a suite starts with a [suite] table giving its name");
    auto broken = load_suite_text("[suite]\nname = \"t\"\n[[case]\n", "bad.toml");
    ASSERT_FALSE(broken.ok());
    EXPECT_EQ(broken.error().rfind("bad.toml:3: ", 0), 0U) << broken.error();
    auto absent = load_suite_file("/nonexistent/suite.toml");
    ASSERT_FALSE(absent.ok());
    EXPECT_EQ(absent.error(), "/nonexistent/suite.toml: cannot read file");
}

std::vector<std::string> shipped() {
    return shipped_suite_files(std::string(MBLAB_SOURCE_DIR) + "/catalogue");
}

TEST(ShippedCatalogue, EverySuiteLoadsAndCitesItsSources) {
    auto files = shipped();
    ASSERT_GE(files.size(), 6U);
    EXPECT_EQ(std::filesystem::path(files.front()).filename(), "policy-2.1.toml");
    std::set<std::string> names;
    for (const auto& file : files) {
        auto suite = load_suite_file(file);
        ASSERT_TRUE(suite.ok()) << suite.error();
        EXPECT_TRUE(names.insert(suite->name).second) << suite->name;
        for (const auto& c : suite->cases) {
            EXPECT_FALSE(c.source.empty()) << c.id;
            EXPECT_FALSE(c.title.empty()) << c.id;
        }
    }
    for (const char* name : {"policy-2.1", "mbap", "exceptions", "diagnostics", "device-id",
                             "function-codes", "serial"}) {
        EXPECT_TRUE(names.count(name)) << name;
    }
}

TEST(ShippedCatalogue, PolicyEncodesEveryTestOfSeed000) {
    auto suite = load_suite_file(std::string(MBLAB_SOURCE_DIR) + "/catalogue/policy-2.1.toml");
    ASSERT_TRUE(suite.ok()) << suite.error();
    std::vector<std::string> ids;
    for (const auto& c : suite->cases)
        ids.push_back(c.id);
    EXPECT_EQ(ids,
              (std::vector<std::string>{"7.2", "7.3.1", "7.4.1", "7.5.1", "7.5.2", "7.6.1", "7.7.1",
                                        "7.8.1", "7.9.1", "7.10.1", "7.11.1", "7.12.1", "7.13.1",
                                        "7.13.2", "9.1.1", "9.1.2", "9.1.3", "9.1.4"}));
    Dut dut;
    dut.unit = 0x11;
    DutFacts facts(dut);
    auto request_of = [&](const std::string& id) {
        for (const auto& c : suite->cases) {
            if (c.id == id) return render_bytes(resolve(c.steps.at(0).request, facts).value());
        }
        return std::vector<std::uint8_t>{};
    };
    EXPECT_EQ(request_of("9.1.3"), test::hex("00 00 00 00 00 FF 11 03 00 00 00 01"));
    EXPECT_EQ(request_of("7.13.1"),
              test::hex("00 00 00 00 00 0C 11 5B 09 00 00 01 00 01 00 07 00 01"));
    // 9.1.2 is the policy's request first, then (only if 0x8001 is a register) a read past the end.
    const auto out_of_range = out_of_range_steps(dut);
    ASSERT_EQ(out_of_range.size(), 2U);
    EXPECT_EQ(out_of_range[0].request, test::hex("00 00 00 00 00 06 11 03 80 01 00 01"));
    EXPECT_EQ(out_of_range[1].request, test::hex("00 00 00 00 00 06 11 03 FF FF 00 02"));
    dut.registers = 100;
    EXPECT_EQ(out_of_range_steps(dut).at(0).request,
              test::hex("00 00 00 00 00 06 11 03 80 01 00 01"));
    dut.registers = 0x9000;
    EXPECT_EQ(out_of_range_steps(dut).at(0).request,
              test::hex("00 00 00 00 00 06 11 03 90 00 00 01"));
    // The write cases begin with the policy's own request.
    EXPECT_EQ(request_of("7.8.1"), test::hex("00 00 00 00 00 06 11 06 00 10 12 34"));
    EXPECT_EQ(request_of("7.9.1"), test::hex("00 00 00 00 00 02 11 07"));
}

}  // namespace
}  // namespace mblab::conformance
