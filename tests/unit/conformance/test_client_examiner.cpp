#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "conformance/client_examiner.hpp"
#include "conformance/references.hpp"
#include "support/hex.hpp"

// The examiner of `mblab conform-client`, hex in and hex out on a manual clock.
namespace mblab::conformance {
namespace {

using namespace std::chrono_literals;
using test::hex;
using test::to_hex;
using Kind = ClientExaminer::Action::Kind;

// Read holding registers 100 and 101 of unit 1, transaction 1.
const std::string kRequest = "00 01 00 00 00 06 01 03 00 64 00 02";
// 10100 and 10101: the seeded values.
const std::string kRight = "00 01 00 00 00 07 01 03 04 27 74 27 75";

ClientCase scenario(ClientScenario which, std::uint8_t code = 0) {
    for (const auto& c : client_tcp_cases())
        if (c.scenario == which && c.exception == code) return c;
    ADD_FAILURE() << "no such scenario";
    return {};
}

struct Exam {
    explicit Exam(ClientScenario which, std::uint8_t code = 0) : exam(make(which, code)) {}
    static ClientExaminer make(ClientScenario which, std::uint8_t code) {
        ClientDeclarations declared;
        declared.timeout = 500ms;
        declared.retries = 1;
        return ClientExaminer(scenario(which, code), declared, ClientExaminer::Clock::time_point{});
    }
    // The actions due at `at` ms, as "send 00 01 ..." / "close" / "reset" lines.
    std::vector<std::string> at(int ms) {
        std::vector<std::string> lines;
        for (const auto& action : exam.due(time(ms))) {
            lines.push_back(action.kind == Kind::Send    ? "send " + to_hex(action.bytes)
                            : action.kind == Kind::Close ? "close"
                                                         : "reset");
        }
        return lines;
    }
    // A connection opens at 0 and `request` comes on it at once; its number.
    std::size_t open_with(const std::string& request) {
        const auto connection = exam.opened(time(0));
        ask(connection, request, 0);
        return connection;
    }
    void ask(std::size_t connection, const std::string& request, int ms) {
        exam.received(connection, hex(request), time(ms));
    }
    static ClientExaminer::Clock::time_point time(int ms) {
        return ClientExaminer::Clock::time_point{} + std::chrono::milliseconds(ms);
    }
    ClientExaminer exam;
};

using Lines = std::vector<std::string>;

TEST(ClientExaminer, SeededAndDecoyValuesAreFarApart) {
    EXPECT_EQ(seeded_value(100), 10100);
    EXPECT_EQ(decoy_value(100), 40100);
    for (std::uint32_t a = 0; a < 65536; a += 97)
        EXPECT_NE(seeded_value(a), decoy_value(a));
}

TEST(ClientExaminer, EveryScenarioCitesKnownDocuments) {
    for (const auto* cases : {&client_tcp_cases(), &client_line_cases()}) {
        for (const auto& c : *cases) {
            EXPECT_FALSE(c.source.empty()) << c.id;
            for (const auto& cited : citations(c.source))
                EXPECT_FALSE(cited.url.empty()) << c.id << ": " << cited.text;
        }
    }
}

TEST(ClientExaminer, NoReplyStaysSilent) {
    Exam e(ClientScenario::NoReply);
    const auto c = e.open_with(kRequest);
    e.ask(c, kRequest, 500);
    EXPECT_EQ(e.at(5000), Lines{});
    EXPECT_EQ(e.exam.deadline(), ClientExaminer::Clock::time_point::max());
    EXPECT_EQ(e.exam.requests().size(), 2U);
    EXPECT_EQ(e.exam.requests()[1].address, 100);
}

TEST(ClientExaminer, WrongTransactionComesFirstWithDecoys) {
    Exam e(ClientScenario::WrongTransaction);
    const auto c = e.exam.opened(Exam::time(0));
    e.ask(c, kRequest, 10);
    EXPECT_EQ(e.at(10), Lines{"send 5A 5B 00 00 00 07 01 03 04 9C A4 9C A5"});
    EXPECT_EQ(e.exam.deadline(), Exam::time(60));
    EXPECT_EQ(e.at(60), Lines{"send " + kRight});
}

TEST(ClientExaminer, WrongUnitComesFirstWithDecoys) {
    Exam e(ClientScenario::WrongUnit);
    e.open_with(kRequest);
    EXPECT_EQ(e.at(49), Lines{"send 00 01 00 00 00 07 02 03 04 9C A4 9C A5"});
    EXPECT_EQ(e.at(50), Lines{"send " + kRight});
}

TEST(ClientExaminer, LateReplyMeetsTheRetry) {
    Exam e(ClientScenario::LateReply);
    const auto c = e.open_with(kRequest);
    EXPECT_EQ(e.at(499), Lines{});
    e.ask(c, "00 02 00 00 00 06 01 03 00 64 00 02", 500);
    EXPECT_EQ(e.at(500), Lines{"send 00 01 00 00 00 07 01 03 04 9C A4 9C A5"});
    EXPECT_EQ(e.at(550), Lines{"send 00 02 00 00 00 07 01 03 04 27 74 27 75"});
    EXPECT_TRUE(e.exam.stale_met_a_wait());
}

TEST(ClientExaminer, LateReplyComesAnywayWithoutARetry) {
    Exam e(ClientScenario::LateReply);
    e.open_with(kRequest);
    EXPECT_EQ(e.exam.deadline(), Exam::time(800));
    EXPECT_EQ(e.at(800), Lines{"send 00 01 00 00 00 07 01 03 04 9C A4 9C A5"});
    EXPECT_FALSE(e.exam.stale_met_a_wait());
}

TEST(ClientExaminer, ARetryUnderTheSameIdIsNotMetWithAStaleAnswer) {
    Exam e(ClientScenario::LateReply);
    const auto c = e.open_with(kRequest);
    e.ask(c, kRequest, 500);
    EXPECT_EQ(e.at(550), Lines{"send " + kRight});
    EXPECT_FALSE(e.exam.stale_met_a_wait());
}

TEST(ClientExaminer, MalformedAnswersThenRecovery) {
    const std::pair<ClientScenario, std::string> cases[] = {
        {ClientScenario::WrongFunction, "00 01 00 00 00 07 01 04 04 9C A4 9C A5"},
        {ClientScenario::Truncated, "00 01 00 00 00 06 01 03 04 9C A4 9C"},
        {ClientScenario::ExtraBytes, "00 01 00 00 00 09 01 03 04 9C A4 9C A5 DE AD"},
        {ClientScenario::ByteCount, "00 01 00 00 00 05 01 03 02 9C A4"},
    };
    for (const auto& [which, bad] : cases) {
        Exam e(which);
        const auto c = e.open_with(kRequest);
        EXPECT_EQ(e.at(0), Lines{"send " + bad});
        e.ask(c, kRequest, 100);
        EXPECT_EQ(e.at(100), Lines{"send " + kRight});
    }
}

TEST(ClientExaminer, ExceptionsAnswerEveryRequest) {
    Exam e(ClientScenario::Exception, 0x0B);
    const auto c = e.open_with(kRequest);
    e.ask(c, kRequest, 10);
    EXPECT_EQ(e.at(10),
              (Lines{"send 00 01 00 00 00 03 01 83 0B", "send 00 01 00 00 00 03 01 83 0B"}));
}

TEST(ClientExaminer, SplitAnswerCutsHeaderAndPdu) {
    Exam e(ClientScenario::SplitAnswer);
    e.open_with(kRequest);
    EXPECT_EQ(e.at(0), Lines{"send 00 01 00"});
    EXPECT_EQ(e.at(30), Lines{"send 00 00 07 01 03 04"});
    EXPECT_EQ(e.at(60), Lines{"send 27 74 27 75"});
}

TEST(ClientExaminer, TwoAnswersInOneSegment) {
    Exam e(ClientScenario::TwoAnswers);
    e.open_with(kRequest);
    EXPECT_EQ(e.at(0), Lines{"send " + kRight + " 5A 5B 00 00 00 07 01 03 04 9C A4 9C A5"});
}

TEST(ClientExaminer, CloseThenAnswerOnTheNextConnection) {
    for (const auto which : {ClientScenario::CloseFin, ClientScenario::CloseReset}) {
        Exam e(which);
        e.open_with(kRequest);
        EXPECT_EQ(e.at(0), Lines{which == ClientScenario::CloseFin ? "close" : "reset"});
        const auto second = e.exam.opened(Exam::time(20));
        e.ask(second, kRequest, 20);
        EXPECT_EQ(e.at(20), Lines{"send " + kRight});
        EXPECT_EQ(e.exam.connections(), 2U);
    }
}

TEST(ClientExaminer, PipelinedRequestsAreAnsweredInReverse) {
    Exam e(ClientScenario::Pipelined);
    e.open_with(kRequest + " 00 02 00 00 00 06 01 03 00 C8 00 01");
    EXPECT_EQ(e.at(0), Lines{"send 00 02 00 00 00 05 01 03 02 27 D8"});
    EXPECT_EQ(e.at(10), Lines{"send " + kRight});
}

TEST(ClientExaminer, ALoneRequestIsAnsweredAfterThePipelineWait) {
    Exam e(ClientScenario::Pipelined);
    e.open_with(kRequest);
    EXPECT_EQ(e.at(199), Lines{});
    EXPECT_EQ(e.at(200), Lines{"send " + kRight});
}

TEST(ClientExaminer, OtherUnitsAndFunctionsAreAnsweredAsADeviceWould) {
    Exam e(ClientScenario::SplitAnswer);
    e.open_with("00 07 00 00 00 06 FF 03 00 64 00 02");  // another unit: silence
    EXPECT_EQ(e.at(100), Lines{});
    Exam w(ClientScenario::WrongFunction);
    w.open_with("00 03 00 00 00 06 01 06 00 64 00 02");  // not a read: 01, not malformed
    EXPECT_EQ(w.at(0), Lines{"send 00 03 00 00 00 03 01 86 01"});
}

}  // namespace
}  // namespace mblab::conformance
