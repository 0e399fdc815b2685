#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>

#include "device/request_handler.hpp"
#include "device/role_rules.hpp"
#include "protocol/exception_code.hpp"
#include "security/tls_context.hpp"
#include "transport/allow_list.hpp"

namespace mblab::server {

struct ServerOptions {
    // Connections admitted at once; when full, the oldest idle one is closed to admit a new
    // one ([TCPG] 4.2.1.1). 0: no limit.
    std::size_t max_connections = 256;
    // A connection without a whole request or an answer for this long is closed; this also
    // ends slowloris clients that send part of a header and go quiet. 0: never.
    std::chrono::milliseconds idle_timeout{60'000};
    // How long an unfinished frame may wait for its missing bytes before it is answered with
    // exception 03 (CTP 9.1.3) and dropped, so the stream stays in step. A connection that
    // has completed no request and sent no answer for this long while it is not idle counts as
    // stalled: a full server closes it first to admit a newcomer.
    std::chrono::milliseconds partial_frame_timeout{250};
    // How long a whole frame may take from its first byte. partial_frame_timeout bounds only the
    // gap between bytes, so a client that trickles a byte at a time would otherwise hold a
    // frame open for ever; past this, it is answered 03 (when its function code came) and
    // closed, since the rest of its frame would be read out of step.
    std::chrono::milliseconds frame_limit{1000};
    // Requests a connection may have waiting for their answers; past it a request is answered
    // with exception 06 (server device busy).
    std::size_t max_outstanding = 16;
    transport::AllowList allow;  // empty: every client
    // Told the unit of each busy answer the server gives itself, so a device can count it
    // (FC 08 sub 11). Called on the server's thread.
    std::function<void(std::uint8_t unit)> on_busy_reply;
    // Told each answer a Modbus/TCP session gives itself, without the handler (06 busy, 01 refused
    // by role, 03 for an unfinished frame; MbapSession::Host::on_own_answer), for the traffic
    // log. Called on the server's thread.
    std::function<void(const device::RequestContext& context, std::span<const std::uint8_t> request,
                       protocol::ExceptionCode code)>
        on_own_answer;
    // Modbus/TCP Security: set, every connection is a TLS session with this context (mbaps://)
    // and each request is authorized by the client's role under `roles` (deny by default).
    security::SharedContext tls;
    std::shared_ptr<const device::RoleRules> roles;
    // A TLS handshake not finished by then closes the connection: a client that trickles its
    // handshake must not hold a connection as long as the idle timeout would let it.
    std::chrono::milliseconds handshake_limit{10'000};
    // Told each refused handshake's reason (on the server's thread), for the operator's log.
    std::function<void(const std::string& reason)> on_tls_refused;
};

}  // namespace mblab::server
