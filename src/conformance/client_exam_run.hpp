#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "conformance/capture.hpp"
#include "conformance/client_exam_scenarios.hpp"
#include "conformance/client_exam_tls.hpp"
#include "conformance/client_transcript.hpp"
#include "conformance/engine.hpp"
#include "conformance/verdict.hpp"
#include "protocol/framer.hpp"
#include "protocol/result.hpp"

// `mblab conform-client` over Modbus/TCP (or Modbus/TCP Security): the examiner on a real listening
// socket, the client's command run once per scenario, and a verdict per scenario in conform's
// RunResult.
namespace mblab::conformance {

// A listening TCP socket on loopback (or the address asked), closed with the object.
class ExamListener {
  public:
    // "tcp://HOST:PORT", "mbaps://HOST:PORT" or "rtu+tcp://HOST:PORT"; port 0 takes a free one.
    static protocol::Result<std::unique_ptr<ExamListener>, std::string> open(
        const std::string& url);
    ExamListener(const ExamListener&) = delete;
    ExamListener& operator=(const ExamListener&) = delete;
    ~ExamListener();

    int fd() const { return fd_; }
    const std::string& host() const { return host_; }  // as clients should write it
    std::uint16_t port() const { return port_; }
    std::string url() const;
    // What the connections carry: MBAP, or RTU frames for rtu+tcp://.
    protocol::Framing framing() const {
        return scheme_ == "rtu+tcp://" ? protocol::Framing::Rtu : protocol::Framing::Mbap;
    }

  private:
    ExamListener() = default;
    int fd_ = -1;
    std::string host_;
    std::uint16_t port_ = 0;
    std::string scheme_ = "tcp://";  // or mbaps://, rtu+tcp://
};

struct ClientExamOptions {
    std::vector<std::string> command;  // the client's argv, placeholders unfilled
    ClientDeclarations declared;
    std::vector<std::string> only;  // case ids (or id prefixes, "tcp.6") to run; empty: all
    // Set: every connection's bytes, the client as the tester's side and the examiner as the
    // device's, each packet labelled with its scenario's id.
    Capture* capture = nullptr;
    // Set: the scenarios run behind TLS (mbaps://), with the certificate scenarios after them.
    const ExamTls* tls = nullptr;
    // --attach: no command; the client polls by itself and each scenario waits this long for it.
    bool attach = false;
    std::chrono::milliseconds attach_wait{60000};
    // Set: what the wire carried in each scenario that ran, for the HTML report.
    ClientTranscripts* transcripts = nullptr;
};

// The name and title of the suite the scenarios make, for the reports.
Suite client_tcp_suite();
Suite client_mbaps_suite();
Suite client_rtu_tcp_suite();

// Runs every scenario against the command. `listener` hears of each verdict as it comes.
RunResult run_client_exam(ExamListener& listen, const ClientExamOptions& options,
                          RunListener* listener);

}  // namespace mblab::conformance
