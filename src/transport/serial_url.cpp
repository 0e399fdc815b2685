#include "transport/serial_url.hpp"

#include <algorithm>
#include <array>
#include <charconv>

#include "transport/bad_address.hpp"
#include "transport/tcp_url.hpp"

namespace mblab::transport {

namespace {

constexpr std::string_view kRtuScheme = "rtu://";
constexpr std::string_view kAsciiScheme = "ascii://";
constexpr std::string_view kRtuTcpScheme = "rtu+tcp://";
constexpr std::string_view kExpected =
    "expected rtu:///dev/ttyUSB0?baud=19200&parity=E&stop=1&data=8, ascii:///dev/... or "
    "rtu+tcp://HOST:PORT";

// Rates termios can set on Linux; others fail only when the port is opened, far from the typo.
constexpr std::array<unsigned, 21> kBaudRates = {
    300,    600,    1200,   1800,   2400,   4800,    9600,    19200,   38400,   57600,  115200,
    230400, 460800, 500000, 576000, 921600, 1000000, 1152000, 1500000, 2000000, 3000000};

std::string url_error(std::string_view url, std::string_view why) {
    return bad_address(url, why, kExpected);
}

bool parse_number(std::string_view text, unsigned& value) {
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return ec == std::errc{} && end == text.data() + text.size() && !text.empty();
}

bool equals_nocase(std::string_view a, std::string_view b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](char x, char y) {
        return (x | 0x20) == (y | 0x20);  // ASCII letters only, which is all we compare
    });
}

bool parse_parity(std::string_view text, Parity& parity) {
    if (equals_nocase(text, "N") || equals_nocase(text, "none")) {
        parity = Parity::None;
    } else if (equals_nocase(text, "E") || equals_nocase(text, "even")) {
        parity = Parity::Even;
    } else if (equals_nocase(text, "O") || equals_nocase(text, "odd")) {
        parity = Parity::Odd;
    } else {
        return false;
    }
    return true;
}

// "1-10,20" -> those unit ids.
bool parse_units(std::string_view text, std::bitset<256>& units) {
    units.reset();
    while (!text.empty()) {
        auto comma = text.find(',');
        auto item = text.substr(0, comma);
        text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
        auto dash = item.find('-');
        unsigned first = 0;
        unsigned last = 0;
        if (!parse_number(item.substr(0, dash), first)) return false;
        last = first;
        if (dash != std::string_view::npos && !parse_number(item.substr(dash + 1), last)) {
            return false;
        }
        if (first > last || last > 255) return false;
        for (unsigned id = first; id <= last; ++id)
            units.set(id);
    }
    return units.any();
}

// Applies one key=value of the query; returns the reason it is wrong, or "" when it is fine.
std::string_view apply_setting(std::string_view key, std::string_view value, SerialUrl& out) {
    unsigned number = 0;
    if (key == "baud") {
        if (!parse_number(value, number) ||
            std::find(kBaudRates.begin(), kBaudRates.end(), number) == kBaudRates.end()) {
            return "baud must be a standard rate such as 9600, 19200, 38400 or 115200";
        }
        out.line.baud = number;
    } else if (key == "data") {
        if (!parse_number(value, number) || (number != 7 && number != 8)) {
            return "data must be 7 or 8 (bits per character)";
        }
        out.line.data_bits = static_cast<std::uint8_t>(number);
    } else if (key == "parity") {
        if (!parse_parity(value, out.line.parity)) return "parity must be N, E or O";
    } else if (key == "stop") {
        if (!parse_number(value, number) || (number != 1 && number != 2)) {
            return "stop must be 1 or 2 (stop bits)";
        }
        out.line.stop_bits = static_cast<std::uint8_t>(number);
    } else if (key == "strict") {
        if (value != "0" && value != "1") return "strict must be 0 or 1";
        out.strict_timing = value == "1";
    } else if (key == "pace") {
        if (value != "0" && value != "1") return "pace must be 0 or 1";
        out.paced = value == "1";
    } else if (key == "timeout") {
        if (!parse_number(value, number) || number == 0 || number > 600'000) {
            return "timeout must be milliseconds from 1 to 600000";
        }
        out.response_timeout = std::chrono::milliseconds(number);
    } else if (key == "units") {
        if (!parse_units(value, out.units)) {
            return "units must list unit ids 0..255 like 1-10,20";
        }
    } else {
        return "unknown setting (known: baud, parity, stop, data, strict, pace, timeout, units)";
    }
    return {};
}

