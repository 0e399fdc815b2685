#pragma once

#include <memory>

#include "conformance/capture.hpp"
#include "conformance/client_exam_wire.hpp"
#include "security/tls_context.hpp"

// The examiner's Modbus/TCP connections: it accepts them on a listening socket, reads what they
// bring and performs the examiner's actions, in plain TCP or (given a TLS context) behind TLS.
namespace mblab::conformance {

// `capture`, when set, gets what the connections carried, the plaintext inside TLS.
std::unique_ptr<ExamWire> make_tcp_wire(ClientExaminer& exam, int listen_fd, Capture* capture,
                                        security::SharedContext tls);

// Closes the connections waiting on `listen_fd`: a client's late reconnect from the scenario
// before is not the next one's.
void drain_backlog(int listen_fd);

}  // namespace mblab::conformance
