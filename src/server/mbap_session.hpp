#pragma once

#include <sys/uio.h>

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "device/request_handler.hpp"
#include "device/role_rules.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/frame_event.hpp"
#include "protocol/framer.hpp"
#include "server/reply_queue.hpp"
#include "server/server_stats.hpp"
#include "server/unfinished_mbap_frame.hpp"
#include "transport/connection_table.hpp"

// The protocol of one Modbus/TCP server connection without I/O: bytes and the clock in, answers
// in request order and what to do with the connection out. The owner reads the socket into
// input_space(), sends what output() gathers and says how much the socket took, wakes the session
// at deadline(), and closes when ending() says so; tests drive it with a manual clock.
namespace mblab::server {

// What a session takes from ServerOptions (whose allow list brings Asio in).
struct MbapSessionLimits {
    std::chrono::milliseconds idle_timeout{60'000};
    std::chrono::milliseconds partial_frame_timeout{250};
    std::chrono::milliseconds frame_limit{1000};
    std::size_t max_outstanding = 16;
};

class MbapSession {
  public:
    // What the session needs from its owner besides bytes and time.
    class Host {
      public:
        // A handler defers the answer with this ticket: the function it gets must bring the
        // answer back to the session's thread, as answer_deferred().
        virtual device::DeferredDone route_deferred(std::uint32_t ticket,
                                                    const protocol::MbapHeader& request) = 0;
        // The session answered a request itself, not the handler: 06 past the outstanding
        // limit, 01 for a request the client's role may not make, 03 for a frame that stopped
        // coming (`request` then holds only its function code, all that came of the PDU).
        virtual void on_own_answer(const device::RequestContext& context,
                                   std::span<const std::uint8_t> request,
                                   protocol::ExceptionCode code) = 0;

      protected:
        ~Host() = default;
    };

    enum class Ending : std::uint8_t {
        Open,
        // Every answer that will come is out: shut the sending side, then close.
        AfterAnswers,
        Now,  // the idle timeout: close without waiting for anything
    };

    static constexpr std::size_t kMaxGather = 32;  // answers output() gathers at most
    static constexpr std::size_t kInputBytes = 1024;

    MbapSession(device::RequestHandler& handler, const MbapSessionLimits& limits,
                ServerStats& stats, Host& host, Clock::time_point now);
    MbapSession(const MbapSession&) = delete;
    MbapSession& operator=(const MbapSession&) = delete;

    // Whether to read: not while the answers queued are at their limit (the client must take
    // some first), nor after the end of input or a frame that ends the connection.
    bool wants_input() const { return !stopped_ && !eof_ && input_begin_ == input_end_; }
    // Where to read into, while wants_input().
    std::span<std::uint8_t> input_space() { return input_; }
    // `count` bytes were read into input_space() at `now`.
    void received(std::size_t count, Clock::time_point now);
    // Copies `bytes` (at most kInputBytes) in and takes them, for owners without a buffer.
    void receive(std::span<const std::uint8_t> bytes, Clock::time_point now);
    // The client will send nothing more: an unfinished frame is answered, as its wait would.
    void end_of_input(Clock::time_point now);

    // The answers ready to go from the head, the unsent part of a partly sent one first; at most
    // out.size() (kMaxGather is plenty). 0 when none is ready: see ending() then.
    std::size_t output(Clock::time_point now, std::span<iovec> out);
    // The socket took `bytes` of what the last output() gathered.
    void sent(std::size_t bytes, Clock::time_point now);
    // Whether to close, once output() has nothing to give.
    Ending ending(Clock::time_point now) const;

    // When on_time() has something to do; time_point::max() when nothing waits. It may come
    // early: on_time() then does nothing.
    Clock::time_point deadline() const;
    void on_time(Clock::time_point now);

