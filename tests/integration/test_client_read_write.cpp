#include <gmock/gmock.h>

#include <nlohmann/json.hpp>

#include "test_client_support.hpp"

// `mblab read` and `mblab write` against the reference device: what one writes the other reads
// back, typed the same way both ways, as tables and as JSON.
namespace mblab::test {
namespace {

using ::testing::HasSubstr;

using ClientReadWrite = ReferenceCliTest;

TEST_F(ClientReadWrite, ReadsHoldingRegistersAsATable) {
    auto ran = mblab("read", {"holding", "0", "3"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.err, "");
    // The reference profile keeps the SEMI signature at holding 0..2 (CTP 7.13.2).
    EXPECT_EQ(ran.out,
              "address     raw     u16\n"
              "0 (0x0000)  0x5345  21317\n"
              "1 (0x0001)  0x4D49  19785\n"
              "2 (0x0002)  0x5F72  24434\n");
}

TEST_F(ClientReadWrite, FloatsWrittenAreReadBackInEveryWordAndByteOrder) {
    for (const char* words : {"big", "little"}) {
        for (const char* bytes : {"big", "little"}) {
            SCOPED_TRACE(std::string(words) + "/" + bytes);
            auto wrote = mblab("write", {"registers", "0x100", "3.5", "-1000", "--type", "f32",
                                         "--word-order", words, "--byte-order", bytes});
            EXPECT_EQ(wrote.status, 0) << wrote.err;
            EXPECT_EQ(wrote.out, "wrote 4 registers at 256 (0x0100)\n");
            auto read = mblab("read", {"holding", "0x100", "2", "--type", "f32", "--word-order",
                                       words, "--byte-order", bytes});
            EXPECT_EQ(read.status, 0) << read.err;
            EXPECT_THAT(read.out, HasSubstr("256 (0x0100)"));
            EXPECT_THAT(read.out, HasSubstr("  3.5\n"));
            EXPECT_THAT(read.out, HasSubstr("  -1000\n"));
        }
    }
}

TEST_F(ClientReadWrite, WordAndByteOrderPlaceTheBytesOfAValue) {
    // 0x11223344 as u32 in each order, read back as raw registers.
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"--word-order", "big", "--byte-order", "big"}, "0x1122  0x3344"},
        {{"--word-order", "little", "--byte-order", "big"}, "0x3344  0x1122"},
        {{"--word-order", "big", "--byte-order", "little"}, "0x2211  0x4433"},
        {{"--word-order", "little", "--byte-order", "little"}, "0x4433  0x2211"},
    };
    for (const auto& [order, raw] : cases) {
        std::vector<std::string> args = {"registers", "200", "0x11223344", "--type", "u32"};
        args.insert(args.end(), order.begin(), order.end());
        ASSERT_EQ(mblab("write", args).status, 0);
        auto read = mblab("read", {"holding", "200", "2", "--type", "hex"});
        const auto first = raw.substr(0, 6);
        const auto second = raw.substr(8);
        EXPECT_EQ(read.out, "address       raw     hex\n200 (0x00C8)  " + first + "  " + first +
                                "\n201 (0x00C9)  " + second + "  " + second + "\n");
    }
}

TEST_F(ClientReadWrite, SignedAsciiAndDoubleValues) {
    struct Case {
        std::vector<std::string> write;  // after "registers"
        std::vector<std::string> read;   // after "holding"
        std::string table;
    };
    const std::vector<Case> cases = {
        {{"10", "-2", "32767", "--type", "i16"},
         {"10", "2", "--type", "i16"},
         "address      raw     i16\n"
         "10 (0x000A)  0xFFFE  -2\n"
         "11 (0x000B)  0x7FFF  32767\n"},
        {{"20", "mblab", "--type", "ascii"},
         {"20", "3", "--type", "ascii"},
         "address      raw     ascii\n"
         "20 (0x0014)  0x6D62  \"mb\"\n"
         "21 (0x0015)  0x6C61  \"la\"\n"
         "22 (0x0016)  0x6200  \"b\\x00\"\n"
         "\"mblab\"\n"},
        // Bytes that are not text (here Latin-1 and a backslash) are escaped, in the rows and
        // in the whole text; the text once ended the command with a JSON exception.
        {{"24", "0xFC5C"},
         {"24", "1", "--type", "ascii"},
         "address      raw     ascii\n"
         "24 (0x0018)  0xFC5C  \"\\xFC\\\\\"\n"
         "\"\\xFC\\\\\"\n"},
        {{"30", "-0.125", "--type", "f64"},
         {"30", "1", "--type", "f64"},
         "address      raw                          f64\n"
         "30 (0x001E)  0xBFC0 0x0000 0x0000 0x0000  -0.125\n"},
    };
    for (const auto& c : cases) {
        auto write = c.write;
        write.insert(write.begin(), "registers");
        ASSERT_EQ(mblab("write", write).status, 0);
        auto read = c.read;
        read.insert(read.begin(), "holding");
        EXPECT_EQ(mblab("read", read).out, c.table);
    }
}

