#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <memory>
#include <string_view>
#include <vector>

#include "client/link.hpp"
#include "client/target.hpp"
#include "protocol/result.hpp"
#include "robustness/run_clock.hpp"

// How a robustness run reaches the device: the links its cases go on and the link the liveness
// check asks on. Over Modbus/TCP each connection of a case is a link of its own, its answers read
// and the link closed once the case is over, and the check asks on a fresh connection while one
// opened before the case stands by. On a serial line (and RTU over TCP) one link carries the
// whole run: every connection of a case is that link, each frame's answer is read until the line
// falls quiet (at least t3.5, Modbus over Serial Line V1.02 2.5.1.1), and the check asks on it
// once quiet. These are the framing's differences; the runner and the oracle are the same for
// both.
namespace mblab::robustness {

using Dial = client::Dial;

struct LinkTimes {
    std::chrono::milliseconds settle{10};  // how long a case's answers are read
    std::chrono::milliseconds quiet{5};    // on a line: the silence that ends the answers
};

class CaseLinks {
  public:
    CaseLinks(Dial dial, LinkTimes times, RunClock clock);
    virtual ~CaseLinks();
    CaseLinks(const CaseLinks&) = delete;
    CaseLinks& operator=(const CaseLinks&) = delete;

    // The link that carries the case's `connection`, opened when it is not open and `open`
    // allows; nullptr when it is not open.
    client::Link* carry(std::size_t connection, bool open);
    // The link failed a write or was let go without a FIN: it is not used again.
    void drop(std::size_t connection);
    // The connection's answers are left for the device to hold (a slow reader).
    void leave_unread(std::size_t connection);
    // A step went out with no pause after it.
    virtual void after_frame(std::size_t connection) = 0;
    // Every step of the case went out: its answers are read, its links closed unless `hold`.
    virtual void end_case(bool hold) = 0;
    // The check after a case is over: the links held through it go.
    virtual void end_check() = 0;
    // The connection numbers a case that uses `connections` takes in a replay of several cases.
    virtual std::size_t numbers_taken(std::size_t connections) const = 0;

    // The link the liveness check asks on; nullptr, with `error`, when it cannot be opened.
    virtual client::Link* ask_on(client::LinkError& error) = 0;
    virtual void done_asking() = 0;
    // Opens a link that stands by through the next case, where a second link can be had.
    virtual void open_bystander() = 0;
    client::Link* bystander() { return bystander_.get(); }
    void close_bystander();
    // How many times the check asks before silence counts.
    virtual int asks() const = 0;
    // For the check's reasons: "a fresh connection" / "the link", and what a device does when
    // the check cannot open one: "refuses connections" / "cannot be reached".
    virtual std::string_view asked_on() const = 0;
    virtual std::string_view unreachable() const = 0;

    void close_all();

  protected:
    // The case link `at` (route()d), opened when it is not.
    client::Link* open(std::size_t at, client::LinkError& error);
    // A new link into `slot`; nullptr, with `error`, when none opens.
    client::Link* dial_into(std::unique_ptr<client::Link>& slot, client::LinkError& error);
    void close_case_links();
    virtual std::size_t route(std::size_t connection) const = 0;
    static void close(std::unique_ptr<client::Link>& link);

    Dial dial_;
    LinkTimes times_;
    RunClock clock_;
    std::vector<std::unique_ptr<client::Link>> links_;
    std::vector<bool> unread_;
    std::unique_ptr<client::Link> fresh_;
    std::unique_ptr<client::Link> bystander_;
};

// The links of a run over `framing`: one link per connection over MBAP, one link on a line.
std::unique_ptr<CaseLinks> make_case_links(client::Framing framing, Dial dial, LinkTimes times,
                                           RunClock clock);

}  // namespace mblab::robustness
