#pragma once

#include <sys/uio.h>

#include <array>
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/steady_timer.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "protocol/exception_code.hpp"
#include "protocol/frame_event.hpp"
#include "protocol/mbap_framer.hpp"
#include "server/reply_queue.hpp"
#include "server/server_core.hpp"
#include "transport/connection_table.hpp"
#include "transport/socket_poller.hpp"

namespace mblab::server {

// One Modbus/TCP connection. The socket is read when the server's SocketPoller says it has
// data; the reader frames requests and asks the device, and the answers go out in request order,
// written at once when they are ready (an answer a fault delays holds back those behind it, and
// what the socket does not take waits for it to drain). A watchdog handles the idle timeout and
// frames whose bytes stop arriving.
class TcpSession final : public std::enable_shared_from_this<TcpSession>,
                         public transport::TrackedConnection,
                         public transport::SocketPoller::Watcher {
  public:
    // Takes the socket's descriptor over from Asio.
    TcpSession(asio::ip::tcp::socket socket, std::shared_ptr<ServerCore> core);
    ~TcpSession();

    // Registers with the listener's connection table and the poller, and starts the watchdog.
    void start();

    transport::Standing standing(Clock::time_point now) const override;
    Clock::time_point last_activity() const override { return last_activity_; }
    void close() override;
    void on_ready(std::uint32_t events) override;

  private:
    // The start of an unfinished frame, for answering it once its wait runs out: the framer
    // holds its bytes, this remembers the header and the function code.
    struct PartialFrame {
        std::size_t bytes = 0;        // of the frame so far, header included
        Clock::time_point started{};  // its first byte, for ServerOptions::frame_limit
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

    void read_ready();
    // Frames and answers what was read; pauses reading while the answer queue is full. The
    // caller brings the watched events up to date (update_interest).
    void continue_reading();
    void resume_reading_soon();
    void on_end_of_input();
    // Which events the poller watches: input unless paused or finished, output while the socket
    // is full.
    void update_interest();
    asio::awaitable<void> watchdog_loop(std::shared_ptr<TcpSession> self);

    Progress process_input();
    bool must_pause(Clock::time_point now);
    void on_partial_bytes(std::span<const std::uint8_t> bytes, Clock::time_point now);
    void on_frame(const protocol::FrameEvent& frame, Clock::time_point now);
    void on_frame_error(const protocol::FrameEvent& frame, Clock::time_point started,
                        Clock::time_point now);
    // Writes the handler's reply into its slot.
    void fill(PendingReply& slot, const protocol::MbapHeader& request, const device::Reply& reply,
              std::span<const std::uint8_t> response, Clock::time_point now);
    // What a deferring handler calls; it brings the answer back to this session's thread.
    device::DeferredDone deferred_done(std::uint32_t ticket, const protocol::MbapHeader& request);
    void on_deferred(std::uint32_t ticket, const protocol::MbapHeader& request,
                     const device::Reply& reply, std::span<const std::uint8_t> pdu);
    bool has_partial() const { return framer_.has_partial() || partial_.overlong; }
    // Answers an unfinished frame 03 (when its function code came) and forgets it.
    void drop_partial(Clock::time_point now);
    // The unfinished frame's bytes stopped coming: answered, and the stream carries on.
    void on_partial_timeout(Clock::time_point now);
    // The unfinished frame is still coming after the frame limit: answered, then closed.
    void on_slow_frame(Clock::time_point now);
    void arm_partial_deadline(Clock::time_point now);
    // When the unfinished frame runs out of time: its gap or its frame limit, the earlier.
    Clock::time_point partial_wakeup() const;
    Clock::time_point idle_deadline() const;
    void queue_exception(const protocol::MbapHeader& header, std::uint8_t function,
                         protocol::ExceptionCode code, Clock::time_point now);
    // Stops reading; the answers already queued go out, then the connection closes.
    void close_after_answers(Clock::time_point now);
    // Writes the ready answers from the head until the socket is full or the head is not ready
    // (a delay fault arms the delay timer; an answer the handler still owes waits for it), then
    // closes if nothing more will come.
    void flush(Clock::time_point now);
    void arm_delay(Clock::time_point until);
    // The ready answers from the head (the head's unsent part first), at most out.size().
    std::size_t gather_ready(Clock::time_point now, std::span<iovec> out) const;
    // Drops the answers `written` bytes completed out of the first `count`.
    void consume_sent(std::size_t count, std::size_t written, Clock::time_point now);
    void shutdown_and_close();
    // Gives the connection's place in the listener's table back (once).
    void leave_table();
    // Stops watching the socket and closes it (once).
    void close_socket();

    asio::any_io_executor executor_;
    int fd_ = -1;
    std::shared_ptr<ServerCore> core_;
    asio::steady_timer delay_timer_;  // a fault delays the head answer
    Clock::time_point delay_until_{};
    asio::steady_timer watchdog_timer_;

    protocol::MbapFramer framer_;
    PartialFrame partial_;
    // What followed an overlong header (function code first), up to a PDU: that frame's body,
    // and perhaps requests sent after it.
    std::vector<std::uint8_t> overlong_body_;
    Clock::time_point partial_deadline_{};
    ReplyQueue replies_;
    std::size_t head_sent_ = 0;  // bytes of the head answer a partial write already sent
    Clock::time_point last_activity_;

    std::array<std::uint8_t, 1024> input_{};
    std::size_t input_begin_ = 0;
    std::size_t input_end_ = 0;

    bool closed_ = false;
    bool in_table_ = false;
    bool reading_ = true;  // false after EOF or a "close" fault
    bool reader_paused_ = false;
    bool resume_posted_ = false;
    bool write_blocked_ = false;     // the socket took less than it was given
    std::uint32_t last_ticket_ = 0;  // of the last request given to the handler
};

}  // namespace mblab::server
