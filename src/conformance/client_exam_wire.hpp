#pragma once

#include <poll.h>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "conformance/client_exam_run.hpp"
#include "conformance/client_examiner.hpp"
#include "conformance/client_process.hpp"

// What runs the scenarios of `mblab conform-client` whatever carries them: a wire (TCP
// connections, or a serial line) performs one examiner's actions while the client's command runs.
namespace mblab::conformance {

class ExamWire {
  public:
    virtual ~ExamWire() = default;
    virtual void add_polls(std::vector<pollfd>& polls) const = 0;
    virtual void on_polled(const std::vector<pollfd>& polls) = 0;
    virtual void perform() = 0;
    // How long poll() may wait before the wire has something to do.
    virtual std::chrono::milliseconds wait() const = 0;
};

// How the scenarios are carried: the suite, its cases, where the client finds the examiner (the
// placeholders but the unit, address and count each case fills in), the framing and a wire for
// each scenario's examiner.
struct ExamCarrier {
    Suite suite;
    const std::vector<ClientCase>* cases = nullptr;
    ClientPlaceholders values;
    protocol::Framing framing = protocol::Framing::Mbap;
    std::function<std::unique_ptr<ExamWire>(ClientExaminer&)> wire;
};

// The suite `cases` make, for the reports.
Suite client_suite(std::string name, std::string title, std::string source,
                   const std::vector<ClientCase>& cases);

RunResult run_client_cases(const ExamCarrier& carrier, const ClientExamOptions& options,
                           RunListener* listener);

}  // namespace mblab::conformance
