#pragma once

#include <sys/socket.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "client/target.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/dut.hpp"
#include "load/answer.hpp"
#include "load/mix.hpp"
#include "protocol/mbap_header.hpp"
#include "protocol/result.hpp"

// What a load run (`mblab load`, CTP section 8) repeats, against which nodes, how hard.
namespace mblab::load {

inline constexpr std::size_t kNoCase = std::numeric_limits<std::size_t>::max();

// One exchange the load run repeats: a request and the answers that pass. Requests carry
// transaction id 00 00; the runner writes its own id over it on the wire.
struct LoadExchange {
    std::string name;                   // "7.3.1", "fc16.3 step 2", "fc3:125"
    std::string source;                 // "CTP 7.3.1", "--mix"
    std::vector<std::uint8_t> request;  // the whole ADU
    std::vector<conformance::ResolvedPattern>
        expect;                          // alternatives, for the evidence of a failure
    std::vector<AnswerPattern> answers;  // the same, compiled for the hot path
    std::size_t test_case = kNoCase;     // index into LoadPlan::cases for protocol tests
    bool first_step = false;

    // The request's function code (a plan holds whole MBAP requests only).
    std::uint8_t function() const { return protocol::read_mbap_frame(request)->pdu[0]; }
};

// A protocol test case in the loop: its steps are exchanges [first, first + steps).
struct LoadCase {
    std::string id;
    std::string source;
    std::string title;
    std::size_t first = 0;
    std::size_t steps = 0;
    bool unsupported_is_na = false;  // exception 01 to the first step takes it out of the loop
};

// A case left out of the loop, and why.
struct LeftOut {
    std::string id;
    std::string reason;
};

// A node: a device under test, by address.
struct LoadTarget {
    std::string url;             // "tcp://127.0.0.1:1502"
    sockaddr_storage address{};  // Modbus/TCP nodes
    socklen_t address_size = 0;
    std::shared_ptr<const client::TlsSetup> tls;  // mbaps:// nodes
    std::optional<client::Target> line;  // RTU, ASCII and RTU over TCP nodes (LoadLineWorker)
};

struct LoadSettings {
    std::chrono::milliseconds duration{std::chrono::hours(1)};  // CTP 8.4
    std::size_t connections = 8;  // traffic generator connections, spread over the nodes
    double rate = 0;              // requests/s over every connection; 0: as fast as answered
    std::size_t pipeline = 1;     // requests in flight per generator connection
    std::chrono::milliseconds timeout{1000};
    std::size_t threads = 1;
    std::uint64_t seed = 1;  // of the generator's choices from the mix
    bool tests = true;       // one connection per node runs the protocol tests
};

struct LoadPlan {
    std::vector<LoadTarget> targets;
    std::vector<LoadExchange> exchanges;  // protocol tests first, then the mix
    std::size_t test_exchanges = 0;
    std::vector<LoadCase> cases;
    std::vector<LeftOut> left_out;
    // Test exchanges that read back a range the mix writes: their values cannot be known under
    // concurrent writers, so only the answer's form is judged ("7.8.1 step 2").
    std::vector<std::string> values_unchecked;
    std::vector<std::string> suites;            // names of the suites the tests come from
    std::vector<MixEntry> mix;                  // mix[i] is exchanges[test_exchanges + i]
    std::vector<std::uint64_t> mix_cumulative;  // running sum of the weights
    LoadSettings settings;

    // Every sender: the generator's connections plus one per node for the tests. On a line node
    // these are not connections but turns on the line (LoadLineWorker).
    std::size_t total_connections() const {
        return settings.connections + (settings.tests && !cases.empty() ? targets.size() : 0);
    }
    // The generator's connection `i` goes to node i % nodes.
    std::size_t node_of_traffic(std::size_t i) const { return i % targets.size(); }
    // The senders that are Modbus/TCP connections.
    std::size_t tcp_connections() const;
};

// Adds the cases of `suites` that are plain request/response exchanges and apply to `dut`:
// no procedure, not isolated, every step one well-formed MBAP request answered by a frame (no
// split writes, no silence, no tolerated close). The others go to `left_out` with the reason.
// `only` (case ids) narrows the choice; an id no suite has is an error.
protocol::Result<bool, std::string> add_protocol_tests(
    LoadPlan& plan, const std::vector<conformance::Suite>& suites, const conformance::Dut& dut,
    const std::vector<std::string>& only);

void add_mix(LoadPlan& plan, const std::vector<MixEntry>& mix, const conformance::Dut& dut);

// "1 h", "10 min", "30 s", "1 h 30 min", "1.5 s".
std::string format_duration_words(std::chrono::milliseconds duration);

}  // namespace mblab::load
