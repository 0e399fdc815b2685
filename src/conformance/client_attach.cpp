#include "conformance/client_attach.hpp"

#include <poll.h>

#include <optional>
#include <vector>

namespace mblab::conformance {

namespace {

using namespace std::chrono_literals;
using Clock = ClientExaminer::Clock;

// A little over what a client takes to act on a timeout before it asks again.
constexpr auto kWindowSlack = 250ms;

std::chrono::milliseconds since(Clock::time_point start) {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start);
}

}  // namespace

std::chrono::milliseconds attach_quiet(const ClientDeclarations& declared) {
    return declared.timeout.value_or(1000ms) + kWindowSlack;
}

ClientRun watch_attached(ExamWire& wire, const ClientExaminer& exam,
                         const ClientDeclarations& declared, std::chrono::milliseconds wait) {
    ClientRun run;
    run.attached = true;
    run.limit = client_run_limit(declared);
    const auto quiet = attach_quiet(declared);
    const auto started = Clock::now();
    std::optional<Clock::time_point> first;
    auto last = started;  // the client's last request or refused handshake
    std::size_t heard = 0;
    while (true) {
        std::vector<pollfd> polls;
        wire.add_polls(polls);
        ::poll(polls.data(), polls.size(), static_cast<int>(wire.wait().count()));
        wire.on_polled(polls);
        wire.perform();
        if (const auto now_heard = exam.requests().size() + exam.refusals().size();
            now_heard != heard) {
            heard = now_heard;
            last = Clock::now();
            if (!first) first = last;
        }
        if (first && (since(last) > quiet || since(*first) > run.limit)) break;
        if (!first && since(started) > wait) {
            run.stopped = true;
            run.elapsed = wait;
            run.ended = Clock::now();
            return run;
        }
    }
    run.elapsed = since(*first);
    run.ended = Clock::now();
    return run;
}

}  // namespace mblab::conformance
