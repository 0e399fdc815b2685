#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>

#include "device/request_handler.hpp"

// A small Modbus/TCP server on 127.0.0.1 that answers through any RequestHandler and breaks its
// answers on purpose, so tests can show the conformance tester catches each kind of defect (and
// does not fault devices that are right but unusual). One connection at a time, one thread.
namespace mblab::test {

enum class Fault : std::uint8_t {
    None,
    WrongTransactionId,  // transaction id + 1
    WrongLength,         // length field one short of the bytes that follow
    WrongUnitId,         // unit id + 1
    WrongByteCount,      // a read's byte count + 1
    WrongExceptionCode,  // exception code 04 (or 01 where 04 was right)
    NoAnswer,            // nothing is sent
    CloseConnection,     // the connection is closed instead of answering
    Dies,                // as CloseConnection, and then no connection is accepted (a crash)
    SlowToReopen,        // as CloseConnection, and new connections are refused for 600 ms (one
                         // connection slot, freed late): conformant
    WrongEcho,           // the last byte of an echoed answer changed
    SplitAnswer,         // right, but written in three pieces 30 ms apart
    LateAnswer,          // right, but 150 ms late
    ReorderAnswers,      // right, but requests that arrive together are answered last first
    BusyWhenQueued,      // requests that arrive behind an unanswered one are answered 06 (busy)
    DuplicateAnswer,     // every answer is sent twice
    UnsolicitedBytes,    // after the answer, 6 more bytes nobody asked for
    WriteNotApplied,     // writes are acknowledged with the right echo and not made
    PadBitsSet,          // FC 01/02: the unused bits of the last byte are set
    IllegalFunction,     // the function is answered 01, as by a device without it
    DeviceIdPastPdu,     // FC 2B/0E: the first object's length runs past the end of the PDU
    DeviceIdEndless,     // FC 2B/0E streams: more follows FF, next object id past the last
    DeviceIdBasicLevel,  // FC 2B/0E: conformity level 81 (basic) whatever objects are sent
    DataPastTheEnd,      // FC 03 reads that should answer 02 answer zeros instead
    SilentAfter,         // after `after` requests on a connection, nothing is answered
    OnlyUnit255,         // requests to any other unit id are ignored
};

struct FaultRule {
    Fault fault = Fault::None;
    std::uint8_t function = 0;  // request function code the fault applies to; 0: every one
    std::uint32_t after = 0;    // SilentAfter: requests answered before the silence
};

class FaultyServer {
  public:
    FaultyServer(device::RequestHandler& handler, FaultRule rule);
    ~FaultyServer();
    FaultyServer(const FaultyServer&) = delete;
    FaultyServer& operator=(const FaultyServer&) = delete;

    // Listens on 127.0.0.1, an ephemeral port, and returns it (0 when it cannot listen).
    std::uint16_t start();
    void stop();

    // How long a partial frame may wait for its missing bytes before exception 03 (9.1.3).
    static constexpr std::chrono::milliseconds kPartialFrameWait{200};

  private:
    void serve();
    // Serves one connection until it ends; true when the device died with it.
    bool serve_connection(int fd);
    // Listens on 127.0.0.1:`port` (0: an ephemeral port); false when it cannot.
    bool listen_on(std::uint16_t port);
    void answer(int fd, const std::uint8_t* frame, std::size_t size, bool queued);

    device::RequestHandler& handler_;
    FaultRule rule_;
    int listener_ = -1;
    std::uint16_t port_ = 0;
    bool closed_by_rule_ = false;  // the last connection was closed by a closing fault
    int wake_[2] = {-1, -1};
    std::thread thread_;
};

}  // namespace mblab::test
