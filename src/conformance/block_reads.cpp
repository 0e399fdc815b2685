#include "conformance/block_reads.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <deque>
#include <map>
#include <thread>

#include "conformance/judge.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"

namespace mblab::conformance {

namespace {

constexpr std::uint8_t kReadHolding = 0x03;
// A device that stays busy this many times in a row for one read is not pacing the tester, it
// is refusing the read.
constexpr std::size_t kMostBusyInARow = 20;
constexpr std::chrono::milliseconds kBusyPause{10};
constexpr std::chrono::milliseconds kLongestBusyPause{200};

std::vector<std::uint8_t> request_for(const BlockRead& read, std::uint8_t unit, std::uint16_t tid) {
    Pattern request;
    request.u16(tid).u16(0).length().byte(unit).byte(kReadHolding).u16(read.offset).u16(read.count);
    return render_bytes(ResolvedPattern{request.tokens()});
}

ResolvedPattern answer_for(const BlockRead& read, std::uint8_t unit, std::uint16_t tid) {
    Pattern answer;
    const auto bytes = static_cast<std::uint8_t>(2 * read.count);
    answer.u16(tid).u16(0).length().byte(unit).byte(kReadHolding).byte(bytes).any(bytes);
    return ResolvedPattern{answer.tokens()};
}

struct InFlight {
    std::size_t read = 0;  // index into the reads
    std::uint16_t tid = 0;
};

class BlockReader {
  public:
    BlockReader(Session& session, const std::vector<BlockRead>& reads, std::string_view what,
                const BlockSink& sink)
        : session_(session),
          reads_(reads),
          what_(what),
          sink_(sink),
          unit_(session.dut().unit),
          depth_(std::max<std::size_t>(1, session.options().pipeline_depth)),
          pipelined_(depth_ > 1),
          first_depth_(depth_) {}

    BlockRun run() {
        while (fed_ < reads_.size() && !stopped_ && !failure_) {
            if (!fill_window()) break;
            take_answer();
        }
        if (Progress* progress = session_.progress()) progress->clear();
        // Answers still in flight would be taken for the next case's; drop the connection.
        if (failure_ || !in_flight_.empty()) session_.close();
        return {std::move(failure_), how()};
    }

  private:
    std::uint16_t next_tid() {
        if (!pipelined_) return 0;  // the policy's own requests
        if (++tid_ == 0) tid_ = 1;
        return tid_;
    }

    // Sends what fits in the window, reads the device asked for again first.
    bool fill_window() {
        if (pause_) {
            pause_ = false;
            std::this_thread::sleep_for(std::min(
                kLongestBusyPause,
                kBusyPause * static_cast<long>(std::max<std::size_t>(1, bursts_in_a_row_))));
        }
        std::vector<std::uint8_t> batch;
        std::size_t count = 0;
        while (in_flight_.size() < depth_ && (!again_.empty() || sent_ < reads_.size())) {
            std::size_t index = 0;
            if (!again_.empty()) {
                index = again_.front();
                again_.pop_front();
            } else {
                index = sent_++;
            }
            const InFlight flight{index, next_tid()};
            auto bytes = request_for(reads_[index], unit_, flight.tid);
            batch.insert(batch.end(), bytes.begin(), bytes.end());
            in_flight_.push_back(flight);
            ++count;
        }
        client::LinkError error;
        if (count > 0 && !session_.send(batch, count, error)) {
            failure_ = Outcome{Verdict::Fail, fmt::format("cannot send: {}", error.message), {}};
            return false;
        }
        return true;
    }

    Outcome fail_read(const InFlight& flight, std::string reason, Exchange evidence) {
        const BlockRead& read = reads_[flight.read];
        return Outcome{Verdict::Fail,
                       fmt::format("{}, read of {} registers at {:04X}: {}", read.phase, read.count,
                                   read.offset, reason),
                       {std::move(evidence)}};
    }

