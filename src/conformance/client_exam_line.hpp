#pragma once

#include <termios.h>

#include <asio/io_context.hpp>
#include <asio/serial_port.hpp>
#include <memory>
#include <optional>
#include <string>

#include "conformance/client_exam_run.hpp"
#include "protocol/adu.hpp"
#include "protocol/result.hpp"
#include "transport/serial_url.hpp"

// `mblab conform-client` on a serial line (RTU or ASCII): the examiner is the slave at one end
// of the line, the client's command the master at the other.
namespace mblab::conformance {

class ExamLine {
  public:
    // "rtu:///dev/ttyUSB0?baud=..." or "ascii://...": the examiner serves that device (one end
    // of a null-modem cable or of a socat pty pair). The device /dev/ptmx makes a new
    // pseudo-terminal pair instead: the examiner holds its master side and the client is given
    // the other end in {url}.
    static protocol::Result<std::unique_ptr<ExamLine>, std::string> open(const std::string& url);
    ExamLine(const ExamLine&) = delete;
    ExamLine& operator=(const ExamLine&) = delete;
    ~ExamLine();

    int fd() const { return fd_; }
    protocol::Framing framing() const { return framing_; }
    // The client's end with the line's settings, for {url}; the examiner's own URL when the
    // client's end is not known (a device given by path).
    const std::string& client_url() const { return client_url_; }
    // The same as a path and a speed, for {device} and {baud}.
    const std::string& client_device() const { return client_device_; }
    unsigned baud() const { return baud_; }
    const std::string& url() const { return url_; }
    // Drops what either end left unread: a scenario starts on a quiet line.
    void flush() const;
    // How long the line stays quiet before an RTU frame without a known length ends (t3.5).
    std::chrono::milliseconds quiet() const { return quiet_; }

  private:
    ExamLine() = default;
    asio::io_context io_;
    std::optional<asio::serial_port> port_;
    int fd_ = -1;        // the examiner's end
    int held_end_ = -1;  // a pty pair's client end, held open so the master never hangs up
    termios held_settings_{};
    protocol::Framing framing_ = protocol::Framing::Rtu;
    std::string url_;
    std::string client_url_;
    std::string client_device_;
    unsigned baud_ = 0;
    std::chrono::milliseconds quiet_{10};
};

// The serial line scenarios against the command, as run_client_exam() runs the TCP ones.
RunResult run_client_line_exam(ExamLine& line, const ClientExamOptions& options,
                               RunListener* listener);

// The suite the line scenarios make, for the reports.
Suite client_line_suite();

}  // namespace mblab::conformance
