#include <gtest/gtest.h>

#include <chrono>
#include <deque>

#include "client/hex_text.hpp"
#include "conformance/serving_check.hpp"
#include "support/hex.hpp"

// The one "does the device still serve?" check, on a scripted link and a clock that moves only
// when the link is read: what is sent, which answers settle it and how.
namespace mblab::conformance {
namespace {

using namespace std::chrono_literals;
using client::Received;
using client::ReceiveStatus;
using protocol::Framing;
using test::hex;

struct ScriptedLink {
    bool accepts = true;
    std::deque<Received> answers;
    std::vector<std::uint8_t> sent;
    std::chrono::steady_clock::time_point now{};

    bool send(std::span<const std::uint8_t> bytes, client::LinkError& error) {
        sent.assign(bytes.begin(), bytes.end());
        if (!accepts) error.message = "Broken pipe";
        return accepts;
    }
    Received receive_frame(std::chrono::milliseconds timeout) {
        if (answers.empty()) {
            now += timeout;
            return Received(ReceiveStatus::Timeout);
        }
        now += 10ms;
        auto next = std::move(answers.front());
        answers.pop_front();
        return next;
    }
};

Received frame(protocol::AduHeader header, std::vector<std::uint8_t> pdu) {
    Received out(ReceiveStatus::Frame, pdu);
    out.header = header;
    out.pdu = std::move(pdu);
    return out;
}

ServingQuestion question(ScriptedLink& link, protocol::AduHeader header, bool any_answer) {
    return {
        .header = header, .address = 5, .timeout = 100ms, .any_answer = any_answer, .now = [&link] {
            return link.now;
        }};
}

const protocol::AduHeader kMbap{Framing::Mbap, 1, 0x7E57, 0};
const protocol::AduHeader kRtu{Framing::Rtu, 17};

TEST(ServingCheck, SendsTheKnownGoodReadInTheLinksFraming) {
    ScriptedLink link;
    ask_serving(link, question(link, kMbap, false));
    EXPECT_EQ(link.sent, hex("7E 57 00 00 00 06 01 03 00 05 00 01"));
    ask_serving(link, question(link, kRtu, false));
    EXPECT_EQ(link.sent.size(), 8U);  // address, the read, CRC
    EXPECT_EQ(std::vector(link.sent.begin(), link.sent.begin() + 6), hex("11 03 00 05 00 01"));
}

TEST(ServingCheck, TheRegistersPairedDataAnswerServesAndGivesItsValue) {
    ScriptedLink link;
    link.answers.push_back(frame(kMbap, hex("03 02 12 34")));
    const auto answer = ask_serving(link, question(link, kMbap, false));
    EXPECT_EQ(answer.served, Served::Yes);
    EXPECT_EQ(answer.value, 0x1234);
}

TEST(ServingCheck, AnUnpairedOrExceptionAnswerIsWrongWhereRequestsAreNumbered) {
    for (auto answer_frame :
         {frame({Framing::Mbap, 1, 0x7E58, 0}, hex("03 02 12 34")), frame(kMbap, hex("83 02"))}) {
        ScriptedLink link;
        link.answers.push_back(answer_frame);
        const auto answer = ask_serving(link, question(link, kMbap, false));
        EXPECT_EQ(answer.served, Served::Wrong);
        EXPECT_EQ(answer.detail(), client::hex_bytes(answer_frame.bytes));
    }
}

TEST(ServingCheck, OnALineAFrameThatIsNotTheAnswerIsReadPast) {
    ScriptedLink link;
    link.answers.push_back(frame({Framing::Rtu, 18}, hex("03 02 00 00")));
    link.answers.push_back(frame(kRtu, hex("03 02 00 07")));
    const auto answer = ask_serving(link, question(link, kRtu, false));
    EXPECT_EQ(answer.served, Served::Yes);
    EXPECT_EQ(answer.value, 7);
}

TEST(ServingCheck, AFrameReadPastThatUsesUpTheTimeoutIsSilence) {
    ScriptedLink link;
    for (int i = 0; i < 20; ++i)
        link.answers.push_back(frame({Framing::Rtu, 18}, hex("03 02 00 00")));
    EXPECT_EQ(ask_serving(link, question(link, kRtu, false)).served, Served::Silent);
    EXPECT_EQ(link.answers.size(), 10U);  // 10 frames of 10 ms each fill the 100 ms
}

TEST(ServingCheck, AnyAnswerCountsWhenAskedSoAndMalformedBytesDoNot) {
    ScriptedLink link;
    link.answers.push_back(frame({Framing::Mbap, 1, 0x0001, 0}, hex("83 02")));
    EXPECT_EQ(ask_serving(link, question(link, kMbap, true)).served, Served::Yes);
    link.answers.push_back(Received(ReceiveStatus::Malformed, hex("00 01 00 00 00 00"), "len 0"));
    EXPECT_EQ(ask_serving(link, question(link, kMbap, true)).served, Served::Wrong);
}

TEST(ServingCheck, ALinkThatCannotCarryTheReadOrClosesIsClosed) {
    ScriptedLink refusing;
    refusing.accepts = false;
    auto answer = ask_serving(refusing, question(refusing, kMbap, true));
    EXPECT_EQ(answer.served, Served::Closed);
    EXPECT_EQ(answer.detail(), "Broken pipe");
    EXPECT_EQ(answer.exchange(100ms).status, ReceiveStatus::Closed);

    ScriptedLink closing;
    closing.answers.push_back(Received(ReceiveStatus::Closed));
    answer = ask_serving(closing, question(closing, kMbap, false));
    EXPECT_EQ(answer.served, Served::Closed);
    EXPECT_EQ(answer.detail(), "closed");
}

TEST(ServingCheck, NothingWithinTheTimeoutIsSilenceAndItsEvidenceSaysHowLong) {
    ScriptedLink link;
    const auto answer = ask_serving(link, question(link, kMbap, true));
    EXPECT_EQ(answer.served, Served::Silent);
    const auto evidence = answer.exchange(100ms);
    EXPECT_EQ(evidence.sent, hex("7E 57 00 00 00 06 01 03 00 05 00 01"));
    EXPECT_EQ(evidence.status, ReceiveStatus::Timeout);
    EXPECT_EQ(evidence.waited, 100ms);
}

}  // namespace
}  // namespace mblab::conformance
