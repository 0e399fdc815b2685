// What a client or a web page can send to `mblab serve --http`, from the attack run that found
// one GET ending the process: every request is answered or refused in one line, the process and
// its Modbus side go on, a page on another site cannot change the device, and slow or oversized
// requests cost a bounded amount.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "blocking_client.hpp"
#include "http_serve.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

std::uint16_t port_of(const std::string& url) {
    return static_cast<std::uint16_t>(std::stoi(url.substr(url.rfind(':') + 1)));
}

// The process's resident memory in KiB (VmRSS), or -1.
long resident_kib(pid_t pid) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    return -1;
}

std::string text_of(const std::vector<std::uint8_t>& bytes) {
    return {bytes.begin(), bytes.end()};
}

// Serve still answers over Modbus and HTTP.
void expect_alive(HttpServe& serve) {
    EXPECT_FALSE(serve.child().wait_exit(0ms)) << "serve ended";
    EXPECT_EQ(run_mblab({"read", serve.modbus(), "holding", "0"}).status, 0);
    const auto metrics = curl({"-m", "10", serve.http() + "/metrics"});
    EXPECT_EQ(metrics.out.substr(metrics.out.size() - 4), "200\n");
}

TEST(HttpHardening, NoRequestEndsServe) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    HttpServe serve({});
    ASSERT_FALSE(serve.http().empty());
    EXPECT_EQ(curl({serve.http() + "/%FF"}).out,
              "{\"error\":\"no such resource: GET /\xef\xbf\xbd\"}\n404\n");
    const auto events = run_program(
        {"/usr/bin/curl", "-s", "-N", "-m", "1", serve.http() + "/api/events?unit=%FF&bank=%FE"});
    EXPECT_EQ(events.out.rfind("data: {", 0), 0U) << events.out;
    EXPECT_EQ(change(serve, "PUT", "/api/units/1/holding_registers/%FF", "{}").out,
              "{\"error\":\"\xef\xbf\xbd: expected an address from 0 to 65535\"}\n400\n");
    for (const std::string& bytes : std::vector<std::string>{
             "GET /\xff\xfe HTTP/1.1\r\nHost: \xff\r\n\r\n", "\xff\xff\xff\r\n\r\n",
             "GET / HTTP/9.9\r\n\r\n", "GET /a%zz HTTP/1.1\r\nHost: localhost\r\n\r\n",
             std::string("GET / HTTP/1.1\r\nX: \0\r\n\r\n", 24)}) {
        BlockingClient client(port_of(serve.http()));
        ASSERT_TRUE(client.connected());
        client.send(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
        const auto answer = text_of(client.read(4096, 5s));
        EXPECT_EQ(answer.rfind("HTTP/1.1 4", 0) == 0 || answer.rfind("HTTP/1.1 5", 0) == 0, true)
            << answer;
    }
    expect_alive(serve);
}

