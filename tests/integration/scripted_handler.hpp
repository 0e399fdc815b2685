#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <span>

#include "device/request_handler.hpp"

// A test double for the server's side of the RequestHandler seam: it echoes every request PDU,
// except for private function codes that ask for each kind of device reply, so server tests
// control exactly what the "device" does:
//   41 NN ..  echo after NN * 10 ms
//   42 ..     no answer (fault "drop")
//   43 ..     close the connection (fault "close")
//   44 ..     answer with bytes that are not a Modbus response (fault "garbage")
namespace mblab::test {

class ScriptedHandler : public device::RequestHandler {
  public:
    static constexpr std::uint8_t kDelayedEcho = 0x41;
    static constexpr std::uint8_t kDrop = 0x42;
    static constexpr std::uint8_t kClose = 0x43;
    static constexpr std::uint8_t kGarbage = 0x44;

    device::Reply handle(const device::RequestContext& context,
                         std::span<const std::uint8_t> request,
                         std::span<std::uint8_t> response) override {
        calls.fetch_add(1);
        last_unit.store(context.unit);
        device::Reply reply;
        switch (request.front()) {
            case kDrop:
                reply.action = device::ReplyAction::NoAnswer;
                return reply;
            case kClose:
                reply.action = device::ReplyAction::Close;
                return reply;
            case kGarbage: {
                static constexpr std::uint8_t kJunk[] = {0xDE, 0xAD, 0xBE, 0xEF};
                std::memcpy(response.data(), kJunk, sizeof kJunk);
                reply.size = sizeof kJunk;
                return reply;
            }
            case kDelayedEcho:
                if (request.size() > 1) reply.delay = std::chrono::milliseconds(10 * request[1]);
                break;
            default:
                break;
        }
        auto size = std::min(request.size(), response.size());
        std::memcpy(response.data(), request.data(), size);
        reply.size = size;
        return reply;
    }

    std::atomic<int> calls{0};
    std::atomic<std::uint8_t> last_unit{0};
};

}  // namespace mblab::test
