#pragma once

#include <sys/types.h>

#include <asio/io_context.hpp>
#include <asio/post.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "device/reference_device.hpp"
#include "device/request_handler.hpp"
#include "server/serial_server.hpp"
#include "server/tcp_server.hpp"
#include "support/serial_frames.hpp"
#include "transport/serial_url.hpp"

// What serial-line tests share: a pseudo-terminal pair from socat, a raw master on one end,
// the server under test on its own thread, and frame builders. Every wait has a timeout.
namespace mblab::test {

using namespace std::chrono_literals;

// Two linked pseudo-terminals, DIR/a and DIR/b, made by a socat the test starts and kills.
class PtyPair {
  public:
    PtyPair();
    ~PtyPair();
    PtyPair(const PtyPair&) = delete;
    PtyPair& operator=(const PtyPair&) = delete;

    bool ok() const { return error_.empty(); }
    const std::string& error() const { return error_; }
    std::string server_end() const { return dir_ + "/a"; }
    std::string client_end() const { return dir_ + "/b"; }

  private:
    std::string dir_;
    pid_t pid_ = -1;
    std::string error_;
};

// The test's own serial master: raw bytes on a pty end.
class RawSerialMaster {
  public:
    explicit RawSerialMaster(const std::string& path);
    ~RawSerialMaster();
    RawSerialMaster(const RawSerialMaster&) = delete;
    RawSerialMaster& operator=(const RawSerialMaster&) = delete;

    bool ok() const { return fd_ >= 0; }
    bool send(std::span<const std::uint8_t> bytes);
    // The bytes that arrive until `quiet` passes without more, once something came; empty
    // when nothing comes within `timeout`.
    std::vector<std::uint8_t> receive(std::chrono::milliseconds timeout = 3s,
                                      std::chrono::milliseconds quiet = 40ms);
    // Sends `frame` (hex), then returns the answer as hex; "" for none within `timeout`.
    std::string transact(std::string_view frame_hex, std::chrono::milliseconds timeout = 3s);
    // ASCII frames are text: sends `frame` and returns the answer's characters.
    std::string transact_text(std::string_view frame, std::chrono::milliseconds timeout = 3s);

  private:
    int fd_ = -1;
};

// A serial server on its own io_context and thread.
class SerialServerThread {
  public:
    SerialServerThread() = default;
    ~SerialServerThread();
    // Parses `url`, opens the line and starts; "" or the error.
    std::string start(device::RequestHandler& handler, std::string_view url,
                      server::SerialLineHooks hooks = {});
    void stop();

  private:
    asio::io_context io_;
    std::unique_ptr<server::SerialServer> server_;
    std::thread thread_;
};

// A profile's reference device served on one end of a pty pair, a raw master on the other, in
// RTU or ASCII: ask() sends an address + PDU (hex) framed for the line and returns the answer as
// it came off the wire; wire() frames an expected address + PDU the same way.
class DeviceOnLine {
  public:
    // "" or what failed. `scheme` is "rtu" or "ascii". Without `open_master` the client end
    // is left for another master (a gateway, pymodbus).
    // `settings` go after the URL's baud and data bits ("&pace=1").
    std::string start(const std::string& profile_name, const std::string& scheme,
                      unsigned baud = 19200, bool open_master = true,
                      const std::string& settings = "");
    ~DeviceOnLine();

    std::string ask(std::string_view address_and_pdu_hex, std::chrono::milliseconds timeout = 3s);
    std::string wire(std::string_view address_and_pdu_hex) const;
    // Send bytes as they are (given as hex, or as text), then wait long enough for the line to
    // fall silent, so that they stand alone as one burst.
    void send_raw_hex(std::string_view bytes_hex);
    void send_raw_text(std::string_view text);

    device::ReferenceDevice& device() { return *device_; }
    PtyPair& pty() { return *pty_; }
    RawSerialMaster& master() { return *master_; }

  private:
    bool ascii_ = false;
    std::unique_ptr<PtyPair> pty_;
    std::unique_ptr<device::ReferenceDevice> device_;
    SerialServerThread server_;
    std::unique_ptr<RawSerialMaster> master_;
};

// The reference device (default profile) answering RTU frames over TCP on a loopback port, served
// on its own thread.
class DeviceOnRtuTcp {
  public:
    // "" or what failed. `extra`: TOML appended to the reference profile (a fault rule).
    std::string start(server::ServerOptions options = {}, const std::string& extra = "");
    ~DeviceOnRtuTcp();

    std::uint16_t port() const { return port_; }
    const server::TcpServer& server() const { return *server_; }

  private:
    asio::io_context io_;
    std::unique_ptr<device::ReferenceDevice> device_;
    std::unique_ptr<server::TcpServer> server_;
    std::thread thread_;
    std::uint16_t port_ = 0;
};

// Runs a command with a timeout; returns its exit status (-1 when it could not run or was
// killed) and puts its standard output and error in `output`.
int run_command(const std::vector<std::string>& argv, std::string& output,
                std::chrono::seconds timeout = 30s);

}  // namespace mblab::test
