#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "conformance/catalogue.hpp"
#include "conformance/session.hpp"
#include "conformance/verdict.hpp"

namespace mblab::conformance {

// Hears about results as they come, so a console can print them while the run goes on.
class RunListener {
  public:
    virtual ~RunListener() = default;
    virtual void suite_started(const Suite& suite) = 0;
    virtual void case_finished(const Suite& suite, const CaseResult& result) = 0;
};

// Runs suites case by case over one session. Cases that do not apply are N/A with the reason;
// cases whose prerequisites failed are NOT RUN.
class Engine {
  public:
    explicit Engine(Session& session, RunListener* listener = nullptr)
        : session_(session), listener_(listener) {}

    // Once `flag` is set (from a signal handler, say), no further case starts: the case under
    // way ends, and every case not reached is NOT RUN, marked interrupted.
    void stop_when(const std::atomic<bool>& flag) { stop_ = &flag; }
    // Ends the run after the first case whose request went unanswered, when the other unit ids
    // were asked too and the device has never sent a byte: a wrong port or unit, or a device in
    // listen-only mode, would otherwise cost every case its timeouts for nothing.
    void stop_if_unanswered() { stop_if_unanswered_ = true; }

    RunResult run(const std::vector<Suite>& suites, const std::string& target);
    SuiteResult run_suite(const Suite& suite);
    Outcome run_case(const Case& c);

  private:
    // `fresh` is set when the next case must start on a new connection (isolated cases, a
    // tolerated close, an N/A that left the device mid-case); the engine closes it once it has
    // looked for bytes nobody asked for.
    Outcome run_steps(const Case& c, bool& fresh);
    std::optional<Outcome> check_reachable();
    bool stopped() const { return stop_ != nullptr && stop_->load(); }
    // Asks `pdu` of the device on the session as a request of its own; what came back.
    Exchange ask(std::vector<std::uint8_t> pdu);
    // After a case the device ended by closing the connection or falling silent, which the case
    // allows: why the device no longer serves (a new connection refused, a plain read unanswered),
    // or nothing when it does.
    std::optional<std::string> no_longer_serves();
    // Exception 01 to `function` makes a case N/A only when the function is not served: the
    // evidence that it is (an earlier answer in the run, or its plain request answered otherwise).
    std::optional<Exchange> served_anyway(std::span<const std::uint8_t> request_pdu);
    // Exception 03 to an individual device identification request (read code 04) is right when
    // the device's conformity level declares stream access only: the level, when it does.
    std::optional<std::uint8_t> stream_access_only();
    void note_served(const Exchange& exchange);

    Session& session_;
    RunListener* listener_;
    const std::atomic<bool>* stop_ = nullptr;
    bool stop_if_unanswered_ = false;
    std::string unanswered_;  // set once nothing answered: the run stops
    // Services answered otherwise than with exception 01 (service_key in engine.cpp).
    std::set<std::uint32_t> served_;
};

}  // namespace mblab::conformance
