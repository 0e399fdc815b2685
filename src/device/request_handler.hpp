#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string_view>

// The seam between a server (any transport) and what answers requests: the reference device,
// a gateway, or a test double. Sans-I/O: the server owns sockets, timers and buffers.
namespace mblab::device {

enum class Link : std::uint8_t { Tcp, Serial };

struct RequestContext {
    std::uint8_t unit = 0;  // MBAP unit id or serial address
    Link link = Link::Tcp;
    // The client's address ("192.0.2.7:50312") where the link has one, for logs; it views the
    // server's text and is valid only during the call.
    std::string_view peer = {};
};

enum class ReplyAction : std::uint8_t {
    Answer,    // send the `size` bytes written to the output, after `delay`
    NoAnswer,  // send nothing (broadcast, listen-only, foreign address, fault "drop")
    Close,     // close the connection (fault "close")
};

struct Reply {
    ReplyAction action = ReplyAction::Answer;
    std::size_t size = 0;  // response PDU bytes written (random ones for fault "garbage")
    std::chrono::milliseconds delay{0};
};

// Called once with a deferred answer: the reply and the response PDU it describes.
using DeferredDone = std::function<void(const Reply& reply, std::span<const std::uint8_t> pdu)>;

// What a server lends handle_or_defer(): a handler that defers takes from it the function to
// call later. Only a handler that defers asks, so answering at once costs nothing extra.
class Deferral {
  public:
    virtual DeferredDone take() = 0;

  protected:
    ~Deferral() = default;
};

class RequestHandler {
  public:
    virtual ~RequestHandler() = default;
    // `request` is a whole request PDU (function code first). The response PDU is written to
    // `response`, which holds at least 253 bytes.
    virtual Reply handle(const RequestContext& context, std::span<const std::uint8_t> request,
                         std::span<std::uint8_t> response) = 0;

    // For servers that can let an answer wait without waiting themselves. A handler whose
    // answers take long (a gateway waiting on a serial line) takes `deferral`'s function,
    // returns nothing, and calls the function exactly once later, from a thread of its own
    // (`request` must be copied if it is needed then). By default the answer is given at once
    // by handle().
    virtual std::optional<Reply> handle_or_defer(const RequestContext& context,
                                                 std::span<const std::uint8_t> request,
                                                 std::span<std::uint8_t> response,
                                                 Deferral& deferral) {
        (void)deferral;
        return handle(context, request, response);
    }
};

// A handler that answers through handle_or_defer() alone. handle() lends it a deferral and, when
// it defers, waits for the answer and copies it into `response`: a caller that cannot let an
// answer wait (a serial line, one request at a time) gets the same answer, later.
class DeferringHandler : public RequestHandler {
  public:
    Reply handle(const RequestContext& context, std::span<const std::uint8_t> request,
                 std::span<std::uint8_t> response) final;
    std::optional<Reply> handle_or_defer(const RequestContext& context,
                                         std::span<const std::uint8_t> request,
                                         std::span<std::uint8_t> response,
                                         Deferral& deferral) override = 0;
};

// A decorator around another handler (counting, journaling): each request goes to `inner`
// unchanged unless the derived class overrides handle_or_defer(), which it does to act before
// and after the inner answer.
class ForwardingHandler : public DeferringHandler {
  public:
    explicit ForwardingHandler(RequestHandler& inner) : inner_(inner) {}

    std::optional<Reply> handle_or_defer(const RequestContext& context,
                                         std::span<const std::uint8_t> request,
                                         std::span<std::uint8_t> response,
                                         Deferral& deferral) override {
        return inner_.handle_or_defer(context, request, response, deferral);
    }

  protected:
    RequestHandler& inner() const { return inner_; }

  private:
    RequestHandler& inner_;
};

namespace detail {

// A deferral that hands the deferred reply to `seen` before passing it on.
template <class Seen>
class SeenDeferral final : public Deferral {
  public:
    SeenDeferral(Deferral& inner, const Seen& seen) : inner_(inner), seen_(seen) {}

    DeferredDone take() override {
        return [done = inner_.take(), seen = seen_](const Reply& reply,
                                                    std::span<const std::uint8_t> pdu) mutable {
            seen(reply, pdu);
            done(reply, pdu);
        };
    }

  private:
    Deferral& inner_;
    const Seen& seen_;
};

}  // namespace detail

// A decorator that watches replies (counting, logging) and passes them on unchanged.
// `watch.start(context, request)` is called as a request arrives; the callable it returns,
// `seen(reply, pdu)`, is called with inner's reply when it comes: at once, or when inner gives
// its deferred answer (a copy of it then waits in the deferred function).
template <class Watch>
class WatchingHandler final : public ForwardingHandler {
  public:
    template <class... WatchArgs>
    explicit WatchingHandler(RequestHandler& inner, WatchArgs&&... watch)
        : ForwardingHandler(inner), watch_{std::forward<WatchArgs>(watch)...} {}

    std::optional<Reply> handle_or_defer(const RequestContext& context,
                                         std::span<const std::uint8_t> request,
                                         std::span<std::uint8_t> response,
                                         Deferral& deferral) override {
        auto seen = watch_.start(context, request);
        detail::SeenDeferral<decltype(seen)> watched(deferral, seen);
        auto reply = inner().handle_or_defer(context, request, response, watched);
        if (reply) seen(*reply, response);
        return reply;
    }

  private:
    Watch watch_;
};

}  // namespace mblab::device
