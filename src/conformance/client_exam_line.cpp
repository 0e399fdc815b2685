#include "conformance/client_exam_line.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "conformance/client_exam_wire.hpp"
#include "transport/serial_port.hpp"

namespace mblab::conformance {

namespace {

using namespace std::chrono_literals;
using Clock = ClientExaminer::Clock;

constexpr auto kPollSlice = 20ms;

bool make_raw(int fd) {
    termios settings{};
    if (::tcgetattr(fd, &settings) != 0) return false;
    ::cfmakeraw(&settings);
    return ::tcsetattr(fd, TCSANOW, &settings) == 0;
}

// The line as one connection, opened once: the examiner reads the client's requests off it and
// writes its answers, and tells the examiner when it went quiet.
class LineWire final : public ExamWire {
  public:
    LineWire(ClientExaminer& exam, const ExamLine& line, Capture* capture)
        : exam_(exam), line_(line), capture_(capture) {
        line.flush();
        exam_.opened(Clock::now());
        if (capture_) capture_->on_label(exam.scenario().id);
    }
    LineWire(const LineWire&) = delete;
    LineWire& operator=(const LineWire&) = delete;
    ~LineWire() override { captured(); }

    void add_polls(std::vector<pollfd>& polls) const override {
        polls.push_back({line_.fd(), POLLIN, 0});
    }

    void on_polled(const std::vector<pollfd>& polls) override {
        const auto now = Clock::now();
        for (const auto& polled : polls) {
            if (polled.fd != line_.fd() || (polled.revents & POLLIN) == 0) continue;
            std::uint8_t buffer[512];
            ssize_t got = 0;
            while ((got = ::read(line_.fd(), buffer, sizeof buffer)) > 0) {
                exam_.received(0, {buffer, static_cast<std::size_t>(got)}, now);
                if (capture_) heard_.insert(heard_.end(), buffer, buffer + got);
                last_byte_ = now;
            }
        }
        if (last_byte_ && now - *last_byte_ >= line_.quiet()) {
            exam_.quiet(0, now);
            last_byte_.reset();
            captured();
        }
    }

    void perform() override {
        for (const auto& action : exam_.due(Clock::now())) {
            if (action.kind != ClientExaminer::Action::Kind::Send) continue;
            captured();
            if (capture_) capture_->on_received(action.bytes);
            std::size_t written = 0;
            while (written < action.bytes.size()) {
                const auto put = ::write(line_.fd(), action.bytes.data() + written,
                                         action.bytes.size() - written);
                if (put < 0 && errno != EAGAIN && errno != EINTR) break;
                if (put > 0) written += static_cast<std::size_t>(put);
            }
        }
    }

    std::chrono::milliseconds wait() const override {
        auto wait = std::chrono::milliseconds(kPollSlice);
        if (last_byte_) wait = std::min(wait, line_.quiet());
        const auto deadline = exam_.deadline();
        if (deadline == Clock::time_point::max()) return wait;
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        return std::clamp(left, 0ms, wait);
    }

  private:
    // The client's bytes since the line was last quiet, as one frame in the capture: a read
    // returns what the line had, a frame's worth or less.
    void captured() {
        if (!capture_ || heard_.empty()) return;
        capture_->on_sent(heard_);
        heard_.clear();
    }

    ClientExaminer& exam_;
    const ExamLine& line_;
    Capture* capture_;
    std::vector<std::uint8_t> heard_;
    std::optional<Clock::time_point> last_byte_;
};

}  // namespace

protocol::Result<std::unique_ptr<ExamLine>, std::string> ExamLine::open(const std::string& url) {
    auto parsed = transport::parse_serial_url(url);
    if (!parsed) return parsed.error();
    if (parsed->kind == transport::SerialUrl::Kind::RtuOverTcp)
        return "--listen " + url + ": rtu+tcp:// is a TCP listener (ExamListener), not a line";
    std::unique_ptr<ExamLine> line(new ExamLine());
    line->framing_ = parsed->kind == transport::SerialUrl::Kind::Ascii ? protocol::Framing::Ascii
                                                                       : protocol::Framing::Rtu;
    line->quiet_ = std::max<std::chrono::milliseconds>(
        10ms, std::chrono::ceil<std::chrono::milliseconds>(
                  transport::rtu_char_times(parsed->line.baud).t35));
    line->url_ = transport::format_serial_url(*parsed);
    line->baud_ = parsed->line.baud;
    if (parsed->line.device == "/dev/ptmx") {
        line->fd_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
        const char* name = nullptr;
        if (line->fd_ < 0 || ::grantpt(line->fd_) != 0 || ::unlockpt(line->fd_) != 0 ||
            (name = ::ptsname(line->fd_)) == nullptr) {
            return "cannot make a pseudo-terminal pair: " + std::string(std::strerror(errno));
        }
        auto client = *parsed;
        client.line.device = name;
        line->client_url_ = transport::format_serial_url(client);
        line->client_device_ = name;
        line->held_end_ = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
        // The client's end raw as well: no line discipline may change an answer on its way.
        if (line->held_end_ < 0 || !make_raw(line->held_end_) ||
            ::tcgetattr(line->held_end_, &line->held_settings_) != 0)
            return "cannot open " + std::string(name) + ": " + std::strerror(errno);
    } else {
        auto port = transport::open_serial_port(line->io_.get_executor(), parsed->line);
        if (!port) return port.error();
        line->port_.emplace(std::move(*port));
        line->fd_ = line->port_->native_handle();
        line->client_url_ = line->url_;
        line->client_device_ = parsed->line.device;
    }
    ::fcntl(line->fd_, F_SETFL, ::fcntl(line->fd_, F_GETFL) | O_NONBLOCK);
    return line;
}

ExamLine::~ExamLine() {
    if (held_end_ >= 0) ::close(held_end_);
    if (!port_ && fd_ >= 0) ::close(fd_);
}

void ExamLine::flush() const {
    ::tcflush(fd_, TCIOFLUSH);
    if (held_end_ >= 0) {
        ::tcflush(held_end_, TCIOFLUSH);
        // And the client's end set as the pair was made, for every run: pyserial (pymodbus's
        // serial client) fails with EINVAL to set parity on a pty its last run left at the
        // same speed with parity (the pty drops PARENB).
        ::tcsetattr(held_end_, TCSANOW, &held_settings_);
    }
}

Suite client_line_suite() {
    return client_suite("client-line", "a Modbus serial line client (master) against the examiner",
                        "SER 2.4.1", client_line_cases());
}

RunResult run_client_line_exam(ExamLine& line, const ClientExamOptions& options,
                               RunListener* listener) {
    ClientPlaceholders where;
    where.url = line.client_url();
    where.device = line.client_device();
    where.baud = std::to_string(line.baud());
    ExamCarrier carrier{client_line_suite(), &client_line_cases(), where, line.framing(),
                        [&](ClientExaminer& exam) -> std::unique_ptr<ExamWire> {
                            return std::make_unique<LineWire>(exam, line, options.capture);
                        }};
    return run_client_cases(carrier, options, listener);
}

}  // namespace mblab::conformance
