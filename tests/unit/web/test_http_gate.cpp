// Who may talk to the HTTP side, decided on a request's head (web/http_gate.hpp).
#include <gtest/gtest.h>

#include <string>

#include "web/http_gate.hpp"
#include "web/json_text.hpp"

namespace mblab::web {
namespace {

HttpRequest head(std::string text) {
    auto parsed = parse_head(text + "\r\n");
    EXPECT_EQ(parsed.kind, HeadResult::Kind::Request) << parsed.reason;
    return parsed.request;
}

int status(const HttpGate& gate, const std::string& text) {
    const auto refusal = gate.check(head(text));
    return refusal ? refusal->status : 0;
}

const HttpGate kLoopback({"s3cret", "127.0.0.1", 8080, {"plc-01.plant.lan"}});

TEST(HttpGate, TakesTheBoundAddressLoopbackNamesAndDeclaredNamesWithThePort) {
    for (const char* host : {"127.0.0.1:8080", "localhost:8080", "LOCALHOST.:8080", "[::1]:8080",
                             "127.0.0.2:8080", "ip6-localhost:8080", "plc-01.plant.lan:8080"}) {
        EXPECT_EQ(status(kLoopback, std::string("GET / HTTP/1.1\r\nHost: ") + host + "\r\n"), 0)
            << host;
    }
}

TEST(HttpGate, RefusesAReboundNameAnotherPortOrNoHost) {
    for (const char* host : {"evil.example:8080", "127.0.0.1.evil.example:8080", "127.0.0.1:8081",
                             "localhost", "[::1", "10.0.0.1:8080", "0.0.0.0:8080"}) {
        EXPECT_EQ(status(kLoopback, std::string("GET / HTTP/1.1\r\nHost: ") + host + "\r\n"), 403)
            << host;
    }
    EXPECT_EQ(status(kLoopback, "GET / HTTP/1.1\r\n"), 400);
}

TEST(HttpGate, OnAWildcardAddressAnyAddressLiteralButNoName) {
    const HttpGate open({"t", "0.0.0.0", 80, {}});
    EXPECT_EQ(status(open, "GET / HTTP/1.1\r\nHost: 192.0.2.7\r\n"), 0);
    EXPECT_EQ(status(open, "GET / HTTP/1.1\r\nHost: attacker.example\r\n"), 403);
}

TEST(HttpGate, AMetricsOnlyServerTakesAnyHostButNoChange) {
    const HttpGate metrics({"", "0.0.0.0", 9100, {}, true});
    EXPECT_EQ(status(metrics, "GET /metrics HTTP/1.1\r\nHost: labhost.plant.lan:9100\r\n"), 0);
    EXPECT_EQ(status(metrics,
                     "PUT /metrics HTTP/1.1\r\nHost: labhost:9100\r\n"
                     "Origin: http://evil.example\r\n"),
              403);
}

constexpr const char* kChange =
    "PUT /api/units/1/coils/0 HTTP/1.1\r\nHost: 127.0.0.1:8080\r\nContent-Length: 2\r\n";

TEST(HttpGate, AChangeNeedsTheTokenAndJson) {
    const std::string change(kChange);
    EXPECT_EQ(status(kLoopback, change + "Content-Type: application/json\r\n"), 401);
    EXPECT_EQ(status(kLoopback, change + "Content-Type: application/json\r\n"
                                         "Authorization: Bearer s3cre\r\n"),
              401);
    EXPECT_EQ(status(kLoopback, change + "Authorization: Bearer s3cret\r\n"), 415);
    EXPECT_EQ(status(kLoopback, change + "Authorization: Bearer s3cret\r\n"
                                         "Content-Type: text/plain\r\n"),
              415);
    EXPECT_EQ(status(kLoopback, change + "Authorization: Bearer s3cret\r\n"
                                         "Content-Type: application/x-www-form-urlencoded\r\n"),
              415);
    EXPECT_EQ(status(kLoopback, change + "Authorization: Bearer s3cret\r\n"
                                         "Content-Type: Application/JSON; charset=utf-8\r\n"),
              0);
}

TEST(HttpGate, AChangeFromAnotherOriginOrSiteIsRefusedEvenWithTheToken) {
    const std::string change =
        std::string(kChange) + "Authorization: Bearer s3cret\r\nContent-Type: application/json\r\n";
    EXPECT_EQ(status(kLoopback, change + "Origin: http://evil.example\r\n"), 403);
    EXPECT_EQ(status(kLoopback, change + "Origin: null\r\n"), 403);
    EXPECT_EQ(status(kLoopback, change + "Origin: http://localhost:3000\r\n"), 403);
    EXPECT_EQ(status(kLoopback, change + "Sec-Fetch-Site: same-site\r\n"), 403);
    EXPECT_EQ(status(kLoopback, change + "Origin: http://127.0.0.1:8080\r\n"
                                         "Sec-Fetch-Site: same-origin\r\n"),
              0);
}

TEST(HttpGate, WithoutATokenAChangeStillNeedsJsonAndItsOwnOrigin) {
    const HttpGate open({"", "127.0.0.1", 8080, {}});
    const std::string form =
        "POST /api/counters/reset HTTP/1.1\r\nHost: 127.0.0.1:8080\r\nContent-Length: 0\r\n";
    EXPECT_EQ(status(open, form + "Content-Type: text/plain\r\n"), 415);
    EXPECT_EQ(status(open, form + "Content-Type: application/json\r\n"), 0);
    EXPECT_EQ(status(open, "DELETE /api/units/1/faults/0 HTTP/1.1\r\nHost: 127.0.0.1:8080\r\n"), 0);
    EXPECT_EQ(status(open, "OPTIONS / HTTP/1.1\r\nHost: 127.0.0.1:8080\r\n"), 405);
}

TEST(HttpGate, RefusalsAreOneLineOfJsonEvenForBytesThatAreNotUtf8) {
    const auto refusal = kLoopback.check(head("GET / HTTP/1.1\r\nHost: \xff\xfe:8080\r\n"));
    ASSERT_TRUE(refusal);
    EXPECT_FALSE(nlohmann::json::parse(refusal->body, nullptr, false).is_discarded());
    EXPECT_EQ(refusal->body.find('\n'), std::string::npos);
}

TEST(SameSecret, EqualOnlyForTheSameBytes) {
    EXPECT_TRUE(same_secret("abc", "abc"));
    EXPECT_FALSE(same_secret("abd", "abc"));
    EXPECT_FALSE(same_secret("ab", "abc"));
    EXPECT_FALSE(same_secret("abcd", "abc"));
    EXPECT_FALSE(same_secret("", "abc"));
}

TEST(JsonText, InvalidUtf8IsReplacedNotThrown) {
    EXPECT_EQ(json_text({{"error", "GET /\xff"}}), "{\"error\":\"GET /\xef\xbf\xbd\"}");
}

TEST(JsonBody, NestingPastTheLimitIsRefusedBeforeParsing) {
    std::string error;
    EXPECT_FALSE(parse_json_body(std::string(1 << 20, '['), error));
    EXPECT_EQ(error, "the body nests arrays or objects deeper than 32 levels");
    EXPECT_TRUE(parse_json_body(R"({"a":"[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[["})", error));
    EXPECT_TRUE(parse_json_body(std::string(32, '[') + std::string(32, ']'), error));
    EXPECT_FALSE(parse_json_body("{nope", error));
    EXPECT_EQ(error, "the body is not valid JSON");
}

}  // namespace
}  // namespace mblab::web
