#include "server/journaled_device.hpp"

#include <future>
#include <vector>

#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"

namespace mblab::server {

namespace {

// The answer for a write that could not be made durable.
void device_failure(std::uint8_t function, device::Reply& reply, std::span<std::uint8_t> response) {
    response[0] = static_cast<std::uint8_t>(function | protocol::kExceptionBit);
    response[1] = static_cast<std::uint8_t>(protocol::ExceptionCode::ServerDeviceFailure);
    reply.size = 2;
}

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

}  // namespace

std::string journal_record(const device::RequestContext& context,
                           std::span<const std::uint8_t> request) {
    static constexpr char kDigits[] = "0123456789ABCDEF";
    std::string line = std::to_string(context.unit);
    line += context.link == device::Link::Serial ? " S " : " T ";
    for (auto byte : request) {
        line += kDigits[byte >> 4];
        line += kDigits[byte & 0x0F];
    }
    return line;
}

bool parse_journal_record(const std::string& line, device::RequestContext& context,
                          std::vector<std::uint8_t>& request) {
    const auto first = line.find(' ');
    if (first == std::string::npos || first == 0 || first > 3 || line.size() < first + 3 ||
        line[first + 2] != ' ') {
        return false;
    }
    unsigned unit = 0;
    for (std::size_t i = 0; i < first; ++i) {
        if (line[i] < '0' || line[i] > '9') return false;
        unit = unit * 10 + static_cast<unsigned>(line[i] - '0');
    }
    const char link = line[first + 1];
    if (unit > 255 || (link != 'T' && link != 'S')) return false;
    const auto hex = std::string_view(line).substr(first + 3);
    if (hex.empty() || hex.size() % 2 != 0) return false;
    request.clear();
    for (std::size_t i = 0; i < hex.size(); i += 2) {
        const int high = hex_digit(hex[i]);
        const int low = hex_digit(hex[i + 1]);
        if (high < 0 || low < 0) return false;
        request.push_back(static_cast<std::uint8_t>(high * 16 + low));
    }
    context.unit = static_cast<std::uint8_t>(unit);
    context.link = link == 'S' ? device::Link::Serial : device::Link::Tcp;
    return true;
}

device::Reply JournaledDevice::handle(const device::RequestContext& context,
                                      std::span<const std::uint8_t> request,
                                      std::span<std::uint8_t> response) {
    const auto before = device_.state_writes();
    auto reply = device_.handle(context, request, response);
    if (device_.state_writes() == before) return reply;
    std::promise<bool> written;
    journal_.append(journal_record(context, request),
                    [&written](bool ok) { written.set_value(ok); });
    if (!written.get_future().get() && reply.action == device::ReplyAction::Answer) {
        device_failure(request[0], reply, response);
    }
    return reply;
}

std::optional<device::Reply> JournaledDevice::handle_or_defer(const device::RequestContext& context,
                                                              std::span<const std::uint8_t> request,
                                                              std::span<std::uint8_t> response,
                                                              device::Deferral& deferral) {
    const auto before = device_.state_writes();
    auto reply = device_.handle(context, request, response);
    if (device_.state_writes() == before) return reply;
    if (reply.action != device::ReplyAction::Answer) {
        // Nothing acknowledges this write (a broadcast, a fault): record it, hold nothing back.
        journal_.append(journal_record(context, request), {});
        return reply;
    }
    auto answer = std::vector<std::uint8_t>(response.begin(), response.begin() + reply.size);
    journal_.append(journal_record(context, request),
                    [done = deferral.take(), reply, answer = std::move(answer),
                     function = request[0]](bool written) mutable {
                        if (!written) {
                            answer.resize(2);
                            device_failure(function, reply, answer);
                        }
                        done(reply, answer);
                    });
    return std::nullopt;
}

}  // namespace mblab::server
