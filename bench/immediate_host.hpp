#pragma once

#include <cstdint>
#include <span>

#include "server/mbap_session.hpp"

// The session's host in the benches that drive MbapSession without a server around it: every
// answer is given at once, nothing is deferred, and the answers the session gives itself go
// unreported.
namespace mblab::bench {

class ImmediateHost final : public server::MbapSession::Host {
  public:
    device::DeferredDone route_deferred(std::uint32_t, const protocol::MbapHeader&) override {
        return {};
    }
    void on_own_answer(const device::RequestContext&, std::span<const std::uint8_t>,
                       protocol::ExceptionCode) override {}
};

}  // namespace mblab::bench
