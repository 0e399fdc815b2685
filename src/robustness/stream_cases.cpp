#include <fmt/core.h>

#include <utility>

#include "robustness/case_generator.hpp"
#include "robustness/request_bytes.hpp"

// The fixed cases of several steps or connections: requests split and pipelined, headers left
// hanging, many connections, slow readers, half-open connections and floods.
namespace mblab::robustness {

namespace {

using Bytes = std::vector<std::uint8_t>;

}  // namespace

void CaseGenerator::fixed_streams() {
    const std::uint8_t unit = recon_.unit;
    const Bytes read = words(0x03, {recon_.check_address, 1});
    using std::chrono::milliseconds;

    {
        FuzzCase c{BadInput::SplitFrame, "a request a byte at a time, 5 ms apart", {}, false};
        for (std::uint8_t byte : mbap_frame(next_transaction(), unit, read))
            c.steps.push_back({0, {byte}, milliseconds(5)});
        add(std::move(c));
    }
    for (auto [cut, pause] : {std::pair{std::size_t{7}, 50}, std::pair{std::size_t{3}, 200},
                              std::pair{std::size_t{1}, 500}, std::pair{std::size_t{10}, 100}}) {
        const Bytes frame = mbap_frame(next_transaction(), unit, read);
        FuzzCase c{BadInput::SplitFrame,
                   fmt::format("a request cut after {} bytes, {} ms apart", cut, pause),
                   {},
                   false};
        c.steps.push_back(
            {0, Bytes(frame.begin(), frame.begin() + static_cast<long>(cut)), milliseconds(pause)});
        c.steps.push_back({0, Bytes(frame.begin() + static_cast<long>(cut), frame.end()), {}});
        add(std::move(c));
    }
    {
        Bytes first = mbap_frame(next_transaction(), unit, read);
        const Bytes second = mbap_frame(next_transaction(), unit, read);
        first.insert(first.end(), second.begin(), second.begin() + 4);
        FuzzCase c{BadInput::SplitFrame, "two requests cut inside the second's header", {}, false};
        c.steps.push_back({0, std::move(first), milliseconds(20)});
        c.steps.push_back({0, Bytes(second.begin() + 4, second.end()), {}});
        add(std::move(c));
    }

    for (std::size_t keep = 1; keep <= 7; ++keep) {
        const Bytes frame = mbap_frame(next_transaction(), unit, read);
        FuzzCase c{BadInput::PartialHeader,
                   fmt::format("{} of {} bytes, left hanging", keep, frame.size()),
                   {},
                   true};
        c.steps.push_back({0, Bytes(frame.begin(), frame.begin() + static_cast<long>(keep)), {}});
        add(std::move(c));
    }

    for (std::size_t count : {2, 10, 50, 200}) {
        FuzzCase c{
            BadInput::Pipelined, fmt::format("{} requests in one segment", count), {}, false};
        Bytes all;
        for (std::size_t i = 0; i < count; ++i) {
            const Bytes frame = mbap_frame(next_transaction(), unit, read);
            all.insert(all.end(), frame.begin(), frame.end());
        }
        c.steps.push_back({0, std::move(all), {}});
        add(std::move(c));
    }
    {
        FuzzCase c{BadInput::Pipelined,
                   "30 requests, valid, unknown and protocol id 1 in turn",
                   {},
                   false};
        Bytes all;
        const Bytes unknown{0x41, 0x00, 0x00};
        for (std::size_t i = 0; i < 10; ++i) {
            for (const Bytes& frame : {mbap_frame(next_transaction(), unit, read),
                                       mbap_frame(next_transaction(), unit, unknown),
                                       mbap_frame(next_transaction(), unit, read, 1)})
                all.insert(all.end(), frame.begin(), frame.end());
        }
        c.steps.push_back({0, std::move(all), {}});
        add(std::move(c));
    }
    {
        FuzzCase c{BadInput::Pipelined, "50 requests with one transaction id", {}, false};
        Bytes all;
        const Bytes frame = mbap_frame(next_transaction(), unit, read);
        for (std::size_t i = 0; i < 50; ++i)
            all.insert(all.end(), frame.begin(), frame.end());
        c.steps.push_back({0, std::move(all), {}});
        add(std::move(c));
    }

    for (std::size_t count : {10, 50, 100}) {
        FuzzCase c{BadInput::ManyConnections,
                   fmt::format("{} connections, a request on each", count),
                   {},
                   false};
        for (std::size_t i = 0; i < count; ++i)
            c.steps.push_back({i, mbap_frame(next_transaction(), unit, read), {}});
        add(std::move(c));
    }
    {
        FuzzCase c{BadInput::ManyConnections, "20 connections, half a header on each", {}, true};
        for (std::size_t i = 0; i < 20; ++i) {
            const Bytes frame = mbap_frame(next_transaction(), unit, read);
            c.steps.push_back({i, Bytes(frame.begin(), frame.begin() + 3), {}});
        }
        add(std::move(c));
    }
}

void CaseGenerator::resource_cases() {
    const std::uint8_t unit = recon_.unit;
    const Bytes read = words(0x03, {recon_.check_address, 1});
    const Bytes largest = words(0x03, {recon_.check_address, recon_.max_read});
    auto requests = [&](std::size_t count, const Bytes& pdu) {
        Bytes all;
        all.reserve(count * (7 + pdu.size()));
        for (std::size_t i = 0; i < count; ++i) {
            const Bytes frame = mbap_frame(next_transaction(), unit, pdu);
            all.insert(all.end(), frame.begin(), frame.end());
        }
        return all;
    };

    if (limits_.connections > 100) {
        // Idle connections held through the check: a device that is full must close the
        // oldest idle one for a newcomer [TCPG 4.2.1.1], not refuse the newcomer.
        FuzzCase c{BadInput::ManyConnections,
                   fmt::format("{} connections, a request on each, held open", limits_.connections),
                   {},
                   true};
        for (std::size_t i = 0; i < limits_.connections; ++i)
            c.steps.push_back({i, mbap_frame(next_transaction(), unit, read), {}});
        add(std::move(c));
    }

    // The answers to the largest read pile up unread: megabytes a device must not buffer.
    for (auto [connections, count] : {std::pair{std::size_t{1}, std::size_t{40000}},
                                      std::pair{std::size_t{8}, std::size_t{4000}}}) {
        FuzzCase c{BadInput::SlowReader,
                   fmt::format("{} connection(s), {} FC 03 reads of {} each, answers never read",
                               connections, count, recon_.max_read),
                   {},
                   true};
        for (std::size_t i = 0; i < connections; ++i) {
            c.steps.push_back({i, requests(count, largest), {}});
            c.steps.back().unread = true;
        }
        // Time for the device to work through the requests until its send buffer is full: a
        // device that stalls on a slow reader does so only once it is.
        c.steps.back().pause = std::chrono::milliseconds(500);
        add(std::move(c));
    }

    if (limits_.half_open) {
        for (auto [connections, keep] : {std::pair{std::size_t{20}, std::size_t{3}},
                                         std::pair{std::size_t{300}, std::size_t{7}}}) {
            FuzzCase c{BadInput::HalfOpen,
                       fmt::format("{} connections, {} bytes of a request, then gone without a FIN",
                                   connections, keep),
                       {},
                       false};
            for (std::size_t i = 0; i < connections; ++i) {
                const Bytes frame = mbap_frame(next_transaction(), unit, read);
                c.steps.push_back(
                    {i, Bytes(frame.begin(), frame.begin() + static_cast<long>(keep)), {}});
                c.steps.back().vanish = true;
            }
            add(std::move(c));
        }
    }

    {
        FuzzCase c{BadInput::Flood, "20000 reads streamed, answers read as they come", {}, false};
        c.steps.push_back({0, requests(20000, read), {}});
        add(std::move(c));
    }
    const Bytes write_probe = words(0x06, {write_address_, 1});
    if (recon_.serves(0x06) && !withhold(BadInput::Flood, write_probe)) {
        FuzzCase c{BadInput::Flood,
                   fmt::format("20000 requests streamed, FC 06 of 1..10000 to register {} between "
                               "reads; the last acknowledged value read back",
                               write_address_),
                   {},
                   false};
        Bytes all;
        for (std::uint16_t value = 1; value <= 10000; ++value) {
            for (const Bytes& frame :
                 {mbap_frame(next_transaction(), unit, words(0x06, {write_address_, value})),
                  mbap_frame(next_transaction(), unit, read)})
                all.insert(all.end(), frame.begin(), frame.end());
        }
        c.steps.push_back({0, std::move(all), {}});
        c.ledger = WriteLedger{write_address_};
        add(std::move(c));
    }
}

}  // namespace mblab::robustness