TEST(HttpHardening, APageOnAnotherSiteCannotChangeTheDevice) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    // Without a token, the weakest setting: Host, Origin and the JSON rule still hold.
    HttpServe serve({"--http-no-token"});
    const auto faults = serve.http() + "/api/units/1/faults";
    const std::string rule = R"({"action":"exception","exception":6,"functions":[3]})";
    // A cross-site form or text/plain POST: what a page sends without the browser asking.
    auto text = curl({"-X", "POST", "-H", "Origin: http://evil.example", "-H",
                      "Content-Type: text/plain", "-d", rule, faults});
    EXPECT_EQ(text.out.substr(text.out.size() - 4), "403\n") << text.out;
    auto form = curl({"-X", "POST", "-d", rule, faults});
    EXPECT_EQ(form.out.substr(form.out.size() - 4), "415\n") << form.out;
    auto json_from_elsewhere = curl({"-X", "POST", "-H", "Sec-Fetch-Site: cross-site", "-H",
                                     "Content-Type: application/json", "-d", rule, faults});
    EXPECT_EQ(json_from_elsewhere.out.substr(json_from_elsewhere.out.size() - 4), "403\n");
    // DNS rebinding: the page's own name, now pointing at 127.0.0.1, in the Host header.
    const auto port = std::to_string(port_of(serve.http()));
    auto rebound = curl({"-X", "PUT", "-H", "Host: attacker.example:" + port, "-H",
                         "Content-Type: application/json", "-d", R"({"values":[1]})",
                         serve.http() + "/api/units/1/holding_registers/0"});
    EXPECT_EQ(rebound.out.substr(rebound.out.size() - 4), "403\n");
    auto read = curl({"-H", "Host: attacker.example:" + port, serve.http() + "/api/units"});
    EXPECT_EQ(read.out.substr(read.out.size() - 4), "403\n");
    // Nothing changed: no rule, the register as the profile has it.
    EXPECT_EQ(curl({faults}).out, "[]\n200\n");
    EXPECT_EQ(run_mblab({"read", serve.modbus(), "holding", "0"}).status, 0);
    // The page's own origin may.
    auto own = curl({"-X", "POST", "-H", "Origin: " + serve.http(), "-H",
                     "Content-Type: application/json", "-d", rule, faults});
    EXPECT_EQ(own.out.substr(own.out.size() - 4), "201\n") << own.out;
}

TEST(HttpHardening, ChangesNeedTheTokenServeMadeByDefault) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    HttpServe serve({});
    ASSERT_EQ(serve.token().size(), 32U);
    auto bare = curl({"-X", "POST", "-H", "Content-Type: application/json",
                      serve.http() + "/api/counters/reset"});
    EXPECT_EQ(bare.out.substr(bare.out.size() - 4), "401\n");
    auto taken = change(serve, "POST", "/api/counters/reset", "");
    EXPECT_EQ(taken.out.substr(taken.out.size() - 4), "200\n") << taken.out;
}

TEST(HttpHardening, EveryAnswerForbidsFramingAndForeignScript) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    HttpServe serve({});
    for (const std::string path : {"/", "/api/units", "/nothing", "/metrics"}) {
        const auto head =
            run_program({"/usr/bin/curl", "-s", "-D", "-", "-o", "/dev/null", serve.http() + path});
        EXPECT_THAT(head.out, HasSubstr("X-Frame-Options: DENY\r\n")) << path;
        EXPECT_THAT(head.out, HasSubstr("frame-ancestors 'none'")) << path;
        EXPECT_THAT(head.out, HasSubstr("script-src 'self';")) << path;
    }
}

TEST(HttpHardening, ChunkedHugeAndDeepBodiesCostABoundedAmount) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    HttpServe serve({});
    const auto before = resident_kib(serve.child().pid());
    {
        // Chunked: refused on its head, before a byte of the body is kept.
        BlockingClient client(port_of(serve.http()));
        const std::string head = "POST /api/units/1/faults HTTP/1.1\r\nHost: 127.0.0.1:" +
                                 std::to_string(port_of(serve.http())) +
                                 "\r\nAuthorization: Bearer " + serve.token() +
                                 "\r\nContent-Type: application/json\r\n"
                                 "Transfer-Encoding: chunked\r\n\r\n";
        client.send(std::span(reinterpret_cast<const std::uint8_t*>(head.data()), head.size()));
        const std::string chunk = "100000\r\n" + std::string(0x100000, '[') + "\r\n";
        for (int i = 0; i < 64; ++i) {
            if (!client.send(
                    std::span(reinterpret_cast<const std::uint8_t*>(chunk.data()), chunk.size()))) {
                break;
            }
        }
        const auto answer = text_of(client.read(4096, 5s));
        EXPECT_EQ(answer.rfind("HTTP/1.1 411 ", 0), 0U) << answer;
    }
    const auto huge = curl({"-X", "PUT", "-H", "Authorization: Bearer " + serve.token(), "-H",
                            "Content-Type: application/json", "-H", "Content-Length: 400000000",
                            serve.http() + "/api/units/1/coils/0"});
    EXPECT_EQ(huge.out.substr(huge.out.size() - 4), "413\n") << huge.out;
    // Past what one argument of curl may hold: the body goes from a file.
    const std::string file = ::testing::TempDir() + "mblab-deep.json";
    std::ofstream(file) << std::string(1000000, '[');
    const auto deep = change(serve, "PUT", "/api/units/1/coils/0", "@" + file);
    EXPECT_EQ(deep.out,
              "{\"error\":\"the body nests arrays or objects deeper than 32 levels\"}\n400\n");
    const auto after = resident_kib(serve.child().pid());
    // A megabyte body may be held while it is read; tens of megabytes would be the old cost.
    EXPECT_LT(after - before, 16 * 1024) << before << " KiB before, " << after << " after";
    expect_alive(serve);
}

