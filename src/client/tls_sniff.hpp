#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "client/raw_link.hpp"

// A plain tcp:// client that has reached a TLS port (a Modbus/TCP Security server, port 802)
// says so in one line instead of reporting a device that closes on every request: a TLS server
// answers bytes that are not TLS by closing the connection (OpenSSL does) or with an alert.
namespace mblab::client {

// Whether `bytes` start as a TLS record does (RFC 8446 5.1): an alert (15) or a handshake (16)
// of protocol version 3.x, with a length such a record can have.
bool looks_like_tls(std::span<const std::uint8_t> bytes);

// "the server at HOST:PORT answered with TLS bytes (15 03 03 00 02 ...): use mbaps://"
std::string tls_answer_text(const Endpoint& endpoint, std::span<const std::uint8_t> bytes);

// Whether `detail` is a tls_answer_text: the link's answer, given to the user as it is.
bool is_tls_answer_text(std::string_view detail);

// A TLS 1.2 ClientHello record (RFC 5246 7.4.1.2) offering the ECDHE AES-GCM suites and, for a
// server that speaks only TLS 1.3, the TLS 1.3 suites: a TLS server answers it with a
// ServerHello or an alert, either a TLS record.
std::vector<std::uint8_t> tls_client_hello();

// Whether the server at `endpoint` speaks TLS, asked on a new plain connection with
// tls_client_hello(), waiting up to `timeout` for its first bytes: tls_answer_text when it does.
// A port does not change between TLS and plain while mblab runs, so each endpoint is asked once
// per process and the answer remembered.
std::optional<std::string> sniff_tls(const Endpoint& endpoint, std::chrono::milliseconds timeout);

}  // namespace mblab::client
