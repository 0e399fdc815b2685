#include "conformance/client_transcript.hpp"

#include <algorithm>

namespace mblab::conformance {

std::vector<ClientWireLine> transcript_of(const ClientExaminer& exam,
                                          ClientExaminer::Clock::time_point start) {
    const auto since = [&](ClientExaminer::Clock::time_point at) {
        return std::chrono::duration_cast<std::chrono::milliseconds>(at - start);
    };
    std::vector<ClientWireLine> lines;
    for (const auto& request : exam.requests())
        lines.push_back({since(request.at), true, request.adu, false, request.connection});
    for (const auto& answer : exam.answers())
        lines.push_back({since(answer.at), false, answer.bytes, answer.decoy, answer.connection});
    // A request comes before the answers it drew, at the same millisecond.
    std::stable_sort(lines.begin(), lines.end(), [](const auto& a, const auto& b) {
        return a.at < b.at || (a.at == b.at && a.from_client && !b.from_client);
    });
    return lines;
}

}  // namespace mblab::conformance
