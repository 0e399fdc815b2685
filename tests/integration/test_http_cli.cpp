// `mblab serve --http` and `mblab load --metrics` as processes, driven with curl and read back
// over Modbus with the mblab client; metrics checked by promtool (Debian's prometheus package).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "http_serve.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

TEST(ServeHttp, AValueWrittenOverRestIsReadOverModbusAndBack) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    HttpServe serve({});
    ASSERT_FALSE(serve.http().empty());
    auto put = change(serve, "PUT", "/api/units/1/holding_registers/10", R"({"values":[4660,7]})");
    EXPECT_EQ(put.out,
              "{\"bank\":\"holding_registers\",\"start\":10,\"unit\":1,\"written\":2}\n200\n");
    auto read = run_mblab({"read", serve.modbus(), "holding", "10", "2"});
    EXPECT_EQ(read.status, 0) << read.err;
    EXPECT_THAT(read.out, HasSubstr("10 (0x000A)  0x1234  4660"));
    EXPECT_THAT(read.out, HasSubstr("11 (0x000B)  0x0007  7"));

    EXPECT_EQ(run_mblab({"write", serve.modbus(), "register", "12", "99"}).status, 0);
    auto get = curl({serve.http() + "/api/units/1/holding_registers?start=10&count=3"});
    EXPECT_EQ(
        get.out,
        "{\"bank\":\"holding_registers\",\"start\":10,\"unit\":1,\"values\":[4660,7,99]}\n200\n");
}

TEST(ServeHttp, AFaultRuleAddedOverRestAnswersModbus) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    HttpServe serve({});
    auto post = change(serve, "POST", "/api/units/1/faults",
                       R"({"action":"exception","exception":4,"functions":[3]})");
    EXPECT_EQ(post.out.substr(post.out.size() - 4), "201\n") << post.out;
    auto read = run_mblab({"read", serve.modbus(), "holding", "0"});
    EXPECT_EQ(read.status, 1);
    EXPECT_THAT(read.err, HasSubstr("exception 04"));
    change(serve, "PUT", "/api/units/1/faults/0",
           R"({"action":"exception","exception":4,"functions":[3],"enabled":false})");
    EXPECT_EQ(run_mblab({"read", serve.modbus(), "holding", "0"}).status, 0);
}

TEST(ServeHttp, BadRequestsGet4xxWithOneLineReasons) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    HttpServe serve({});
    EXPECT_EQ(change(serve, "PUT", "/api/units/1/coils/0", "{nope").out,
              "{\"error\":\"the body is not valid JSON\"}\n400\n");
    EXPECT_EQ(curl({serve.http() + "/api/units/7/coils"}).out,
              "{\"error\":\"unit 7: no such unit (units: 1)\"}\n404\n");
    EXPECT_EQ(curl({serve.http() + "/api/units/1/coils?start=70000"}).out,
              "{\"error\":\"start: expected an address from 0 to 65535\"}\n400\n");
    EXPECT_EQ(curl({"-X", "POST", "-H", "Authorization: Bearer " + serve.token(),
                    serve.http() + "/api/counters/reset"})
                  .out,
              "{\"error\":\"POST takes a body of Content-Type: application/json (with curl: -H "
              "'Content-Type: application/json')\"}\n415\n");
    EXPECT_EQ(curl({serve.http() + "/nothing"}).out,
              "{\"error\":\"no such resource: GET /nothing\"}\n404\n");
    EXPECT_EQ(curl({serve.http() + "/%FF"}).out,
              "{\"error\":\"no such resource: GET /\xef\xbf\xbd\"}\n404\n");
    // The server still serves after them.
    EXPECT_EQ(run_mblab({"read", serve.modbus(), "coils", "0"}).status, 0);
}

TEST(ServeHttp, MetricsCountModbusRequestsAndPassPromtool) {
    if (!have("/usr/bin/curl") || !have("/usr/bin/promtool")) GTEST_SKIP() << "no curl/promtool";
    HttpServe serve({});
    run_mblab({"read", serve.modbus(), "holding", "0", "3"});
    run_mblab({"read", serve.modbus(), "holding", "70000"});  // refused by the client itself
    auto metrics = curl({serve.http() + "/metrics"});
    EXPECT_THAT(metrics.out, HasSubstr("mblab_requests_total{unit=\"1\",function=\"0x03\"} 1\n"));
    EXPECT_THAT(metrics.out, HasSubstr("mblab_request_duration_seconds_count 1\n"));
    auto lint =
        run_program({"/bin/sh", "-c",
                     "/usr/bin/curl -sf " + serve.http() + "/metrics | promtool check metrics"});
    EXPECT_EQ(lint.status, 0) << lint.out << lint.err;
}

TEST(ServeHttp, EventStreamAndASelfContainedDashboard) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    HttpServe serve({});
    auto events =
        run_program({"/usr/bin/curl", "-s", "-N", "-m", "1",
                     serve.http() + "/api/events?unit=1&bank=holding_registers&start=0&count=2"});
    EXPECT_EQ(events.out.rfind("data: {\"counters\":", 0), 0U) << events.out;
    EXPECT_THAT(events.out,
                HasSubstr("\"page\":{\"bank\":\"holding_registers\",\"start\":0,\"unit\":1,"
                          "\"values\":[21317,19785]}"));
    auto page = curl({serve.http() + "/"});
    EXPECT_EQ(page.out.rfind("<!DOCTYPE html>", 0), 0U);
    EXPECT_EQ(page.out.find("http://"), std::string::npos) << "the page fetches nothing else";
    EXPECT_EQ(page.out.find("https://"), std::string::npos);
}

