#pragma once

#include <chrono>
#include <memory>
#include <string>

#include "client/link.hpp"
#include "client/raw_link.hpp"
#include "protocol/result.hpp"

namespace mblab::client {

// Modbus/TCP over the conformance tester's RawLink: frames are cut by the MBAP length field.
class TcpLink final : public Link {
  public:
    static protocol::Result<std::unique_ptr<Link>, LinkError> open(
        const Endpoint& endpoint, std::string name, std::chrono::milliseconds timeout,
        LinkObserver* observer = nullptr);

    Framing framing() const override { return Framing::Mbap; }
    const std::string& name() const override { return name_; }
    bool is_open() const override { return raw_.is_open(); }
    bool send(std::span<const std::uint8_t> adu, LinkError& error) override;
    Received receive_frame(std::chrono::milliseconds timeout) override;
    Received receive_any(std::chrono::milliseconds timeout) override {
        return raw_.receive_any(timeout);
    }
    void close() override { raw_.close(); }
    std::size_t send_for(std::span<const std::uint8_t> bytes, std::chrono::milliseconds timeout,
                         LinkError& error) override {
        return raw_.send_for(bytes, timeout, error);
    }
    bool vanish() override { return raw_.vanish(); }
    int tcp_descriptor() const override { return raw_.descriptor(); }
    Received next_frame(std::chrono::milliseconds timeout) override {
        return raw_.next_frame(timeout);
    }
    const security::TlsPeer* tls_peer() const override {
        return raw_.tls() ? &raw_.tls()->peer() : nullptr;
    }

  private:
    TcpLink(RawLink raw, std::string name, Endpoint endpoint)
        : raw_(std::move(raw)), name_(std::move(name)), endpoint_(std::move(endpoint)) {}

    RawLink raw_;
    std::string name_;
    Endpoint endpoint_;
    bool heard_ = false;  // the server has sent a byte on this connection
};

}  // namespace mblab::client
