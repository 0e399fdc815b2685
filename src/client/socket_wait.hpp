#pragma once

#include <netdb.h>
#include <sys/socket.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <string>

// The blocking side of a client's socket: a connect and waits bounded by a deadline, and errno in
// the words the tester's reports use. The bytes themselves go through a transport::Channel.
namespace mblab::client {

using SteadyClock = std::chrono::steady_clock;

std::string errno_text(int code);

// Milliseconds left before `deadline` for poll(): 0 once it passed, -1 (no limit) for max().
int remaining_ms(SteadyClock::time_point deadline);

// Waits until `fd` is ready for `events` (POLLIN, POLLOUT): false when the deadline passed
// first. An interrupted wait counts as ready: the caller tries, finds nothing, and waits again.
bool wait_ready(int fd, short events, SteadyClock::time_point deadline);

// A non-blocking connect bounded by the deadline; the socket, or -1 with `error` set.
int connect_one(const addrinfo& info, SteadyClock::time_point deadline, std::string& error);

// The address and port of a socket address (IPv4 in the first 4 bytes of `ip`).
void describe(const sockaddr_storage& address, std::array<std::uint8_t, 16>& ip,
              std::uint16_t& port);

}  // namespace mblab::client