TEST_F(ClientReadWrite, CoilsAndSingleWrites) {
    auto wrote = mblab("write", {"coils", "0x10", "1", "0", "on", "true"});
    EXPECT_EQ(wrote.out, "wrote 4 coils at 16 (0x0010)\n");
    EXPECT_EQ(mblab("write", {"coil", "21", "on"}).out, "wrote coil 21 (0x0015): on\n");
    EXPECT_EQ(mblab("read", {"coils", "16", "6"}).out,
              "address      raw  value\n"
              "16 (0x0010)  1    on\n"
              "17 (0x0011)  0    off\n"
              "18 (0x0012)  1    on\n"
              "19 (0x0013)  1    on\n"
              "20 (0x0014)  0    off\n"
              "21 (0x0015)  1    on\n");
    EXPECT_EQ(mblab("write", {"register", "40", "0xBEEF"}).out,
              "wrote register 40 (0x0028): 0xBEEF (48879)\n");
    EXPECT_EQ(mblab("read", {"holding", "40", "--type", "hex"}).out,
              "address      raw     hex\n40 (0x0028)  0xBEEF  0xBEEF\n");
}

TEST_F(ClientReadWrite, MaskWriteFollowsTheFormulaOfTheSpecification) {
    // [APP] 6.16's example: 0x0012 AND 0x00F2 OR 0x0025 gives 0x0017.
    ASSERT_EQ(mblab("write", {"register", "4", "0x12"}).status, 0);
    EXPECT_EQ(mblab("write", {"mask", "4", "0x00F2", "0x0025"}).out,
              "masked register 4 (0x0004): and 0x00F2, or 0x0025\n");
    EXPECT_EQ(mblab("read", {"holding", "4", "--type", "hex"}).out,
              "address     raw     hex\n4 (0x0004)  0x0017  0x0017\n");
}

TEST_F(ClientReadWrite, ReadWriteWritesFirstThenReads) {
    auto ran = mblab("write", {"readwrite", "50", "2", "50", "7", "8"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.out,
              "wrote 2 registers at 50 (0x0032), then read:\n"
              "address      raw     u16\n"
              "50 (0x0032)  0x0007  7\n"
              "51 (0x0033)  0x0008  8\n");
}

TEST_F(ClientReadWrite, FileRecordsRoundTrip) {
    auto wrote = mblab("write", {"file", "1", "3", "10", "-1", "--type", "i16"});
    EXPECT_EQ(wrote.out, "wrote 2 registers to file 1 from record 3\n");
    EXPECT_EQ(mblab("read", {"file", "1", "3", "2", "--type", "i16"}).out,
              "address   raw     i16\n"
              "record 3  0x000A  10\n"
              "record 4  0xFFFF  -1\n");
}

TEST_F(ClientReadWrite, JsonIsOneDocument) {
    ASSERT_EQ(mblab("write", {"registers", "60", "1", "2"}).status, 0);
    auto ran = mblab("read", {"holding", "60", "2", "--json", "--unit", "1"});
    EXPECT_EQ(ran.status, 0);
    auto document = nlohmann::json::parse(ran.out);
    EXPECT_EQ(document["ok"], true);
    EXPECT_EQ(document["command"], "read");
    EXPECT_EQ(document["target"], target());
    EXPECT_EQ(document["unit"], 1);
    EXPECT_EQ(document["type"], "u16");
    EXPECT_EQ(document["values"], nlohmann::json::parse(R"([{"address":60,"raw":[1],"value":1},
                                        {"address":61,"raw":[2],"value":2}])"));
}

TEST_F(ClientReadWrite, OtherReadFunctions) {
    auto status = mblab("read", {"exception-status"});
    EXPECT_EQ(status.out,
              "field             raw   value\n"
              "exception status  0x00  outputs 0..7: 0 0 0 0 0 0 0 0\n");
    auto counter = mblab("read", {"event-counter", "--json"});
    auto document = nlohmann::json::parse(counter.out);
    EXPECT_EQ(document["status"], 0);
    EXPECT_TRUE(document["event count"].is_number());
    auto server_id = mblab("read", {"server-id"});
    EXPECT_EQ(server_id.status, 0);
    EXPECT_THAT(server_id.out, HasSubstr("server id data  6D 62 6C 61 62 FF"));
    auto log = mblab("read", {"event-log"});
    EXPECT_EQ(log.status, 0);
    EXPECT_THAT(log.out, HasSubstr("message count"));
}

}  // namespace
}  // namespace mblab::test