// Applies a query's KEY=VALUE&... in turn; `line_only` refuses what is not a line setting.
std::string_view apply_query(std::string_view query, SerialUrl& out, bool line_only) {
    while (!query.empty()) {
        auto amp = query.find('&');
        auto pair = query.substr(0, amp);
        query = amp == std::string_view::npos ? std::string_view{} : query.substr(amp + 1);
        auto eq = pair.find('=');
        if (eq == std::string_view::npos) return "settings are KEY=VALUE";
        const auto key = pair.substr(0, eq);
        if (line_only && key != "baud" && key != "parity" && key != "stop" && key != "data")
            return "a line setting is one of baud, parity, stop and data";
        auto why = apply_setting(key, pair.substr(eq + 1), out);
        if (!why.empty()) return why;
    }
    return {};
}

protocol::Result<SerialUrl, std::string> parse_line_url(std::string_view url, std::string_view rest,
                                                        SerialUrl out) {
    auto question = rest.find('?');
    auto path = rest.substr(0, question);
    if (path.empty() || path.front() != '/') {
        return url_error(url, "the device must be an absolute path such as /dev/ttyUSB0");
    }
    out.line.device = std::string(path);
    auto query =
        question == std::string_view::npos ? std::string_view{} : rest.substr(question + 1);
    if (const auto why = apply_query(query, out, false); !why.empty()) return url_error(url, why);
    if (out.kind == SerialUrl::Kind::Rtu && out.line.data_bits != 8) {
        return url_error(url, "RTU needs 8 data bits");
    }
    return out;
}

}  // namespace

std::optional<std::string> line_settings_error(std::string_view settings) {
    if (settings.empty()) return "no setting given";
    SerialUrl scratch;
    const auto why = apply_query(settings, scratch, true);
    if (why.empty()) return std::nullopt;
    return std::string(why);
}

SerialUrl with_line_settings(SerialUrl url, std::string_view settings) {
    apply_query(settings, url, true);
    return url;
}

bool is_serial_url(std::string_view url) {
    return url.starts_with("rtu:") || url.starts_with("ascii:") || url.starts_with("rtu+tcp:");
}

protocol::Result<SerialUrl, std::string> parse_serial_url(std::string_view url) {
    SerialUrl out;
    for (unsigned id = 1; id <= 247; ++id)
        out.units.set(id);
    if (url.starts_with(kRtuTcpScheme)) {
        out.kind = SerialUrl::Kind::RtuOverTcp;
        auto rest = url.substr(kRtuTcpScheme.size());
        if (rest.find('?') != std::string_view::npos) {
            return url_error(url, "rtu+tcp:// takes no settings");
        }
        auto address = parse_tcp_address(rest);
        if (!address)
            return url_error(url, "HOST:PORT must be a host name or IP address and a port");
        auto endpoint = resolve_tcp_address(url, *address);
        if (!endpoint) return endpoint.error();
        out.endpoint = endpoint->front();
        return out;
    }
    if (url.starts_with(kRtuScheme)) {
        out.kind = SerialUrl::Kind::Rtu;
        return parse_line_url(url, url.substr(kRtuScheme.size()), std::move(out));
    }
    if (url.starts_with(kAsciiScheme)) {
        out.kind = SerialUrl::Kind::Ascii;
        out.line.data_bits = 7;
        return parse_line_url(url, url.substr(kAsciiScheme.size()), std::move(out));
    }
    return url_error(url, "unknown scheme");
}

std::string format_serial_url(const SerialUrl& url) {
    if (url.kind == SerialUrl::Kind::RtuOverTcp) {
        return "rtu+" + format_tcp_url(url.endpoint);
    }
    static constexpr std::array<char, 3> kParity = {'N', 'E', 'O'};
    std::string out(url.kind == SerialUrl::Kind::Rtu ? kRtuScheme : kAsciiScheme);
    out += url.line.device;
    out += "?baud=" + std::to_string(url.line.baud);
    out += "&parity=";
    out += kParity[static_cast<std::size_t>(url.line.parity)];
    out += "&stop=" + std::to_string(url.line.stop_bits);
    out += "&data=" + std::to_string(url.line.data_bits);
    if (url.strict_timing) out += "&strict=1";
    if (url.paced) out += "&pace=1";
    return out;
}

}  // namespace mblab::transport
