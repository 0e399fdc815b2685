#include "load/line_use.hpp"

#include <fmt/format.h>

#include "transport/serial_port.hpp"

namespace mblab::load {

std::optional<LineUse> line_use(const transport::SerialUrl& url, std::uint64_t chars,
                                std::uint64_t frames, std::chrono::microseconds elapsed) {
    if (url.kind == transport::SerialUrl::Kind::RtuOverTcp || chars == 0 || elapsed.count() <= 0)
        return std::nullopt;
    using Seconds = std::chrono::duration<double>;
    const double char_time = Seconds(transport::character_time(url.line)).count();
    const double silence = url.kind == transport::SerialUrl::Kind::Rtu
                               ? Seconds(transport::rtu_char_times(url.line.baud).t35).count()
                               : 0.0;
    const double busy =
        static_cast<double>(chars) * char_time + static_cast<double>(frames) * silence;
    LineUse use;
    use.chars_per_second = static_cast<double>(chars) / Seconds(elapsed).count();
    use.limit_per_second = static_cast<double>(chars) / busy;
    use.share = use.chars_per_second / use.limit_per_second;
    use.logical = transport::is_pseudo_terminal(url.line.device);
    return use;
}

std::string line_use_text(const transport::SerialUrl& url, const LineUse& use) {
    std::string text =
        fmt::format("{:.0f} characters/s, {:.1f}% of the {:.0f}/s {} baud allows{}",
                    use.chars_per_second, 100.0 * use.share, use.limit_per_second, url.line.baud,
                    url.kind == transport::SerialUrl::Kind::Rtu ? " with t3.5 between frames" : "");
    if (use.logical && !url.paced) {
        text += " (a pty passes bytes on at once: pace=1 on both ends keeps a line's timing)";
    }
    return text;
}

}  // namespace mblab::load
