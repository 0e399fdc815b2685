#include "wrong_serial_slave.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cctype>

#include "device/profile_paths.hpp"
#include "protocol/adu.hpp"
#include "protocol/crc16.hpp"
#include "protocol/limits.hpp"
#include "protocol/lrc.hpp"

namespace mblab::test {

namespace {

constexpr std::uint8_t kOwnAddress = 1;

int hex_value(std::uint8_t c) {
    if (c >= '0' && c <= '9') return c - '0';
    const int lower = std::tolower(c);
    if (lower >= 'a' && lower <= 'f') return lower - 'a' + 10;
    return -1;
}

// Whether `bytes` are a frame whose CRC holds (the CRC over a whole frame leaves 0).
bool crc_holds(std::span<const std::uint8_t> bytes) {
    return bytes.size() >= 4 && protocol::crc16(bytes) == 0;
}

// A burst cut into frames: each shortest run whose CRC holds, and the bytes between them.
std::vector<std::vector<std::uint8_t>> rtu_frames(const std::vector<std::uint8_t>& burst) {
    std::vector<std::vector<std::uint8_t>> out;
    const std::span<const std::uint8_t> all(burst);
    std::size_t junk = 0;  // start of bytes that belong to no frame yet
    for (std::size_t at = 0; at < burst.size(); ++at) {
        for (std::size_t size = 4; at + size <= burst.size(); ++size) {
            if (!crc_holds(all.subspan(at, size))) continue;
            if (junk < at) out.emplace_back(burst.begin() + junk, burst.begin() + at);
            out.emplace_back(burst.begin() + at, burst.begin() + at + size);
            at += size - 1;
            junk = at + 1;
            break;
        }
    }
    if (junk < burst.size()) out.emplace_back(burst.begin() + junk, burst.end());
    return out;
}

}  // namespace

std::string WrongSerialSlave::start(const PtyPair& pty, bool ascii, SlaveFault fault) {
    ascii_ = ascii;
    fault_ = fault;
    master_end_ = pty.client_end();
    auto loaded = device::load_profile(device::default_profile_path());
    if (!loaded) return loaded.error();
    device_ = std::move(loaded.value());
    port_ = std::make_unique<RawSerialMaster>(pty.server_end());
    if (!port_->ok()) return "cannot open " + pty.server_end();
    thread_ = std::thread([this] { serve(); });
    return {};
}

WrongSerialSlave::~WrongSerialSlave() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
}

std::optional<WrongSerialSlave::Request> WrongSerialSlave::decode(
    const std::vector<std::uint8_t>& bytes) const {
    Request request;
    std::vector<std::uint8_t> body;  // address, PDU and checksum
    if (!ascii_) {
        if (bytes.size() < 4) return std::nullopt;
        body = bytes;
        const auto crc = protocol::crc16(std::span(body).first(body.size() - 2));
        request.checksum_ok = body[body.size() - 2] == (crc & 0xFF) && body.back() == (crc >> 8);
        body.resize(body.size() - 2);
    } else {
        if (bytes.size() < 9 || bytes.front() != ':' || bytes[bytes.size() - 2] != '\r' ||
            bytes.back() != '\n' || bytes.size() % 2 == 0) {
            return std::nullopt;
        }
        for (std::size_t i = 1; i + 2 < bytes.size(); i += 2) {
            const int high = hex_value(bytes[i]);
            const int low = hex_value(bytes[i + 1]);
            if (high < 0 || low < 0) return std::nullopt;
            request.lower_case |= std::islower(bytes[i]) != 0 || std::islower(bytes[i + 1]) != 0;
            body.push_back(static_cast<std::uint8_t>(high << 4 | low));
        }
        const std::uint8_t lrc = body.back();
        body.pop_back();
        request.checksum_ok = protocol::lrc(body) == lrc;
    }
    request.address = body.front();
    request.pdu.assign(body.begin() + 1, body.end());
    return request;
}

