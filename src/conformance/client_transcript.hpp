#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "conformance/client_examiner.hpp"

// What the wire carried in one scenario of `mblab conform-client`, in time order: the client's
// requests and the examiner's answers, each decoy marked. The evidence the HTML report shows.
namespace mblab::conformance {

struct ClientWireLine {
    std::chrono::milliseconds at{0};  // since the scenario started
    bool from_client = false;
    std::vector<std::uint8_t> bytes = {};
    bool decoy = false;
    std::size_t connection = 0;
};

using ClientTranscripts = std::map<std::string, std::vector<ClientWireLine>>;  // by case id

std::vector<ClientWireLine> transcript_of(const ClientExaminer& exam,
                                          ClientExaminer::Clock::time_point start);

}  // namespace mblab::conformance
