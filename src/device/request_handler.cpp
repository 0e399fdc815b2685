#include "device/request_handler.hpp"

#include <algorithm>
#include <future>
#include <vector>

namespace mblab::device {

namespace {

// Hands out a function that fulfils a promise with the deferred answer.
class WaitingDeferral final : public Deferral {
  public:
    using Answer = std::pair<Reply, std::vector<std::uint8_t>>;

    DeferredDone take() override {
        return [this](const Reply& reply, std::span<const std::uint8_t> pdu) {
            answer_.set_value({reply, std::vector<std::uint8_t>(pdu.begin(), pdu.end())});
        };
    }
    Answer wait() { return answer_.get_future().get(); }

  private:
    std::promise<Answer> answer_;
};

}  // namespace

Reply DeferringHandler::handle(const RequestContext& context, std::span<const std::uint8_t> request,
                               std::span<std::uint8_t> response) {
    WaitingDeferral deferral;
    if (auto reply = handle_or_defer(context, request, response, deferral)) return *reply;
    auto [reply, pdu] = deferral.wait();
    reply.size = std::min({reply.size, pdu.size(), response.size()});
    std::copy_n(pdu.begin(), reply.size, response.begin());
    return reply;
}

}  // namespace mblab::device
