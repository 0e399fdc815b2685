// A bad profile is refused with one line naming the file, line, key and the fix.
#include <gtest/gtest.h>

#include "device/profile_loader.hpp"
#include "device_harness.hpp"

namespace mblab::test {
namespace {

struct BadProfile {
    std::string_view text;
    std::string_view error;
};

class ProfileErrors : public ::testing::TestWithParam<BadProfile> {};

TEST_P(ProfileErrors, NamesFileLineKeyAndFix) {
    EXPECT_EQ(profile_error(GetParam().text), GetParam().error);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, ProfileErrors,
    ::testing::Values(
        BadProfile{"[[unit]]\nid = 1\n[[unit.holding_registers]]\nstart = 0\naccess = \"rx\"\n",
                   "test.toml:5: unit[0].holding_registers[0].access: expected one of ro, rw, wo, "
                   "got \"rx\""},
        BadProfile{"name = \"x\"\n",
                   "test.toml:1: unit: missing key; add at least one [[unit]] table with an id"},
        BadProfile{"[[unit]]\nid = 1\n[[unit.coils]]\nstart = 0\nacess = \"rw\"\n",
                   "test.toml:5: unit[0].coils[0].acess: unknown key; expected one of start, "
                   "access, type, name, description, count, value, values"},
        BadProfile{"[[unit]]\nid = 1\n[[unit.holding_registers]]\nstart = 0\ncount = 10\n"
                   "[[unit.holding_registers]]\nstart = 5\n",
                   "test.toml:6: unit[0].holding_registers[1]: addresses 5..5 overlap "
                   "holding_registers[0] (0..9); ranges of a bank must not overlap"},
        BadProfile{"addresses = [1, 95]\n[[unit]]\nid = 96\n",
                   "test.toml:3: unit[0].id: expected an integer from 1 to 95, got 96"},
        BadProfile{"[[unit]]\nid = 1\n[[unit]]\nid = 1\n",
                   "test.toml:4: unit[1].id: unit 1 appears twice"},
        BadProfile{"[[unit]]\nid = 1\nsemi_signature = 0\n",
                   "test.toml:3: unit[0].semi_signature: holding register 0 is not in any "
                   "holding_registers range; the signature takes 3 registers"},
        BadProfile{"[[unit]]\nid = 1\n[[unit.coils]]\nstart = 65535\ncount = 2\n",
                   "test.toml:5: unit[0].coils[0].count: expected an integer from 1 to 1, got 2"},
        BadProfile{"[[unit]]\nid = 1\nmax_read_registers = \"many\"\n",
                   "test.toml:3: unit[0].max_read_registers: expected an integer, got the "
                   "string \"many\""},
        BadProfile{"[[unit]]\nid = 1\nmax_read_registers = 126\n",
                   "test.toml:3: unit[0].max_read_registers: expected an integer from 1 to 125, "
                   "got 126"},
        BadProfile{"[[unit]]\nid = 1\n[[unit.faults]]\naction = \"drop\"\nevery = 2\n"
                   "probability = 0.5\n",
                   "test.toml:6: unit[0].faults[0].probability: give either every (every Nth "
                   "request) or probability"},
        BadProfile{"[[unit]]\nid = 1\n[[unit.faults]]\naction = \"delay\"\n",
                   "test.toml:3: unit[0].faults[0].delay_ms: missing key; a delay rule needs it: "
                   "how long to hold the answer, in milliseconds"},
        BadProfile{"[[unit]]\nid = 1\n[unit.identification]\nvendor = \"v\"\n"
                   "product_code = \"p\"\n",
                   "test.toml:3: unit[0].identification.revision: missing key; vendor, "
                   "product_code and revision are mandatory objects"},
        BadProfile{"[[unit]]\nid = 1\n[[unit.holding_registers]]\nstart = 0\ncount = 2\n"
                   "values = [1, 2, 3]\n",
                   "test.toml:6: unit[0].holding_registers[0].values: the value needs 3 "
                   "addresses but count is 2"},
        BadProfile{"[[unit]]\nid = 1\n[[unit.holding_registers]]\nstart = 0\nvalue = 70000\n",
                   "test.toml:5: unit[0].holding_registers[0].value: expected an integer from 0 "
                   "to 65535, got 70000"},
        BadProfile{"[[unit]]\nid = 1\nfunctions = [3, 65]\n",
                   "test.toml:3: unit[0].functions: function 65 is not a public function code "
                   "the device implements"},
        BadProfile{"[[unit]]\nid = 1\nfifos = [10]\n",
                   "test.toml:3: unit[0].fifos: holding register 10 (the FIFO count) is not in "
                   "any holding_registers range"},
        BadProfile{"[[unit]\nid = 1\n",
                   "test.toml:1: TOML syntax: Error while parsing table header: expected ']', "
                   "saw '\\n'"}));

TEST(ProfileFiles, MissingFileNamesThePath) {
    auto loaded = device::read_profile("/nonexistent/x.toml");
    ASSERT_FALSE(loaded);
    EXPECT_EQ(loaded.error(),
              "/nonexistent/x.toml: cannot open the profile; check the path (the shipped profiles "
              "are in the profiles/ folder)");
}

TEST(ProfileFiles, EveryShippedProfileLoads) {
    for (const char* name :
         {"reference", "rs485-instrument", "access-ranges", "multi-unit", "moving"}) {
        EXPECT_NE(shipped_device(name), nullptr) << name;
    }
}

}  // namespace
}  // namespace mblab::test