    // The answer a deferring handler owed for `ticket`, on the session's thread.
    void answer_deferred(std::uint32_t ticket, const protocol::MbapHeader& request,
                         const device::Reply& reply, std::span<const std::uint8_t> pdu,
                         Clock::time_point now);

    // Modbus/TCP Security: from now on each request is checked against `rules` for `role` (none:
    // the certificate named no role) and answered 01 when its role may not make it. `rules`
    // must outlive the session.
    void authorize(const device::RoleRules& rules, std::optional<std::string> role) {
        rules_ = &rules;
        role_ = std::move(role);
    }

    // The client's address, handed to the handler with each request (RequestContext::peer).
    void set_peer(std::string peer) { peer_ = std::move(peer); }

    // For a full listener choosing a connection to close.
    transport::Standing standing(Clock::time_point now) const;
    // The last complete request or answer sent.
    Clock::time_point last_activity() const { return last_activity_; }
    bool has_partial() const { return framer_.has_partial() || unfinished_.overlong(); }
    std::size_t answers_queued() const { return replies_.size(); }

  private:
    // Frames and answers the input until it is used up or the answer queue is full.
    void process_input(Clock::time_point now);
    bool must_pause(Clock::time_point now) const;
    void on_frame(const protocol::FrameEvent& frame, Clock::time_point now);
    void on_frame_error(const protocol::FrameEvent& frame, Clock::time_point started,
                        Clock::time_point now);
    // Writes the handler's reply into its slot.
    void fill(PendingReply& slot, const protocol::MbapHeader& request, const device::Reply& reply,
              std::span<const std::uint8_t> response, Clock::time_point now);
    // Answers `request` (its PDU, or as much as came) with `code`, and tells the host.
    void queue_exception(const protocol::MbapHeader& header, std::span<const std::uint8_t> request,
                         protocol::ExceptionCode code, Clock::time_point now);
    // The unfinished frame's bytes stopped coming: answered 03, and the stream carries on.
    void on_partial_timeout(Clock::time_point now);
    // The unfinished frame is still coming after the frame limit: answered, then closed.
    void on_slow_frame(Clock::time_point now);
    // Answers the unfinished frame 03 (when its function code came) and forgets it.
    void drop_partial(Clock::time_point now);
    // When the unfinished frame runs out of time: its gap or its frame limit, the earlier.
    Clock::time_point partial_wakeup() const;
    Clock::time_point idle_deadline() const;
    // No more input is read; the answers queued go out, then the connection closes.
    void close_after_answers(Clock::time_point now);
    // The input after the end of input is framed: the last unfinished frame is answered.
    void finish_input(Clock::time_point now);

    device::RequestHandler& handler_;
    MbapSessionLimits limits_;
    ServerStats& stats_;
    Host& host_;

    protocol::Framer framer_{{.framing = protocol::Framing::Mbap}};
    UnfinishedMbapFrame unfinished_;
    Clock::time_point partial_deadline_{};  // when the unfinished frame's gap runs out
    ReplyQueue replies_;
    std::size_t head_sent_ = 0;  // bytes of the head answer a partial write already sent
    std::size_t gathered_ = 0;   // answers the last output() gave
    Clock::time_point head_delay_ = Clock::time_point::max();  // a fault holds the head back
    Clock::time_point last_activity_;
    std::uint32_t last_ticket_ = 0;             // of the last request given to the handler
    const device::RoleRules* rules_ = nullptr;  // set: requests are authorized by role_
    std::optional<std::string> role_;
    std::string peer_;

    std::array<std::uint8_t, kInputBytes> input_{};
    std::size_t input_begin_ = 0;
    std::size_t input_end_ = 0;

    bool eof_ = false;              // the client finished sending
    bool carried_request_ = false;  // a whole request came: the connection is in use
    bool stopped_ = false;    // no more input is framed (after eof, a "close" fault, a bad frame)
    bool close_now_ = false;  // the idle timeout ran out (or no room was left for a close)
};

}  // namespace mblab::server