TEST(ServeHttp, ATokenGuardsWritesButNotReads) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    HttpServe serve({"--http-token", "s3cret"});
    const auto url = serve.http() + "/api/units/1/coils/0";
    const std::string json = "Content-Type: application/json";
    auto refused = curl({"-X", "PUT", "-H", json, "-d", R"({"values":[1]})", url});
    EXPECT_EQ(refused.out.substr(refused.out.size() - 4), "401\n");
    auto wrong = curl({"-X", "PUT", "-H", json, "-H", "Authorization: Bearer nope", "-d",
                       R"({"values":[1]})", url});
    EXPECT_EQ(wrong.out.substr(wrong.out.size() - 4), "401\n");
    auto taken = curl({"-X", "PUT", "-H", json, "-H", "Authorization: Bearer s3cret", "-d",
                       R"({"values":[1]})", url});
    EXPECT_EQ(taken.out.substr(taken.out.size() - 4), "200\n");
    EXPECT_EQ(curl({serve.http() + "/api/units/1/coils?count=1"}).out,
              "{\"bank\":\"coils\",\"start\":0,\"unit\":1,\"values\":[1]}\n200\n");
}

TEST(ServeHttp, RefusesAnOpenAddressWithoutAToken) {
    auto ran = run_mblab(
        {"serve", "--listen", "tcp://127.0.0.1:0", "--http", "0.0.0.0:0", "--http-no-token"});
    expect_failed(ran, 2,
                  "mblab serve: --http 0.0.0.0:0: not a loopback address, so changes need a token "
                  "(--http-no-token is for loopback only)\n");
    ran = run_mblab({"serve", "--http", "127.0.0.1:0", "--http-token", "a", "--http-no-token"});
    expect_failed(ran, 2,
                  "mblab serve: give one of --http-token, --http-token-file and --http-no-token\n");
    ran = run_mblab({"serve", "--http", "localhost"});
    expect_failed(
        ran, 2,
        "mblab serve: --http 'localhost': expected HOST:PORT, e.g. 127.0.0.1:8080 (port 0: "
        "any free port)\n");
    ran = run_mblab({"serve", "--http", "127.0.0.1:0", "--devices", "2"});
    EXPECT_EQ(ran.err, "mblab serve: --http shows one device: not with --gateway or --devices\n");
}

// docs/http.md's curl examples, as printed, against a server on another port: each answered 2xx.
TEST(ServeHttp, TheGuidesExamplesWork) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    HttpServe serve({"--http-token", "s3cret"});
    std::ifstream guide(std::string(MBLAB_SOURCE_DIR) + "/docs/http.md");
    std::string line;
    int examples = 0;
    while (std::getline(guide, line)) {
        if (line.rfind("curl ", 0) != 0) continue;
        ++examples;
        const auto at = line.find("http://127.0.0.1:8080");
        ASSERT_NE(at, std::string::npos) << line;
        line.replace(at, std::string("http://127.0.0.1:8080").size(), serve.http());
        auto ran = run_program({"/bin/sh", "-c", line + " -o /dev/null -w '%{http_code}\\n'"});
        EXPECT_EQ(ran.status, 0) << line;
        EXPECT_EQ(ran.out.substr(0, 1), "2") << line << " answered " << ran.out;
    }
    EXPECT_EQ(examples, 8);
}

TEST(LoadMetrics, ServedWhileTheRunGoesAndPassPromtool) {
    if (!have("/usr/bin/curl") || !have("/usr/bin/promtool")) GTEST_SKIP() << "no curl/promtool";
    HttpServe serve({});
    ChildProcess load({MBLAB_BINARY, "load", serve.modbus(), "--no-tests", "--connections", "2",
                       "--duration", "20s", "--metrics", "127.0.0.1:0"});
    std::smatch match;
    auto line = load.read_stdout_line(10s).value_or("");
    ASSERT_TRUE(std::regex_search(line, match, std::regex("http://127\\.0\\.0\\.1:[0-9]+/metrics")))
        << line;
    const std::string url = match[0];
    // The first status comes a second into the run; until then the counts are 0.
    std::string text;
    for (int tries = 0; tries < 50; ++tries) {
        text = curl({url}).out;
        if (text.find("mblab_load_answers_total{target=\"" + serve.modbus() + "\"} 0\n") ==
                std::string::npos &&
            text.find("mblab_load_answers_total{") != std::string::npos) {
            break;
        }
        ::usleep(100000);
    }
    EXPECT_NE(text.find("mblab_load_answer_duration_seconds_count{target=\"" + serve.modbus()),
              std::string::npos)
        << text;
    EXPECT_EQ(text.find("mblab_load_answers_total{target=\"" + serve.modbus() + "\"} 0\n"),
              std::string::npos)
        << text;
    auto lint =
        run_program({"/bin/sh", "-c", "/usr/bin/curl -sf " + url + " | promtool check metrics"});
    EXPECT_EQ(lint.status, 0) << lint.out << lint.err;
    load.signal(SIGINT);
    EXPECT_TRUE(load.wait_exit(10s).has_value());
}

}  // namespace
}  // namespace mblab::test