    void take_answer() {
        const auto timeout = session_.options().timeout;
        const std::vector<std::uint8_t> previous = session_.last_frame();
        auto received = session_.receive_frame(timeout);
        const std::size_t carried = session_.connection_requests();
        // Which read this answers: by transaction id when pipelined, else the one outstanding.
        auto slot = in_flight_.begin();
        if (pipelined_ && received.status == client::ReceiveStatus::Frame) {
            const std::uint16_t tid = transaction_of(received.bytes);
            slot = std::find_if(in_flight_.begin(), in_flight_.end(),
                                [&](const InFlight& f) { return f.tid == tid; });
            if (slot == in_flight_.end()) {
                const InFlight oldest = in_flight_.front();
                auto request = request_for(reads_[oldest.read], unit_, oldest.tid);
                Judgement judgement = judge(request, std::move(received), timeout,
                                            {answer_for(reads_[oldest.read], unit_, oldest.tid)});
                judgement.exchange.on_connection = carried;
                failure_ = fail_read(
                    oldest,
                    fmt::format("an answer with transaction id {:04X} matches no request in "
                                "flight (a duplicate or unsolicited answer)",
                                tid),
                    judgement.exchange);
                return;
            }
        }
        const InFlight flight = *slot;
        in_flight_.erase(slot);
        const BlockRead& read = reads_[flight.read];
        const auto request = request_for(read, unit_, flight.tid);
        if (received.status == client::ReceiveStatus::Frame &&
            is_exception_answer(request, received.bytes,
                                protocol::ExceptionCode::ServerDeviceBusy) &&
            transaction_of(received.bytes) == flight.tid) {
            back_off(flight);
            return;
        }
        busy_in_a_row_ = 0;
        if (lowered_) {
            lowered_ = false;
        } else {
            bursts_in_a_row_ = 0;
        }
        const bool silent =
            received.status == client::ReceiveStatus::Timeout && received.bytes.empty();
        Judgement judgement =
            judge(request, std::move(received), timeout, {answer_for(read, unit_, flight.tid)});
        judgement.exchange.on_connection = carried;
        if (judgement.matched < 0) {
            const auto& got = judgement.exchange.received;
            std::string reason;
            if (judgement.exchange.status == client::ReceiveStatus::Frame && !previous.empty() &&
                got == previous) {
                reason = describe_duplicate(got);
            } else {
                reason = describe_failure(judgement.exchange, session_.framing());
                if (silent) reason += session_.no_answer_hint(request);
            }
            failure_ = fail_read(flight, std::move(reason), judgement.exchange);
            return;
        }
        ++answered_;
        if (Progress* progress = session_.progress()) {
            progress->update(what_, answered_, reads_.size());
        }
        done_.emplace(flight.read,
                      std::vector<std::uint8_t>(judgement.exchange.received.begin() + 9,
                                                judgement.exchange.received.end()));
        feed();
        if (!pipelined_ && !stopped_ && fed_ < reads_.size()) {
            // Before the next read goes out, nothing else may be waiting from the device.
            auto unasked = session_.take_unasked(std::chrono::milliseconds(0));
            if (!unasked.bytes.empty()) {
                auto reason =
                    describe_unasked(unasked, "after this answer,", judgement.exchange.received);
                failure_ = fail_read(flight, std::move(reason),
                                     unasked_exchange(std::move(unasked), request));
            }
        }
    }

    // Gives the registers to the sink in the order of the reads, whatever order answers came in.
    void feed() {
        while (!stopped_) {
            auto next = done_.find(fed_);
            if (next == done_.end()) return;
            const auto values = protocol::RegisterView(std::span<const std::uint8_t>(next->second));
            if (!sink_(reads_[fed_], values)) stopped_ = true;
            done_.erase(next);
            ++fed_;
        }
    }

    // Exception 06: the device holds fewer requests than were in flight. Halve the depth once
    // per burst of busy answers, pause before sending more, and ask for the read again.
    void back_off(const InFlight& flight) {
        ++busy_;
        ++busy_in_a_row_;
        if (busy_in_a_row_ > kMostBusyInARow + 2 * first_depth_) {
            Exchange evidence;
            evidence.sent = request_for(reads_[flight.read], unit_, flight.tid);
            failure_ = fail_read(flight,
                                 fmt::format("the device answered exception 06 (busy) {} times "
                                             "in a row, down to one request in flight",
                                             busy_in_a_row_),
                                 std::move(evidence));
            return;
        }
        if (!lowered_) {
            lowered_ = true;
            ++bursts_in_a_row_;
            depth_ = std::max<std::size_t>(1, depth_ / 2);
            lowest_depth_ = std::min(lowest_depth_, depth_);
            pause_ = true;
        }
        again_.push_back(flight.read);
    }

    std::string how() const {
        std::string text =
            pipelined_ ? fmt::format("pipelined {} deep", first_depth_) : "one request at a time";
        if (busy_ > 0) {
            text += fmt::format(
                "; the device answered 06 (busy) {} time{}: depth lowered to {}, those reads "
                "sent again",
                busy_, busy_ == 1 ? "" : "s", lowest_depth_);
        }
        return text;
    }

    Session& session_;
    const std::vector<BlockRead>& reads_;
    std::string_view what_;
    const BlockSink& sink_;
    const std::uint8_t unit_;
    std::size_t depth_;
    const bool pipelined_;
    const std::size_t first_depth_;
    std::size_t lowest_depth_ = SIZE_MAX;
    std::uint16_t tid_ = 0;
    std::size_t sent_ = 0;
    std::size_t answered_ = 0;
    std::size_t fed_ = 0;
    std::size_t busy_ = 0;
    std::size_t busy_in_a_row_ = 0;
    std::size_t bursts_in_a_row_ = 0;
    bool lowered_ = false;  // the depth was lowered for the current burst of busy answers
    bool pause_ = false;    // wait a little before the next requests go out
    bool stopped_ = false;
    std::deque<InFlight> in_flight_;
    std::deque<std::size_t> again_;
    std::map<std::size_t, std::vector<std::uint8_t>> done_;
    std::optional<Outcome> failure_;
};

}  // namespace

BlockRun read_blocks(Session& session, const std::vector<BlockRead>& reads, std::string_view what,
                     const BlockSink& sink) {
    return BlockReader(session, reads, what, sink).run();
}

}  // namespace mblab::conformance
