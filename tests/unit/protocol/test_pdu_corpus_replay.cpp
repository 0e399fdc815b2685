// Replays the PDU fuzz corpora (fuzz/corpus/fuzz_{request,response}_decode) in every build, so
// a codec change that breaks the round trip shows up without a fuzzing run.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "protocol/round_trip.hpp"

namespace mblab::protocol {
namespace {

struct Replay {
    std::size_t same = 0;
    std::size_t rejected = 0;
};

Replay replay(const char* target, RoundTrip (*round_trip)(std::span<const std::uint8_t>)) {
    const auto folder = std::filesystem::path(MBLAB_SOURCE_DIR) / "fuzz" / "corpus" / target;
    Replay counts;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        std::ifstream file(entry.path(), std::ios::binary);
        const std::vector<std::uint8_t> pdu{std::istreambuf_iterator<char>(file), {}};
        const RoundTrip result = round_trip(pdu);
        EXPECT_NE(result, RoundTrip::Differs) << entry.path();
        ++(result == RoundTrip::Same ? counts.same : counts.rejected);
    }
    return counts;
}

TEST(PduCorpusReplay, RequestsRoundTrip) {
    const Replay counts = replay("fuzz_request_decode", request_round_trip);
    // The corpus holds both valid requests and malformed ones the decoder must refuse.
    EXPECT_GE(counts.same, 30u);
    EXPECT_GE(counts.rejected, 5u);
}

TEST(PduCorpusReplay, ResponsesRoundTrip) {
    const Replay counts = replay("fuzz_response_decode", response_round_trip);
    EXPECT_GE(counts.same, 30u);
    EXPECT_GE(counts.rejected, 5u);
}

}  // namespace
}  // namespace mblab::protocol
