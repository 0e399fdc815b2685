// A whole Modbus/TCP server session (server::MbapSession) with the reference device behind it,
// driven from the input: bytes in chunks, the clock stepping over the session's deadlines, the
// client's socket taking some or all of the answers, a gateway-like unit whose answers come
// later, the end of input. It must not crash, and:
//   - what goes out is whole MBAP frames (protocol id 0, a length a PDU can have) and never more
//     than the session offered;
//   - well-formed mode: every answer is for a request sent, at most one each, in request order;
//     raw mode: no more answers than 8-byte frames could fit in what was received;
//   - every deadline, once on_time() has run, has moved on or ended the connection;
//   - after the end of input, with the answers taken and the clock run on, the session ends.
//
// Input: byte 0 picks the mode (bit 0: well-formed), max_outstanding (bits 1-2) and whether
// unit 9 defers (bit 3); then operations, one byte each (op in the low 3 bits, an argument in the
// high 5) with their bytes. A write takes arg * 9 + 1 bytes (raw), or is a request of unit
// {1, 0, FF, 9}[arg & 3] whose PDU is the (arg >> 2) + 1 bytes that follow (well-formed).
#include <sys/uio.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <memory>
#include <vector>

#include "device/profile_paths.hpp"
#include "device/reference_device.hpp"
#include "server/mbap_session.hpp"

namespace {

using mblab::server::Clock;
using mblab::server::MbapSession;
using namespace std::chrono_literals;

void require(bool condition, const char* what) {
    if (!condition) {
        std::fprintf(stderr, "server session invariant broken: %s\n", what);
        std::abort();
    }
}

mblab::device::ReferenceDevice& reference_device() {
    static const auto device = [] {
        auto loaded = mblab::device::load_profile(mblab::device::default_profile_path());
        require(static_cast<bool>(loaded), "the default profile does not load");
        return std::move(loaded).value();
    }();
    return *device;
}

constexpr std::uint8_t kDeferredUnit = 9;

// The reference device, with a unit whose answers wait for the input to release them (as a
// serial gateway's do).
class Device final : public mblab::device::RequestHandler {
  public:
    explicit Device(bool defers) : defers_(defers) {}

    mblab::device::Reply handle(const mblab::device::RequestContext& context,
                                std::span<const std::uint8_t> request,
                                std::span<std::uint8_t> response) override {
        return reference_device().handle(context, request, response);
    }
    std::optional<mblab::device::Reply> handle_or_defer(
        const mblab::device::RequestContext& context, std::span<const std::uint8_t> request,
        std::span<std::uint8_t> response, mblab::device::Deferral& deferral) override {
        if (!defers_ || context.unit != kDeferredUnit) return handle(context, request, response);
        waiting_.push_back({{request.begin(), request.end()}, deferral.take()});
        return std::nullopt;
    }
    bool release_one() {
        if (waiting_.empty()) return false;
        auto job = std::move(waiting_.front());
        waiting_.pop_front();
        std::array<std::uint8_t, 253> response{};
        const auto reply = handle({1, mblab::device::Link::Tcp}, job.pdu, response);
        job.done(reply, std::span(response).first(std::min(reply.size, response.size())));
        return true;
    }

  private:
    struct Job {
        std::vector<std::uint8_t> pdu;
        mblab::device::DeferredDone done;
    };
    bool defers_;
    std::deque<Job> waiting_;
};

// What the client sent and what it expects back, in order.
struct Request {
    std::uint16_t transaction = 0;
    std::uint8_t unit = 0;
    std::uint8_t function = 0;
};

class Run final : private MbapSession::Host {
  public:
    Run(std::uint8_t flags)
        : well_formed_(flags & 1),
          device_((flags & 8) != 0),
          session_(device_, limits_for(flags), stats_, *this, now_) {}

    // Reads one operation; false at the end of the input.
    bool step(std::span<const std::uint8_t>& input);
    void finish();

  private:
    static mblab::server::MbapSessionLimits limits_for(std::uint8_t flags) {
        static constexpr std::size_t kOutstanding[] = {16, 1, 2, 4};
        mblab::server::MbapSessionLimits limits;
        limits.max_outstanding = kOutstanding[(flags >> 1) & 3];
        return limits;
    }

