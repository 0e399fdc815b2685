#pragma once

#include <array>
#include <asio/awaitable.hpp>
#include <asio/buffer.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/steady_timer.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "protocol/exception_code.hpp"
#include "protocol/frame_event.hpp"
#include "protocol/mbap_framer.hpp"
#include "server/reply_queue.hpp"
#include "server/server_core.hpp"
#include "transport/connection_table.hpp"

namespace mblab::server {

// One Modbus/TCP connection: a reader that frames requests and asks the device, a writer that
// sends the answers in request order (holding back answers a fault delays), and a watchdog for
// the idle timeout and for frames whose bytes stop arriving.
class TcpSession final : public std::enable_shared_from_this<TcpSession>,
                         public transport::TrackedConnection {
  public:
    TcpSession(asio::ip::tcp::socket socket, std::shared_ptr<ServerCore> core);
    ~TcpSession();

    // Registers with the listener's connection table and spawns the three coroutines.
    void start();

    bool idle() const override;
    Clock::time_point last_activity() const override { return last_activity_; }
    void close() override;

  private:
    // The start of an unfinished frame, for answering it once its wait runs out: the framer
    // holds its bytes, this remembers the header and the function code.
    struct PartialFrame {
        std::size_t bytes = 0;  // of the frame so far, header included
        std::optional<protocol::MbapHeader> header;
        std::optional<std::uint8_t> function;
        // An MBAP length over 254 declares more than a frame may hold: its body is skipped
        // here (the framer has given up on it) until the wait runs out or the body really
        // exceeds a PDU.
        bool overlong = false;
        std::size_t skipped = 0;
    };
    enum class Progress : std::uint8_t { Consumed, Paused, Stopped };
    static constexpr std::size_t kMaxGather = 32;  // answers sent in one gathered write

    // The reader runs on plain completion handlers, the per-request path; the writer and the
    // watchdog are coroutines. Each holds `self` so the session lives until the last ends.
    void read_some();
    void on_read(const asio::error_code& ec, std::size_t n);
    // Frames and answers what was read, then reads again, or waits for the writer to make room.
    void continue_reading();
    void on_end_of_input();
    asio::awaitable<void> write_loop(std::shared_ptr<TcpSession> self);
    asio::awaitable<void> watchdog_loop(std::shared_ptr<TcpSession> self);

    Progress process_input();
    bool must_pause(Clock::time_point now);
    void on_partial_bytes(std::span<const std::uint8_t> bytes, Clock::time_point now);
    void on_frame(const protocol::FrameEvent& frame, Clock::time_point now);
    void on_frame_error(const protocol::FrameEvent& frame, Clock::time_point now);
    // Writes the handler's reply into its slot.
    void fill(PendingReply& slot, const protocol::MbapHeader& request, const device::Reply& reply,
              std::span<const std::uint8_t> response, Clock::time_point now);
    // What a deferring handler calls; it brings the answer back to this session's thread.
    device::DeferredDone deferred_done(std::uint32_t ticket, const protocol::MbapHeader& request);
    void on_deferred(std::uint32_t ticket, const protocol::MbapHeader& request,
                     const device::Reply& reply, std::span<const std::uint8_t> pdu);
    void on_partial_timeout(Clock::time_point now);
    void arm_partial_deadline(Clock::time_point now);
    Clock::time_point idle_deadline() const;
    void queue_exception(const protocol::MbapHeader& header, std::uint8_t function,
                         protocol::ExceptionCode code, Clock::time_point now);
    // Stops reading; the answers already queued go out, then the connection closes.
    void close_after_answers(Clock::time_point now);
    void wake_writer();
    // After a batch of requests: when the writer is idle and every answer is ready, write them
    // at once without blocking (saving the writer's wake-up); otherwise, or for what the socket
    // did not take, wake the writer.
    void send_now_or_wake_writer(Clock::time_point now);
    // The ready answers from the head (the head's unsent part first), at most out.size().
    std::size_t gather_ready(Clock::time_point now, std::span<asio::const_buffer> out) const;
    // Drops the answers `written` bytes completed out of the first `count`.
    void consume_sent(std::size_t count, std::size_t written, Clock::time_point now);
    void shutdown_and_close();

    asio::ip::tcp::socket socket_;
    std::shared_ptr<ServerCore> core_;
    asio::steady_timer writer_timer_;  // new answers, and fault delays
    asio::steady_timer reader_timer_;  // the writer made room in a full queue
    asio::steady_timer watchdog_timer_;

    protocol::MbapFramer framer_;
    PartialFrame partial_;
    Clock::time_point partial_deadline_{};
    ReplyQueue replies_;
    std::size_t head_sent_ = 0;  // bytes of the head answer a partial write already sent
    Clock::time_point last_activity_;

    std::array<std::uint8_t, 1024> input_{};
    std::size_t input_begin_ = 0;
    std::size_t input_end_ = 0;

    bool closed_ = false;
    bool reading_ = true;          // false after EOF or a "close" fault
    bool writer_waiting_ = false;  // for work, not for a delay
    bool reader_paused_ = false;
    std::uint32_t last_ticket_ = 0;  // of the last request given to the handler
};

}  // namespace mblab::server
