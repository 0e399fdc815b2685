#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "device/request_handler.hpp"

// A device that breaks a rule on purpose: `rule` answers the requests it picks with a PDU of its
// own, and every other request goes to the device behind it.
namespace mblab::test {

class RewritingHandler : public device::RequestHandler {
  public:
    using Rule = std::function<std::optional<std::vector<std::uint8_t>>(
        std::span<const std::uint8_t> request)>;
    RewritingHandler(device::RequestHandler& inner, Rule rule)
        : inner_(inner), rule_(std::move(rule)) {}
    device::Reply handle(const device::RequestContext& context,
                         std::span<const std::uint8_t> request,
                         std::span<std::uint8_t> response) override {
        if (auto answer = rule_(request)) {
            std::copy(answer->begin(), answer->end(), response.begin());
            return {device::ReplyAction::Answer, answer->size(), {}};
        }
        return inner_.handle(context, request, response);
    }

  private:
    device::RequestHandler& inner_;
    Rule rule_;
};

}  // namespace mblab::test