std::vector<std::uint8_t> WrongSerialSlave::encode(std::uint8_t address,
                                                   std::span<const std::uint8_t> pdu) const {
    std::array<std::uint8_t, protocol::limits::kMaxAsciiChars> out{};
    const auto framing = ascii_ ? protocol::Framing::Ascii : protocol::Framing::Rtu;
    const std::size_t size = protocol::write_adu({framing, address}, pdu, out);
    std::vector<std::uint8_t> wire(out.begin(), out.begin() + static_cast<long>(size));
    if (fault_ == SlaveFault::LowerCaseAnswer) {
        for (auto& c : wire)
            c = static_cast<std::uint8_t>(std::tolower(c));
    } else if (fault_ == SlaveFault::WrongLrc) {
        // The LRC's two digits sit before CR LF; '0'..'9' and 'A'..'E' plus one stay hex digits.
        auto& digit = wire[wire.size() - 3];
        digit = digit == '9' ? 'A' : digit == 'F' ? '0' : static_cast<std::uint8_t>(digit + 1);
    } else if (fault_ == SlaveFault::CrWithoutLf) {
        wire.pop_back();
    } else if (fault_ == SlaveFault::CrcHighByteFirst) {
        std::swap(wire[wire.size() - 2], wire[wire.size() - 1]);
    }
    return wire;
}

void WrongSerialSlave::take(const Request& request) {
    const bool broadcast = request.address == 0;
    bool serve = request.address == kOwnAddress || broadcast;
    if (fault_ == SlaveFault::AnswersOtherAddress && request.address != 0) serve = true;
    // A frame with a wrong checksum is counted (FC 08 sub-function 0C) whatever is done with it.
    if (!request.checksum_ok) device_->counters().count_crc_error();
    if (!request.checksum_ok && fault_ != SlaveFault::ExecutesBadChecksum) serve = false;
    if (request.lower_case) serve = false;
    if (fault_ == SlaveFault::SetTo9600N2 && !master_set_alike()) serve = false;
    if (!serve) return;
    // Executed as its own (a broadcast too, when it answers one).
    const bool answer_broadcast = fault_ == SlaveFault::AnswersBroadcast;
    const std::uint8_t unit = broadcast && !answer_broadcast ? 0 : kOwnAddress;
    std::array<std::uint8_t, protocol::limits::kMaxPdu> response{};
    const auto reply =
        device_->handle({unit, device::Link::Serial}, request.pdu, std::span(response));
    if (reply.action != device::ReplyAction::Answer) return;
    std::uint8_t address = broadcast ? kOwnAddress : request.address;
    if (fault_ == SlaveFault::ForeignAddressInAnswer) address = kOwnAddress + 1;
    const auto wire = encode(address, std::span(response).first(reply.size));
    if (fault_ != SlaveFault::GapInAnswer) {
        port_->send(wire);
        return;
    }
    // Well over t1.5 at any baud rate, and under the tester's 20 ms reading silence, so the
    // frame still comes whole and only its timing is wrong.
    const std::span<const std::uint8_t> bytes(wire);
    port_->send(bytes.first(3));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    port_->send(bytes.subspan(3));
}

bool WrongSerialSlave::master_set_alike() const {
    const int fd = ::open(master_end_.c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK);
    if (fd < 0) return false;
    termios settings{};
    const bool read = ::tcgetattr(fd, &settings) == 0;
    ::close(fd);
    return read && ::cfgetospeed(&settings) == B9600 && (settings.c_cflag & PARENB) == 0 &&
           (settings.c_cflag & CSTOPB) != 0;
}

void WrongSerialSlave::serve() {
    while (!stop_) {
        // The tester sends one request and waits: a burst is one frame.
        // A burst is one frame: it ends after a silence, of 200 ms for the slave that joins
        // what a silence broke.
        const auto silence =
            std::chrono::milliseconds(fault_ == SlaveFault::JoinsBrokenFrame ? 200 : 15);
        auto bytes = port_->receive(std::chrono::milliseconds(100), silence);
        if (bytes.empty()) continue;
        // An ASCII frame ends with its LF, and up to 1 s may pass between its characters
        // [SER 2.5.2.1].
        while (ascii_ && bytes.back() != '\n') {
            const auto more = port_->receive(std::chrono::milliseconds(1000), silence);
            if (more.empty()) break;
            bytes.insert(bytes.end(), more.begin(), more.end());
        }
        // The tester may send its next RTU frame t3.5 after its last one, well inside this
        // slave's silence: a burst is cut into the frames whose CRC holds, and what lies
        // between them.
        for (const auto& frame :
             ascii_ ? std::vector<std::vector<std::uint8_t>>{bytes} : rtu_frames(bytes)) {
            if (auto request = decode(frame)) take(*request);
        }
    }
}

}  // namespace mblab::test
