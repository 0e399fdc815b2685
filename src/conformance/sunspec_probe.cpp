#include "conformance/sunspec_probe.hpp"

#include <fmt/core.h>

#include <array>
#include <thread>

#include "device/profile_paths.hpp"
#include "device/sunspec_loader.hpp"
#include "protocol/limits.hpp"
#include "protocol/mbap_header.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"

namespace mblab::conformance {

namespace {

constexpr std::uint8_t kBroadcast = 0;
constexpr int kBusyAttempts = 5;
constexpr std::chrono::milliseconds kBusyPause{50};

client::ClientError error(client::ErrorKind kind, std::string message) {
    return {kind, std::move(message), std::nullopt};
}

// Register addresses end at 0xFFFF ([APP] 4.4): a model chain that runs past it cannot be read
// there, and sending the address cut to 16 bits would read somewhere else.
std::optional<client::ClientError> past_last_address(std::uint32_t address, std::size_t count) {
    if (address + count <= 0x10000) return std::nullopt;
    return error(client::ErrorKind::Invalid,
                 fmt::format("registers {} to {} run past the last address, 65535", address,
                             address + count - 1));
}

// The answer decoded by the codec's strict rules, and of the kind asked for.
template <class Answer>
client::CallResult<Answer> decode_answer(std::span<const std::uint8_t> pdu) {
    auto decoded = protocol::decode_response(pdu);
    if (!decoded) {
        return error(
            client::ErrorKind::BadAnswer,
            fmt::format("bad answer: {}: {}", decoded.error().field, decoded.error().reason));
    }
    if (const auto* answer = std::get_if<Answer>(&*decoded)) return *answer;
    return error(client::ErrorKind::BadAnswer, "an answer of another kind than the request's");
}

}  // namespace

SunSpecProbe::SunSpecProbe(Session& session) : session_(session) {
    auto models = device::read_sunspec_models(device::sunspec_models_dir());
    if (!models) {
        unusable_ = Outcome{Verdict::NotApplicable, models.error(), {}};
        return;
    }
    models_ = std::move(models).value();
    client::LinkError link_error;
    if (!session_.connect(link_error)) {
        unusable_ = Outcome{Verdict::Fail, "cannot reach the device: " + link_error.message, {}};
        return;
    }
    auto scan = scan_sunspec(
        [this](std::uint16_t address, std::uint16_t count) { return read(address, count); },
        models_);
    if (!scan) {
        // No marker at any base: no SunSpec device, which the suite does not apply to.
        const bool no_marker = scan.error().starts_with("no SunSpec marker");
        unusable_ =
            no_marker ? Outcome{Verdict::NotApplicable, scan.error(), {}} : fail(scan.error());
        return;
    }
    scan_ = std::move(scan).value();
}

client::CallResult<std::vector<std::uint8_t>> SunSpecProbe::ask(
    const std::vector<std::uint8_t>& pdu, std::optional<std::chrono::milliseconds> quiet) {
    // Exception 06 asks the client to send the request again later ([APP] 7): a busy device is
    // asked again, a little later each time, before its answer counts.
    for (int attempt = 1;; ++attempt) {
        auto answer = ask_once(pdu, quiet);
        if (answer || answer.error().exception != protocol::ExceptionCode::ServerDeviceBusy ||
            attempt == kBusyAttempts) {
            return answer;
        }
        std::this_thread::sleep_for(kBusyPause * attempt);
    }
}

client::CallResult<std::vector<std::uint8_t>> SunSpecProbe::ask_once(
    const std::vector<std::uint8_t>& pdu, std::optional<std::chrono::milliseconds> quiet) {
    const protocol::AduHeader header{protocol::Framing::Mbap,
                                     quiet ? kBroadcast : session_.dut().unit, ++transaction_};
    std::vector<std::uint8_t> frame(protocol::adu_size(protocol::Framing::Mbap, pdu.size()));
    protocol::write_adu(header, pdu, frame);
    Exchange exchange;
    exchange.sent = frame;
    client::LinkError link_error;
    if (!session_.send(frame, 1, link_error)) {
        exchange.status = client::ReceiveStatus::Closed;
        exchange.detail = link_error.message;
        last_ = exchange;
        return error(client::ErrorKind::Closed, "sending: " + link_error.message);
    }
    const auto received = session_.receive_frame(quiet.value_or(session_.options().timeout));
    exchange.status = received.status;
    exchange.received = received.bytes;
    exchange.detail = received.detail;
    exchange.silence_expected = quiet.has_value();
    last_ = exchange;
    if (quiet) {
        if (received.status == client::ReceiveStatus::Timeout) return std::vector<std::uint8_t>{};
        return error(client::ErrorKind::BadAnswer, "a broadcast was answered");
    }
    const auto adu = received.status == client::ReceiveStatus::Frame
                         ? protocol::read_mbap_frame(received.bytes)
                         : std::nullopt;
    if (!adu || adu->pdu.empty()) {
        return error(client::ErrorKind::Timeout,
                     received.detail.empty() ? "no answer" : received.detail);
    }
    std::vector<std::uint8_t> answer(adu->pdu.begin(), adu->pdu.end());
    if ((answer[0] & 0x7F) != pdu[0]) {
        return error(
            client::ErrorKind::BadAnswer,
            fmt::format("answer of function {:02X} to function {:02X}", answer[0], pdu[0]));
    }
    if (answer[0] & 0x80) {
        const auto code = static_cast<protocol::ExceptionCode>(answer.size() > 1 ? answer[1] : 0);
        return client::ClientError{client::ErrorKind::Exception,
                                   fmt::format("exception {:02X}", static_cast<int>(code)), code};
    }
    return answer;
}

client::CallResult<std::vector<std::uint16_t>> SunSpecProbe::read(std::uint32_t address,
                                                                  std::uint16_t count) {
    if (const auto refused = past_last_address(address, count)) return *refused;
    auto answer = ask(protocol::encoded_pdu(protocol::ReadRegistersRequest{
        protocol::FunctionCode::ReadHoldingRegisters, static_cast<std::uint16_t>(address), count}));
    if (!answer) return answer.error();
    auto decoded = decode_answer<protocol::ReadRegistersResponse>(*answer);
    if (!decoded) return decoded.error();
    if (decoded->values.size() != count) {
        return error(client::ErrorKind::BadAnswer,
                     fmt::format("{} registers asked, {} answered", count, decoded->values.size()));
    }
    std::vector<std::uint16_t> words(count);
    for (std::size_t i = 0; i < count; ++i)
        words[i] = decoded->values[i];
    return words;
}

client::CallResult<bool> SunSpecProbe::write(std::uint32_t address,
                                             std::span<const std::uint16_t> values,
                                             std::optional<std::chrono::milliseconds> quiet) {
    if (const auto refused = past_last_address(address, values.size())) return *refused;
    std::array<std::uint8_t, 2 * protocol::limits::kMaxWriteRegisters> bytes{};
    protocol::WriteCursor out(bytes);
    for (std::uint16_t value : values)
        out.put_u16(value);
    const auto quantity = static_cast<std::uint16_t>(values.size());
    const auto pdu = protocol::encoded_pdu(protocol::WriteMultipleRegistersRequest{
        static_cast<std::uint16_t>(address), quantity, protocol::RegisterView(out.written())});
    if (!out.ok() || pdu.empty()) {
        return error(client::ErrorKind::Invalid,
                     fmt::format("{} registers do not fit one write (at most {})", values.size(),
                                 protocol::limits::kMaxWriteRegisters));
    }
    auto answer = ask(pdu, quiet);
    if (!answer) return answer.error();
    if (quiet) return true;  // a broadcast: ask() has checked that nothing answered
    auto echo = decode_answer<protocol::WriteMultipleRegistersResponse>(*answer);
    if (!echo) return echo.error();
    if (echo->address != address || echo->quantity != quantity) {
        return error(client::ErrorKind::BadAnswer,
                     fmt::format("write of {} registers at {} answered as {} at {}", quantity,
                                 address, echo->quantity, echo->address));
    }
    return true;
}

std::vector<const SunSpecPointReading*> SunSpecProbe::points() const {
    std::vector<const SunSpecPointReading*> all;
    for (const SunSpecModelReading& model : scan_.models) {
        for (const SunSpecPointReading& point : model.points)
            all.push_back(&point);
    }
    return all;
}

Outcome SunSpecProbe::fail(std::string reason) const {
    Outcome outcome{Verdict::Fail, std::move(reason), {}};
    if (last_) outcome.evidence.push_back(*last_);
    return outcome;
}

Outcome SunSpecProbe::fail(const client::ClientError& why, const std::string& what) const {
    return fail(what + ": " + why.message);
}

std::string point_name(std::uint16_t model, const SunSpecPointReading& point) {
    return fmt::format("{}.{}{}", model, point.group.empty() ? "" : point.group + ".",
                       point.point->name);
}

}  // namespace mblab::conformance
