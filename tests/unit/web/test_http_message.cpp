// The HTTP request head as bytes in, a request or a refusal out (web/http_message.hpp).
#include <gtest/gtest.h>

#include <string>

#include "web/http_message.hpp"

namespace mblab::web {
namespace {

using Kind = HeadResult::Kind;

TEST(HttpHead, ARequestWithItsHeadersQueryAndLength) {
    const std::string bytes =
        "PUT /api/units/1/coils/0?start=3&name=a%20b+c HTTP/1.1\r\nHost: 127.0.0.1:8080\r\n"
        "Content-Type:  application/json \r\nContent-Length: 5\r\n\r\n{\"a\"}";
    const auto head = parse_head(bytes);
    ASSERT_EQ(head.kind, Kind::Request) << head.reason;
    EXPECT_EQ(head.used, bytes.size() - 5);
    EXPECT_EQ(head.request.method, "PUT");
    EXPECT_EQ(head.request.path, "/api/units/1/coils/0");
    EXPECT_EQ(head.request.query.at("start"), "3");
    EXPECT_EQ(head.request.query.at("name"), "a b c");
    EXPECT_EQ(*head.request.header("content-type"), "application/json");
    EXPECT_EQ(head.request.body_length, 5U);
    EXPECT_TRUE(head.request.keep_alive);
}

TEST(HttpHead, NeedsTheBlankLineAndTakesBareLineFeeds) {
    EXPECT_EQ(parse_head("GET / HTTP/1.1\r\nHost: a\r\n").kind, Kind::NeedMore);
    const auto head = parse_head("GET /x HTTP/1.0\nHost: a\n\nGET /y");
    ASSERT_EQ(head.kind, Kind::Request);
    EXPECT_EQ(head.used, std::string("GET /x HTTP/1.0\nHost: a\n\n").size());
    EXPECT_FALSE(head.request.keep_alive);  // HTTP/1.0 without keep-alive
}

TEST(HttpHead, APathOfInvalidUtf8IsKeptAsBytesForTheHandlerToEscape) {
    const auto head = parse_head("GET /%FF%fe HTTP/1.1\r\nHost: a\r\n\r\n");
    ASSERT_EQ(head.kind, Kind::Request);
    EXPECT_EQ(head.request.path, "/\xff\xfe");
}

struct Refusal {
    const char* bytes;
    int status;
};

class HttpHeadRefused : public ::testing::TestWithParam<Refusal> {};

TEST_P(HttpHeadRefused, WithItsStatus) {
    const auto head = parse_head(GetParam().bytes);
    ASSERT_EQ(head.kind, Kind::Refused) << GetParam().bytes;
    EXPECT_EQ(head.status, GetParam().status) << head.reason;
    EXPECT_FALSE(head.reason.empty());
}

INSTANTIATE_TEST_SUITE_P(
    BadHeads, HttpHeadRefused,
    ::testing::Values(
        Refusal{"POST / HTTP/1.1\r\nHost: a\r\nTransfer-Encoding: chunked\r\n\r\n", 411},
        Refusal{"POST / HTTP/1.1\r\nHost: a\r\nContent-Length: 1048577\r\n\r\n", 413},
        Refusal{"POST / HTTP/1.1\r\nHost: a\r\nContent-Length: 99999999999999999999999\r\n\r\n",
                413},
        Refusal{"POST / HTTP/1.1\r\nHost: a\r\nContent-Length: 1\r\nContent-Length: 2\r\n\r\n",
                400},
        Refusal{"POST / HTTP/1.1\r\nHost: a\r\nContent-Length: -1\r\n\r\n", 400},
        Refusal{"GET /%zz HTTP/1.1\r\nHost: a\r\n\r\n", 400},
        Refusal{"GET /a%00b HTTP/1.1\r\nHost: a\r\n\r\n", 400},
        Refusal{"GET /a?b=%4 HTTP/1.1\r\nHost: a\r\n\r\n", 400},
        Refusal{"GET http://a/ HTTP/1.1\r\nHost: a\r\n\r\n", 400},
        Refusal{"GET / HTTP/2.0\r\nHost: a\r\n\r\n", 505},
        Refusal{"GET / HTTP/1.1 extra\r\nHost: a\r\n\r\n", 400},
        Refusal{"GET / HTTP/1.1\r\nHost: a\r\n folded\r\n\r\n", 400},
        Refusal{"GET / HTTP/1.1\r\nHost : a\r\n\r\n", 400},
        Refusal{"GET / HTTP/1.1\r\nX: a\x01b\r\n\r\n", 400},
        Refusal{"GET / HTTP/1.1\r\nExpect: 200-ok\r\n\r\n", 417},
        Refusal{"G(T / HTTP/1.1\r\n\r\n", 400}));

TEST(HttpHead, AHeadPastTheLimitIsRefusedWithoutItsEnd) {
    std::string bytes = "GET / HTTP/1.1\r\nX: " + std::string(kMaxHead, 'a');
    const auto head = parse_head(bytes);
    ASSERT_EQ(head.kind, Kind::Refused);
    EXPECT_EQ(head.status, 431);
    std::string many = "GET / HTTP/1.1\r\n";
    for (int i = 0; i < 101; ++i)
        many += "X: 1\r\n";
    EXPECT_EQ(parse_head(many + "\r\n").status, 431);
}

TEST(HttpReplyText, CarriesLengthConnectionAndTheSecurityHeaders) {
    const auto text = write_reply({404, "{}", "application/json"}, false, false);
    EXPECT_EQ(text.rfind("HTTP/1.1 404 Not Found\r\nContent-Type: application/json\r\n"
                         "Content-Length: 2\r\nConnection: close\r\n",
                         0),
              0U);
    EXPECT_NE(text.find("X-Frame-Options: DENY\r\n"), std::string::npos);
    EXPECT_NE(text.find("frame-ancestors 'none'"), std::string::npos);
    EXPECT_NE(text.find("X-Content-Type-Options: nosniff\r\n"), std::string::npos);
    EXPECT_EQ(text.substr(text.size() - 6), "\r\n\r\n{}");
    const auto head_only = write_reply({200, "abc", "text/plain"}, true, true);
    EXPECT_NE(head_only.find("Content-Length: 3\r\n"), std::string::npos);
    EXPECT_EQ(head_only.substr(head_only.size() - 4), "\r\n\r\n");
}

}  // namespace
}  // namespace mblab::web
