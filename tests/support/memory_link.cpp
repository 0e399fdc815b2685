#include "support/memory_link.hpp"

#include <algorithm>
#include <array>
#include <deque>
#include <optional>

#include "client/frame_reader.hpp"
#include "protocol/adu.hpp"
#include "support/hex.hpp"

namespace mblab::test {

namespace {

using protocol::Framing;

// The silence that ends an RTU frame whose layout does not give its length: t3.5 at 19200 baud.
constexpr std::chrono::microseconds kSilence{1750};
// Bytes reach a framer a socket read's worth at a time, as over a descriptor: a framer keeps
// what it has not cut in one buffer, and a flood of megabytes in one piece would be moved
// through it once per frame.
constexpr std::size_t kChunk = 1024;

}  // namespace

class MemoryLink final : public client::Link {
  public:
    explicit MemoryLink(MemoryDevice& device)
        : device_(device),
          name_("memory://" + std::to_string(device.opened_)),
          requests_({.framing = device.framing_, .direction = protocol::Direction::Request}),
          answers_({.framing = device.framing_,
                    .direction = protocol::Direction::Response,
                    .lenient = device.framing_ == Framing::Mbap}) {}

    Framing framing() const override { return device_.framing_; }
    const std::string& name() const override { return name_; }
    bool is_open() const override { return open_; }

    bool send(std::span<const std::uint8_t> adu, client::LinkError& error) override {
        if (!open_) {
            error.message = "closed";
            return false;
        }
        end_silent_frame();
        last_byte_ = device_.clock_.now();
        for (std::size_t at = 0; at < adu.size() && open_; at += kChunk) {
            requests_.add(adu.subspan(at, std::min(kChunk, adu.size() - at)));
            while (open_) {
                auto request = requests_.next();
                if (!request) break;
                take(*request);
            }
        }
        return true;
    }

    client::Received receive_frame(std::chrono::milliseconds timeout) override {
        if (auto frame = next_answer()) return *frame;
        if (!open_) return {client::ReceiveStatus::Closed, {}, "closed by the device"};
        // Silence: a request the device was waiting on ends, and may be answered.
        const std::chrono::steady_clock::duration silence =
            std::min<std::chrono::steady_clock::duration>(kSilence, timeout);
        device_.clock_.advance(silence);
        end_silent_frame();
        if (auto frame = next_answer()) return *frame;
        device_.clock_.advance(timeout - silence);
        return {client::ReceiveStatus::Timeout};
    }

    // Whatever came, as a frame on a line, as bytes over MBAP.
    client::Received receive_any(std::chrono::milliseconds timeout) override {
        if (device_.framing_ != Framing::Mbap) return receive_frame(timeout);
        auto out = answers_.take(client::ReceiveStatus::Timeout);
        for (; !bursts_.empty(); bursts_.pop_front(), read_ = 0) {
            const auto& burst = bursts_.front();
            out.bytes.insert(out.bytes.end(), burst.begin() + static_cast<long>(read_),
                             burst.end());
        }
        if (out.bytes.empty()) device_.clock_.advance(timeout);
        if (!open_) out.status = client::ReceiveStatus::Closed;
        return out;
    }

    void close() override { open_ = false; }

  private:
    friend class MemoryDevice;

    void take(const client::Received& request) {
        device_.serve(*this, request);
        if (request.status != client::ReceiveStatus::Frame && device_.framing_ == Framing::Mbap) {
            // A header that describes no frame: where the next one starts is unknown.
            open_ = false;
        }
    }

    void end_silent_frame() {
        if (device_.framing_ != Framing::Rtu || !requests_.has_partial()) return;
        if (device_.clock_.now() - last_byte_ < kSilence) return;
        if (auto request = requests_.on_silence()) take(*request);
    }

    std::optional<client::Received> next_answer() {
        while (true) {
            if (auto frame = answers_.next()) return frame;
            if (bursts_.empty()) return std::nullopt;
            const auto& burst = bursts_.front();
            if (read_ < burst.size()) {
                const std::size_t n = std::min(kChunk, burst.size() - read_);
                answers_.add(std::span(burst).subspan(read_, n));
                read_ += n;
                continue;
            }
            // Each answer is followed by silence, which ends a frame whose layout does not give
            // its length (an FC 08 echo on RTU).
            bursts_.pop_front();
            read_ = 0;
            if (answers_.has_partial()) {
                if (auto frame = answers_.on_silence()) return frame;
            }
        }
    }

    MemoryDevice& device_;
    std::string name_;
    client::FrameReader requests_;                  // the device's side
    client::FrameReader answers_;                   // the client's side
    std::deque<std::vector<std::uint8_t>> bursts_;  // answers not read, each as the device sent it
    std::size_t read_ = 0;                          // of the first burst
    ManualClock::time_point last_byte_{};
    bool open_ = true;
};

MemoryDevice::MemoryDevice(device::RequestHandler& handler, Framing framing, ManualClock& clock)
    : handler_(handler), framing_(framing), clock_(clock) {}

std::unique_ptr<client::Link> MemoryDevice::open() {
    ++opened_;
    return std::make_unique<MemoryLink>(*this);
}

void MemoryDevice::serve(MemoryLink& link, const client::Received& request) {
    requests_.push_back(to_hex(request.bytes));
    if (!dead_ && kills_ && kills_(request)) dead_ = true;
    if (dead_ || request.status != client::ReceiveStatus::Frame) return;
    std::array<std::uint8_t, 260> response{};
    const device::RequestContext context{
        request.header.unit, framing_ == Framing::Mbap ? device::Link::Tcp : device::Link::Serial};
    const auto reply = handler_.handle(context, request.pdu, response);
    if (reply.action == device::ReplyAction::Close) link.open_ = false;
    if (reply.action != device::ReplyAction::Answer) return;
    const std::span<const std::uint8_t> pdu(response.data(), reply.size);
    std::vector<std::uint8_t> answer(protocol::adu_size(framing_, pdu.size()));
    answer.resize(protocol::write_adu(request.header, pdu, answer));
    link.bursts_.push_back(std::move(answer));
}

}  // namespace mblab::test
