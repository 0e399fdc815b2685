#include "device/request_scope.hpp"

#include <algorithm>
#include <variant>

#include "protocol/function_table.hpp"

namespace mblab::device {

namespace {

template <class Message>
concept NamesAddress = requires(Message message) {
    message.address;
};
template <class Message>
concept NamesRange = NamesAddress<Message> && requires(Message message) {
    message.quantity;
};

}  // namespace

RequestScope scope_of(std::uint8_t function, const protocol::Result<protocol::Request>& decoded) {
    RequestScope scope;
    scope.function = function;
    const protocol::FunctionRow* row = protocol::find_function(function);
    if (!decoded || !row) return scope;
    const auto span = [&](std::uint32_t first, std::uint32_t count) {
        scope.has_addresses = true;
        scope.first = first;
        scope.last = first + (count ? count - 1 : 0);
    };
    const protocol::Request& request = decoded.value();
    switch (row->scope) {
        case protocol::AddressScope::None:
            break;
        case protocol::AddressScope::Range:
            std::visit(
                [&](const auto& r) {
                    if constexpr (NamesRange<decltype(r)>) span(r.address, r.quantity);
                },
                request);
            break;
        case protocol::AddressScope::Single:
            std::visit(
                [&](const auto& r) {
                    if constexpr (NamesAddress<decltype(r)>) span(r.address, 1);
                },
                request);
            break;
        case protocol::AddressScope::ReadWrite:
            if (const auto* r =
                    std::get_if<protocol::ReadWriteMultipleRegistersRequest>(&request)) {
                const std::uint32_t first = std::min(r->read_address, r->write_address);
                const std::uint32_t end = std::max<std::uint32_t>(
                    r->read_address + r->read_quantity, r->write_address + r->write_quantity);
                span(first, end - first);
            }
            break;
    }
    return scope;
}

}  // namespace mblab::device
