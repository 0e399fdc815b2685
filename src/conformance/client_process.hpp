#pragma once

#include <sys/types.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "protocol/result.hpp"

// The client command `mblab conform-client` examines: started with its arguments as given (no
// shell), its standard output and standard error read from one pipe, stopped at a limit.
namespace mblab::conformance {

class ClientProcess {
  public:
    ClientProcess() = default;
    ClientProcess(const ClientProcess&) = delete;
    ClientProcess& operator=(const ClientProcess&) = delete;
    ~ClientProcess();  // kills and reaps a process still running

    // Starts argv[0] (searched in PATH) in a process group of its own.
    static protocol::Result<std::unique_ptr<ClientProcess>, std::string> start(
        const std::vector<std::string>& argv);

    // The pipe to poll for output; -1 once it ended.
    int output_fd() const { return output_; }
    // Reads what the pipe holds into output(); closes it at its end.
    void read_output();
    const std::string& output() const { return text_; }

    // Whether it exited (reaped now if it did); exit_status() then holds 0..255, or 128 + signal.
    bool exited();
    int exit_status() const { return status_; }
    // SIGKILL to its process group, then reaped.
    void kill();

  private:
    pid_t pid_ = -1;
    int output_ = -1;
    int status_ = 0;
    bool reaped_ = false;
    std::string text_;
};

// `text` with {host}, {port}, {url}, {unit}, {address} and {count} filled in; on a line {device}
// and {baud} (the client's end and its speed, for clients that take them apart); over mbaps {ca},
// {cert} and {key}: the lab PKI's CA and a client certificate and key.
struct ClientPlaceholders {
    std::string host = {};
    std::string port = {};
    std::string url = {};
    std::string unit = {};
    std::string address = {};
    std::string count = {};
    std::string device = {};
    std::string baud = {};
    std::string ca = {};
    std::string cert = {};
    std::string key = {};
};
std::string fill_placeholders(std::string text, const ClientPlaceholders& values);

}  // namespace mblab::conformance
