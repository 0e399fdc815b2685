#include "robustness/storm_ladder.hpp"

#include <fmt/core.h>

#include <thread>

#include "robustness/fuzz_case.hpp"
#include "support/comma_list.hpp"

namespace mblab::robustness {

LadderRung storm(const client::Dial& dial, std::uint8_t unit, std::uint16_t address, double rate,
                 std::chrono::milliseconds duration) {
    LadderRung rung;
    rung.rate = rate;
    rung.begin = Clock::now();
    const auto until = rung.begin + duration;
    const std::vector<std::uint8_t> pdu = {0x03, static_cast<std::uint8_t>(address >> 8),
                                           static_cast<std::uint8_t>(address), 0x00, 0x01};
    std::unique_ptr<client::Link> link;
    std::uint16_t transaction = 0;
    auto last_open = Clock::time_point{};
    while (Clock::now() < until) {
        const auto now = Clock::now();
        if (!link && now - last_open >= std::chrono::milliseconds(100)) {
            // A device that closes the storm's connection gets another, at most ten a second.
            last_open = now;
            if (auto opened = dial()) {
                link = std::move(opened.value());
                rung.reconnects += rung.sent > 0 ? 1 : 0;
            }
        }
        // Every request due by now, in one go: the pace holds at rates above a thousand a second.
        const auto elapsed = std::chrono::duration<double>(now - rung.begin).count();
        const auto due = static_cast<std::size_t>(rate * elapsed);
        client::LinkError error;
        while (link && rung.sent < due) {
            if (!link->send(mbap_frame(++transaction, unit, pdu), error)) {
                link.reset();
                break;
            }
            ++rung.sent;
        }
        while (link && link->is_open()) {
            const auto answer = link->next_frame(std::chrono::milliseconds(0));
            if (answer.status == client::ReceiveStatus::Frame) {
                ++rung.answered;
                continue;
            }
            if (answer.status == client::ReceiveStatus::Closed) link.reset();
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    rung.end = Clock::now();
    return rung;
}

protocol::Result<std::vector<double>, std::string> parse_rates(const std::string& text) {
    std::vector<double> rates;
    for (const auto& item : comma_items(text)) {
        double rate = 0;
        try {
            std::size_t used = 0;
            rate = std::stod(item, &used);
            if (used != item.size()) rate = 0;
        } catch (const std::exception&) {
            rate = 0;
        }
        if (rate <= 0 || (!rates.empty() && rate <= rates.back()))
            return fmt::format(
                "--ladder '{}': give rising request rates per second, e.g. "
                "100,500,1000",
                text);
        rates.push_back(rate);
    }
    if (rates.empty()) return fmt::format("--ladder '{}': no rate", text);
    return rates;
}

}  // namespace mblab::robustness