TEST(HttpHardening, SlowClientsDoNotKeepAScrapeOut) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    HttpServe serve({});
    std::vector<BlockingClient> slow;
    const std::string start = "GET /metrics HTTP/1.1\r\nHost: 127.0";
    for (int i = 0; i < 200; ++i) {
        slow.emplace_back(port_of(serve.http()));
        slow.back().send(
            std::span(reinterpret_cast<const std::uint8_t*>(start.data()), start.size()));
    }
    for (int round = 0; round < 3; ++round) {
        const auto scrape = curl({"-m", "10", serve.http() + "/metrics"});
        EXPECT_EQ(scrape.out.substr(scrape.out.size() - 4), "200\n") << scrape.out;
        for (auto& client : slow) {
            const std::uint8_t dot = '.';
            client.send(std::span(&dot, 1));
        }
    }
    expect_alive(serve);
}

TEST(HttpHardening, PipelinedRequestsAreAnsweredInOrder) {
    HttpServe serve({});
    BlockingClient client(port_of(serve.http()));
    const std::string host = "Host: 127.0.0.1:" + std::to_string(port_of(serve.http())) + "\r\n";
    const std::string requests =
        "GET /api/units/1/coils?count=1 HTTP/1.1\r\n" + host + "\r\nGET /nothing HTTP/1.1\r\n" +
        host + "\r\nGET /api/counters HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n";
    client.send(std::span(reinterpret_cast<const std::uint8_t*>(requests.data()), requests.size()));
    std::string answers;
    while (true) {
        const auto got = client.read(65536, 5s);
        if (got.empty()) break;
        answers += text_of(got);
    }
    const auto first = answers.find("HTTP/1.1 200 OK");
    const auto second = answers.find("HTTP/1.1 404 Not Found");
    const auto third = answers.find("HTTP/1.1 200 OK", second == std::string::npos ? 0 : second);
    EXPECT_EQ(first, 0U) << answers;
    EXPECT_NE(second, std::string::npos) << answers;
    EXPECT_NE(third, std::string::npos) << answers;
    EXPECT_THAT(answers, HasSubstr("Connection: close"));
}

TEST(HttpHardening, ARangeOfAThousandPartsIsAnsweredWhole) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    HttpServe serve({});
    std::string ranges = "Range: bytes=0-0";
    for (int i = 1; i < 1000; ++i)
        ranges += "," + std::to_string(i) + "-" + std::to_string(i);
    const auto plain =
        curl({"-o", "/dev/null", "-w", "%{http_code} %{size_download}\n", serve.http() + "/"});
    const auto ranged = curl({"-H", ranges, "-o", "/dev/null", "-w",
                              "%{http_code} %{size_download}\n", serve.http() + "/"});
    EXPECT_EQ(ranged.out, plain.out);
    EXPECT_EQ(ranged.out.rfind("200 ", 0), 0U) << ranged.out;
}

}  // namespace
}  // namespace mblab::test
