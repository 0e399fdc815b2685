#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "protocol/request.hpp"
#include "robustness/case_generator.hpp"
#include "robustness/recon.hpp"
#include "robustness/storm_core.hpp"

// What each request storm streams, chosen from the reconnaissance and the write policy, without
// I/O: reads of a place the device answered, FC 08's echo, FC 2B's basic identification, and
// writes only where the policy lets the tester write and never the monitor's register, each
// writing back the value read there just before, so the device's state is what it was. Every
// request is the protocol's own encoding of a typed request (protocol/request.hpp).
namespace mblab::robustness {

struct RequestPlan {
    std::uint16_t address = 0;  // the coil, input, register, FIFO or file the request names
    // Places to try in turn: a write's, `address` the first (the policy's, less the monitor's);
    // the files of FC 14 and 15, the FIFOs of FC 18.
    std::vector<std::uint16_t> places;
    // A write's read of `address` (FC 01, 03 or 14), whose answer is the value written back.
    std::vector<std::uint8_t> read_first;
    std::vector<std::uint8_t> pdu;  // the request streamed; a write's once its value is known
    std::string not_run;            // why the storm cannot run; "" when it can
};

// The request of storm `kind` at `address`; a write carries `value` (for a coil, 0 off, else on).
// Empty for a connection storm.
std::vector<std::uint8_t> storm_request(StormKind kind, std::uint16_t address,
                                        std::uint16_t value = 0);

// The plan of request storm `kind` against a device known by `recon`, under `policy`, with the
// monitor on holding register `monitor`. A code the reconnaissance did not find served, or a
// write with no place it may write other than the monitor's register, is not run, with why.
RequestPlan plan_request_storm(StormKind kind, const Recon& recon, const WritePolicy& policy,
                               std::uint16_t monitor);

// Completes a write's plan from the answer to its `read_first` (nullopt: none came): the request
// writes back the value read, or `not_run` says why there is none. Reads are left as they are.
void write_back(StormKind kind, RequestPlan& plan,
                const std::optional<std::vector<std::uint8_t>>& answer);

// One request and its answer's PDU; nullopt when none came.
using StormAsk =
    std::function<std::optional<std::vector<std::uint8_t>>(const std::vector<std::uint8_t>& pdu)>;

// A write's place, chosen before the storm: at each of `plan.places` in turn, its value read and
// written back once; the first whose write is answered with its echo is the storm's (the device
// refuses writes to some places the policy allows: a read-only register). None: `not_run` says
// why, the last place's reason.
void choose_write_place(StormKind kind, RequestPlan& plan, const StormAsk& ask);

// A read storm's place (FC 14's file, FC 18's FIFO), chosen before the storm: the first of
// `plan.places` whose request is answered with data rather than an exception. None: `not_run`
// says which were tried.
void choose_read_place(StormKind kind, RequestPlan& plan, const StormAsk& ask);

// Whatever the plan still needs asked before its storm (a write's place and value, a read's
// place); nothing when its request is known already or it is not run.
void choose_place(StormKind kind, RequestPlan& plan, const StormAsk& ask);

// Whether storm `kind`'s request names a coil, input, register or FIFO (the rung's address).
bool names_address(StormKind kind);

}  // namespace mblab::robustness
