#include "conformance/block_reads.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "conformance/judge.hpp"

namespace mblab::conformance {

namespace {

constexpr std::uint8_t kReadHolding = 0x03;

std::vector<std::uint8_t> request_for(const BlockRead& read, std::uint8_t unit) {
    Pattern request;
    request.u16(0).u16(0).length().byte(unit).byte(kReadHolding).u16(read.offset).u16(read.count);
    return render_bytes(ResolvedPattern{request.tokens()});
}

ResolvedPattern answer_for(const BlockRead& read, std::uint8_t unit) {
    Pattern answer;
    const auto bytes = static_cast<std::uint8_t>(2 * read.count);
    answer.u16(0).u16(0).length().byte(unit).byte(kReadHolding).byte(bytes).any(bytes);
    return ResolvedPattern{answer.tokens()};
}

}  // namespace

std::optional<Outcome> read_blocks(Session& session, const std::vector<BlockRead>& reads,
                                   std::string_view what, const BlockSink& sink) {
    const std::uint8_t unit = session.dut().unit;
    const std::size_t depth = std::max<std::size_t>(1, session.options().pipeline_depth);
    const auto timeout = session.options().timeout;
    Progress* progress = session.progress();
    std::size_t sent = 0;
    std::size_t answered = 0;
    std::optional<Outcome> failure;
    client::LinkError error;
    while (answered < reads.size()) {
        // Keep the window full: everything that fits goes out in one write.
        std::vector<std::uint8_t> batch;
        std::size_t batch_count = 0;
        while (sent < reads.size() && sent - answered < depth) {
            auto bytes = request_for(reads[sent++], unit);
            batch.insert(batch.end(), bytes.begin(), bytes.end());
            ++batch_count;
        }
        if (batch_count > 0 && !session.send(batch, batch_count, error)) {
            failure = Outcome{Verdict::Fail, fmt::format("cannot send: {}", error.message), {}};
            break;
        }
        const BlockRead& read = reads[answered];
        auto received = session.receive_frame(timeout);
        Judgement judgement =
            judge(request_for(read, unit), std::move(received), timeout, {answer_for(read, unit)});
        ++answered;
        if (progress != nullptr) progress->update(what, answered, reads.size());
        if (judgement.matched < 0) {
            failure =
                Outcome{Verdict::Fail,
                        fmt::format("{}, read of {} registers at {:04X}: {}", read.phase,
                                    read.count, read.offset, describe_failure(judgement.exchange)),
                        {judgement.exchange}};
            break;
        }
        const auto& frame = judgement.exchange.received;
        auto values = protocol::RegisterView(std::span(frame).subspan(9));
        if (!sink(read, values)) break;
    }
    if (progress != nullptr) progress->clear();
    // Answers still in flight would be taken for the next case's; drop the connection instead.
    if (failure || sent != answered) session.close();
    return failure;
}

}  // namespace mblab::conformance
