#include "conformance/session.hpp"

#include <fmt/core.h>

#include <array>
#include <thread>

#include "client/target.hpp"
#include "client/unit_probe.hpp"
#include "protocol/adu.hpp"
#include "protocol/framer.hpp"
#include "protocol/limits.hpp"
#include "protocol/mbap_header.hpp"

namespace mblab::conformance {

namespace {

std::string framing_name(const client::Target& target) {
    if (target.tcp) return {};
    switch (target.serial->kind) {
        case transport::SerialUrl::Kind::Rtu:
            return "RTU";
        case transport::SerialUrl::Kind::Ascii:
            return "ASCII";
        case transport::SerialUrl::Kind::RtuOverTcp:
            return "RTU over TCP";
    }
    return "a serial framing";
}

Dut on_target(Dut dut, const client::Target& target) {
    dut.serial_framing = framing_name(target);
    return dut;
}

client::Target tcp_target(const client::Endpoint& endpoint) {
    client::Target target;
    target.name = fmt::format("tcp://{}:{}", endpoint.host, endpoint.port);
    target.tcp = endpoint;
    return target;
}

}  // namespace

Session::Session(client::Target target, Dut dut, EngineOptions options,
                 client::LinkObserver* observer, Progress* progress)
    : target_(std::move(target)),
      dut_(on_target(std::move(dut), target_)),
      facts_(dut_),
      options_(options),
      observer_(observer),
      progress_(progress) {
    // A serial line carries one request at a time.
    if (!target_.tcp) options_.pipeline_depth = 1;
    if (options_.pipeline_depth == 0) options_.pipeline_depth = 1;
    if (target_.secure) secure_target_ = target_;
}

Session::Session(const client::Endpoint& endpoint, Dut dut, EngineOptions options,
                 client::LinkObserver* observer, Progress* progress)
    : Session(tcp_target(endpoint), std::move(dut), options, observer, progress) {}

std::optional<std::string> Session::host() const {
    if (target_.tcp) return target_.tcp->host;
    if (target_.serial->kind == transport::SerialUrl::Kind::RtuOverTcp) {
        return target_.serial->endpoint.address().to_string();
    }
    return std::nullopt;
}

client::Framing Session::framing() const {
    return client::framing_of(target_);
}

bool Session::connect(client::LinkError& error) {
    if (link_ && link_->is_open()) return true;
    link_.reset();
    auto opened = dial_ ? dial_() : client::open_link(target_, options_.connect_timeout, observer_);
    if (!opened) {
        error = opened.error();
        return false;
    }
    link_ = std::move(opened.value());
    if (const auto* peer = link_->tls_peer();
        peer != nullptr && peer->own_role.kind == security::RoleReading::Kind::Role) {
        certificate_role_ = peer->own_role.role;
    }
    ever_connected_ = true;
    connection_requests_ = 0;
    last_frame_.clear();
    return true;
}

bool Session::reconnect(client::LinkError& error) {
    constexpr std::array<std::chrono::milliseconds, 3> kPauses{std::chrono::milliseconds(250),
                                                               std::chrono::milliseconds(500),
                                                               std::chrono::milliseconds(750)};
    if (connect(error)) return true;
    for (auto pause : kPauses) {
        std::this_thread::sleep_for(pause);
        if (connect(error)) return true;
    }
    return false;
}

void Session::close() {
    link_.reset();
}

bool Session::send(std::span<const std::uint8_t> bytes, std::size_t count, client::LinkError& error,
                   std::span<const std::size_t> split, std::chrono::milliseconds delay) {
    if (!connect(error)) return false;
    requests_ += count;
    connection_requests_ += count;
    if (link_->framing() != client::Framing::Mbap) {
        if (count != 1 || !split.empty()) {
            error.message = "a serial line carries one whole request at a time";
            return false;
        }
        return send_on_line(bytes, error);
    }
    std::size_t from = 0;
    for (std::size_t cut : split) {
        if (cut <= from || cut >= bytes.size()) continue;
        if (!link_->send(bytes.subspan(from, cut - from), error)) return false;
        std::this_thread::sleep_for(delay);
        from = cut;
    }
    return link_->send(bytes.subspan(from), error);
}

bool Session::send_on_line(std::span<const std::uint8_t> bytes, client::LinkError& error) {
    protocol::Framer framer({client::Framing::Mbap});
    const auto request = framer.whole_frame(bytes);
    if (!request) {
        error.message = std::string("not a plain Modbus/TCP request: ") + request.error();
        return false;
    }
    line_transaction_ = request->header.transaction_id;
    std::array<std::uint8_t, protocol::limits::kMaxAsciiChars> adu{};
    const std::size_t size =
        protocol::write_adu({link_->framing(), request->header.unit}, request->pdu, adu);
    if (size == 0) {
        error.message = "the request does not fit in one serial frame";
        return false;
    }
    if (in_case_) line_frames_.note(bytes, std::span(adu).first(size));
    return link_->send(std::span(adu).first(size), error);
}

bool Session::send_on_wire(std::span<const std::uint8_t> wire, client::LinkError& error) {
    if (!connect(error)) return false;
    if (link_->framing() == client::Framing::Mbap) {
        error.message = "raw line frames are for serial framings only";
        return false;
    }
    ++requests_;
    ++connection_requests_;
    return link_->send(wire, error);
}

client::Received Session::receive_from_wire(std::chrono::milliseconds timeout) {
    if (!link_) return {client::ReceiveStatus::Closed, {}, "connection closed"};
    auto got = link_->receive_frame(timeout);
    if (!got.bytes.empty()) heard_ = true;
    return got;
}

client::Received Session::in_case_notation(client::Received received) {
    if (received.status != client::ReceiveStatus::Frame ||
        received.header.framing == client::Framing::Mbap) {
        return received;
    }
    std::array<std::uint8_t, protocol::limits::kMaxTcpAdu> adu{};
    const std::size_t size = protocol::write_adu(
        {client::Framing::Mbap, received.header.unit, line_transaction_}, received.pdu, adu);
    if (in_case_) line_frames_.note(std::span(adu).first(size), received.bytes);
    received.bytes.assign(adu.begin(), adu.begin() + static_cast<long>(size));
    return received;
}

void Session::start_case(std::string_view id) {
    line_frames_.clear();
    in_case_ = true;
    if (observer_ != nullptr) observer_->on_label(fmt::format("case {}", id));
}

void Session::end_case() {
    line_frames_.clear();
    in_case_ = false;
    if (observer_ != nullptr) observer_->on_label({});
}

client::Received Session::receive_frame(std::chrono::milliseconds timeout) {
    client::Received received{client::ReceiveStatus::Closed, {}, "connection closed"};
    if (link_) received = in_case_notation(link_->receive_frame(timeout));
    if (received.status == client::ReceiveStatus::Frame) last_frame_ = received.bytes;
    if (!received.bytes.empty()) heard_ = true;
    return received;
}

client::Received Session::take_unasked(std::chrono::milliseconds wait) {
    if (!link_ || !link_->is_open()) return {client::ReceiveStatus::Timeout};
    // On a line a framing error also means bytes arrived; they are kept as they came.
    auto got = link_->receive_any(wait);
    if (!got.bytes.empty()) heard_ = true;
    return got.bytes.empty() ? client::Received{client::ReceiveStatus::Timeout} : got;
}

std::string Session::no_answer_hint(std::span<const std::uint8_t> request) {
    const auto asked = protocol::read_mbap_frame(request);
    if (probed_ || !asked) return {};
    probed_ = true;
    auto hint = client::probe_units(framing(), asked->header.unit, [this](std::uint8_t unit) {
        // A fresh connection each time, so a late answer to an earlier request is not taken for
        // this one.
        close();
        std::array<std::uint8_t, protocol::limits::kMaxTcpAdu> probe{};
        const std::size_t size =
            protocol::write_adu({client::Framing::Mbap, unit}, client::kUnitProbePdu, probe);
        client::LinkError error;
        if (!send(std::span(probe).first(size), 1, error)) return false;
        const auto got = receive_frame(options_.timeout);
        const auto answer = protocol::read_mbap_frame(got.bytes);
        return got.status == client::ReceiveStatus::Frame && answer && answer->header.unit == unit;
    });
    close();
    return hint;
}

client::Received Session::receive_any(std::chrono::milliseconds timeout) {
    if (!link_) return {client::ReceiveStatus::Closed, {}, "connection closed"};
    auto got = link_->receive_any(timeout);
    if (!got.bytes.empty()) heard_ = true;
    return link_->framing() == client::Framing::Mbap ? got : in_case_notation(std::move(got));
}

std::optional<std::string> mbap_only_reason(const Session& session, bool pipelined, bool split,
                                            std::span<const std::uint8_t> request) {
    if (session.framing() == client::Framing::Mbap) return std::nullopt;
    const std::string& over = session.dut().serial_framing;
    if (pipelined) {
        return fmt::format("pipelined requests are a Modbus/TCP test; {} carries one at a time",
                           over);
    }
    if (split) return fmt::format("a request split over TCP segments cannot be sent over {}", over);
    protocol::Framer framer({client::Framing::Mbap});
    const auto plain = framer.whole_frame(request);
    if (!plain)
        return fmt::format("a Modbus/TCP header test ({}); not sent over {}", plain.error(), over);
    return std::nullopt;
}

}  // namespace mblab::conformance