    mblab::device::DeferredDone route_deferred(
        std::uint32_t ticket, const mblab::protocol::MbapHeader& request) override {
        return [this, ticket, request](const mblab::device::Reply& reply,
                                       std::span<const std::uint8_t> pdu) {
            if (!ended_) session_.answer_deferred(ticket, request, reply, pdu, now_);
        };
    }
    void on_own_answer(const mblab::device::RequestContext& /*context*/,
                       std::span<const std::uint8_t> request,
                       mblab::protocol::ExceptionCode /*code*/) override {
        // The log it feeds shows the function code: an answer always has one to show.
        require(!request.empty(), "the session answered a request without a function code");
    }

    void queue_bytes(std::span<const std::uint8_t> bytes);
    void queue_request(std::uint8_t unit, std::span<const std::uint8_t> pdu);
    void deliver(std::size_t most);
    void end_input();
    void wait(Clock::duration time);
    // The client's socket takes up to `most` bytes of what the session offers.
    void accept(std::size_t most);
    void check_answers();
    void check_ending();

    bool well_formed_;
    Device device_;
    mblab::server::ServerStats stats_;
    Clock::time_point now_ = Clock::time_point{} + 1h;
    MbapSession session_;

    std::deque<std::uint8_t> unsent_;  // written by the client, not read by the session yet
    std::size_t delivered_ = 0;
    bool input_ended_ = false;
    std::deque<Request> requests_;  // well-formed mode: sent and not answered yet
    std::uint16_t next_transaction_ = 0;
    std::vector<std::uint8_t> output_;  // taken, not yet checked as whole frames
    std::size_t answers_ = 0;
    bool ended_ = false;
};

void Run::queue_bytes(std::span<const std::uint8_t> bytes) {
    if (!input_ended_) unsent_.insert(unsent_.end(), bytes.begin(), bytes.end());
}

void Run::queue_request(std::uint8_t unit, std::span<const std::uint8_t> pdu) {
    if (input_ended_ || pdu.empty()) return;
    const auto transaction = next_transaction_++;
    const auto length = static_cast<std::uint16_t>(pdu.size() + 1);
    const std::uint8_t header[] = {
        static_cast<std::uint8_t>(transaction >> 8), static_cast<std::uint8_t>(transaction), 0,   0,
        static_cast<std::uint8_t>(length >> 8),      static_cast<std::uint8_t>(length),      unit};
    queue_bytes(header);
    queue_bytes(pdu);
    requests_.push_back({transaction, unit, pdu[0]});
}

void Run::deliver(std::size_t most) {
    if (ended_ || !session_.wants_input() || unsent_.empty()) return;
    const auto space = session_.input_space();
    const auto count = std::min({most, space.size(), unsent_.size()});
    std::copy_n(unsent_.begin(), count, space.begin());
    unsent_.erase(unsent_.begin(), unsent_.begin() + static_cast<std::ptrdiff_t>(count));
    delivered_ += count;
    session_.received(count, now_);
    check_ending();
}

void Run::end_input() {
    input_ended_ = true;
    if (ended_ || !unsent_.empty() || !session_.wants_input()) return;
    session_.end_of_input(now_);
    check_ending();
}

void Run::wait(Clock::duration time) {
    const auto until = now_ + time;
    while (!ended_) {
        const auto at = session_.deadline();
        if (at > until) break;
        now_ = std::max(now_, at);
        session_.on_time(now_);
        require(session_.deadline() > now_ || session_.ending(now_) == MbapSession::Ending::Now,
                "a deadline that on_time() leaves in the past");
        check_ending();
    }
    now_ = until;
}

void Run::accept(std::size_t most) {
    if (ended_) return;
    std::array<iovec, MbapSession::kMaxGather> gathered;
    const auto count = session_.output(now_, gathered);
    require(count <= gathered.size(), "output() past its buffers");
    std::size_t offered = 0;
    for (std::size_t i = 0; i < count; ++i) {
        const auto* bytes = static_cast<const std::uint8_t*>(gathered[i].iov_base);
        const auto take = std::min(gathered[i].iov_len, most - std::min(most, offered));
        output_.insert(output_.end(), bytes, bytes + take);
        offered += gathered[i].iov_len;
    }
    const auto taken = std::min(most, offered);
    session_.sent(taken, now_);
    check_answers();
    if (count == 0) check_ending();
}

// Takes the whole frames out of output_ and checks each.
void Run::check_answers() {
    std::size_t at = 0;
    while (output_.size() - at >= 7) {
        const std::uint8_t* frame = output_.data() + at;
        const unsigned protocol = frame[2] << 8 | frame[3];
        const unsigned length = frame[4] << 8 | frame[5];
        require(protocol == 0, "an answer with a protocol id other than 0");
        require(length >= 2 && length <= 254, "an answer with a length no PDU has");
        if (output_.size() - at < 6 + length) break;
        ++answers_;
        if (well_formed_) {
            const unsigned transaction = frame[0] << 8 | frame[1];
            while (!requests_.empty() && requests_.front().transaction != transaction) {
                requests_.pop_front();  // unanswered: a broadcast, a unit that stays silent
            }
            require(!requests_.empty(), "an answer out of order or for no request");
            const auto& request = requests_.front();
            require(frame[6] == request.unit, "an answer for another unit");
            require((frame[7] & 0x7F) == (request.function & 0x7F) ||
                        ((frame[7] & 0x80) && frame[8] == 0x06),
                    "an answer for another function");
            requests_.pop_front();
        } else {
            require(answers_ <= delivered_ / 8, "more answers than requests fit in the input");
        }
        at += 6 + length;
    }
    output_.erase(output_.begin(), output_.begin() + static_cast<std::ptrdiff_t>(at));
}

void Run::check_ending() {
    if (ended_) return;
    const auto ending = session_.ending(now_);
    if (ending == MbapSession::Ending::Open) return;
    if (ending == MbapSession::Ending::AfterAnswers) {
        std::array<iovec, MbapSession::kMaxGather> gathered;
        require(session_.output(now_, gathered) == 0, "output after the last answer");
        require(output_.empty(), "closed after answers with an answer cut short");
    }
    ended_ = true;
}

bool Run::step(std::span<const std::uint8_t>& input) {
    if (input.empty() || ended_) return false;
    const std::uint8_t op = input[0] & 7;
    const std::uint8_t arg = input[0] >> 3;
    input = input.subspan(1);
    switch (op) {
        case 0: {  // the client writes: bytes (raw), or a request of a unit (well-formed)
            static constexpr std::uint8_t kUnits[] = {1, 0, 0xFF, kDeferredUnit};
            const auto wanted = well_formed_ ? (arg >> 2) + 1u : arg * 9u + 1u;
            const auto bytes = input.first(std::min<std::size_t>(input.size(), wanted));
            input = input.subspan(bytes.size());
            if (well_formed_) {
                queue_request(kUnits[arg & 3], bytes);
            } else {
                queue_bytes(bytes);
            }
            break;
        }
        case 1:
            deliver(arg == 0 ? 1024 : arg);
            break;
        case 2: {
            static constexpr Clock::duration kSteps[] = {0ms,   1ms,   10ms,  99ms,   100ms, 249ms,
                                                         250ms, 251ms, 999ms, 1000ms, 60s,   61s};
            // Well-formed frames stay whole: the clock waits while one is half read.
            if (!well_formed_ || !session_.has_partial()) wait(kSteps[arg % std::size(kSteps)]);
            break;
        }
        case 3:
            accept(arg == 31 ? SIZE_MAX : arg * 3u);
            break;
        case 4:
            device_.release_one();
            check_ending();
            break;
        case 5:
            end_input();
            break;
        default:
            accept(SIZE_MAX);
            deliver(1024);
            break;
    }
    return true;
}

// Everything sent is read, the input ends, answers are taken and the clock runs until the
// session ends; it must.
void Run::finish() {
    input_ended_ = true;
    for (int round = 0; !ended_; ++round) {
        require(round < 10'000, "the session does not end after the end of input");
        deliver(1024);
        end_input();
        accept(SIZE_MAX);
        if (device_.release_one() || ended_) continue;
        // Well-formed frames stay whole: time passes once the session has read all it can.
        if (session_.wants_input() && !unsent_.empty()) continue;
        const auto at = session_.deadline();
        require(at != Clock::time_point::max(), "the session waits for nothing to end");
        wait(std::max(at, now_) - now_);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    Run run(data[0]);
    auto input = std::span(data + 1, size - 1);
    while (run.step(input)) {
    }
    run.finish();
    return 0;
}
