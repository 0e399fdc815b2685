#include "serial_test_support.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "device/profile_paths.hpp"
#include "server/rtu_tcp_server.hpp"
#include "support/hex.hpp"

extern char** environ;

namespace mblab::test {

namespace {

using Clock = std::chrono::steady_clock;

// Waits for `fd` to be readable until `deadline`; true when it is.
bool readable(int fd, Clock::time_point deadline) {
    for (;;) {
        auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        if (left.count() < 0) return false;
        pollfd p{fd, POLLIN, 0};
        int ready = ::poll(&p, 1, static_cast<int>(left.count()));
        if (ready > 0) return true;
        if (ready == 0) return false;
        if (errno != EINTR) return false;
    }
}

pid_t spawn(const std::vector<std::string>& argv, int out_fd) {
    std::vector<char*> args;
    for (const auto& arg : argv)
        args.push_back(const_cast<char*>(arg.c_str()));
    args.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, out_fd, STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, out_fd, STDERR_FILENO);
    pid_t pid = -1;
    if (posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&actions);
    return pid;
}

// Ends the child we started: SIGTERM, then SIGKILL if it lingers.
void end_child(pid_t pid) {
    if (pid <= 0) return;
    ::kill(pid, SIGTERM);
    for (int i = 0; i < 100; ++i) {
        if (::waitpid(pid, nullptr, WNOHANG) == pid) return;
        std::this_thread::sleep_for(10ms);
    }
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
}

}  // namespace

PtyPair::PtyPair() {
    char pattern[] = "/tmp/mblab-serial-XXXXXX";
    if (!::mkdtemp(pattern)) {
        error_ = "mkdtemp failed";
        return;
    }
    dir_ = pattern;
    int devnull = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    pid_ = spawn({"socat", "-d", "-d", "pty,raw,echo=0,link=" + server_end(),
                  "pty,raw,echo=0,link=" + client_end()},
                 devnull);
    ::close(devnull);
    if (pid_ < 0) {
        error_ = "cannot start socat";
        return;
    }
    std::error_code ignored;
    for (auto give_up = Clock::now() + 5s; Clock::now() < give_up;) {
        if (std::filesystem::exists(server_end(), ignored) &&
            std::filesystem::exists(client_end(), ignored)) {
            return;
        }
        std::this_thread::sleep_for(10ms);
    }
    error_ = "socat made no pty links within 5 s";
}

PtyPair::~PtyPair() {
    end_child(pid_);
    std::error_code ignored;
    if (!dir_.empty()) std::filesystem::remove_all(dir_, ignored);
}

RawSerialMaster::RawSerialMaster(const std::string& path) {
    fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) return;
    termios tio{};
    ::tcgetattr(fd_, &tio);
    ::cfmakeraw(&tio);
    ::tcsetattr(fd_, TCSANOW, &tio);
}

RawSerialMaster::~RawSerialMaster() {
    if (fd_ >= 0) ::close(fd_);
}

bool RawSerialMaster::send(std::span<const std::uint8_t> bytes) {
    std::size_t sent = 0;
    auto give_up = Clock::now() + 3s;
    while (sent < bytes.size()) {
        auto n = ::write(fd_, bytes.data() + sent, bytes.size() - sent);
        if (n > 0) {
            sent += static_cast<std::size_t>(n);
            continue;
        }
        if (n < 0 && errno != EAGAIN && errno != EINTR) return false;
        if (Clock::now() > give_up) return false;
        std::this_thread::sleep_for(1ms);
    }
    return true;
}

std::vector<std::uint8_t> RawSerialMaster::receive(std::chrono::milliseconds timeout,
                                                   std::chrono::milliseconds quiet) {
    std::vector<std::uint8_t> out;
    auto deadline = Clock::now() + timeout;
    std::uint8_t buffer[512];
    while (readable(fd_, deadline)) {
        auto n = ::read(fd_, buffer, sizeof buffer);
        if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
        if (n <= 0) break;
        out.insert(out.end(), buffer, buffer + n);
        deadline = Clock::now() + quiet;
    }
    return out;
}

std::string RawSerialMaster::transact(std::string_view frame_hex,
                                      std::chrono::milliseconds timeout) {
    if (!send(hex(frame_hex))) return "send failed";
    return to_hex(receive(timeout));
}

std::string RawSerialMaster::transact_text(std::string_view frame,
                                           std::chrono::milliseconds timeout) {
    auto bytes = std::span(reinterpret_cast<const std::uint8_t*>(frame.data()), frame.size());
    if (!send(bytes)) return "send failed";
    auto answer = receive(timeout);
    return std::string(answer.begin(), answer.end());
}

SerialServerThread::~SerialServerThread() {
    stop();
}

std::string SerialServerThread::start(device::RequestHandler& handler, std::string_view url,
                                      server::SerialLineHooks hooks) {
    auto parsed = transport::parse_serial_url(url);
    if (!parsed) return parsed.error();
    auto server = server::start_serial_server(io_, handler, *parsed, std::move(hooks));
    if (!server) return server.error();
    server_ = std::move(server.value());
    thread_ = std::thread([this] { io_.run(); });
    return {};
}

void SerialServerThread::stop() {
    if (!thread_.joinable()) return;
    asio::post(io_, [this] { server_->stop(); });
    thread_.join();
    server_.reset();
}

std::string DeviceOnLine::start(const std::string& profile_name, const std::string& scheme,
                                unsigned baud, bool open_master, const std::string& settings) {
    ascii_ = scheme == "ascii";
    pty_ = std::make_unique<PtyPair>();
    if (!pty_->ok()) return pty_->error();
    auto loaded = device::load_profile(device::profiles_dir() / (profile_name + ".toml"));
    if (!loaded) return loaded.error();
    device_ = std::move(loaded.value());
    // Pseudo-terminals take only 8 data bits.
    auto url = scheme + "://" + pty_->server_end() + "?baud=" + std::to_string(baud) + "&data=8" +
               settings;
    auto error = server_.start(*device_, url, server::device_line_hooks(*device_));
    if (!error.empty() || !open_master) return error;
    master_ = std::make_unique<RawSerialMaster>(pty_->client_end());
    return master_->ok() ? "" : "cannot open " + pty_->client_end();
}

std::string DeviceOnRtuTcp::start(server::ServerOptions options, const std::string& extra) {
    std::ifstream file(device::default_profile_path());
    std::stringstream text;
    text << file.rdbuf() << "\n" << extra;
    auto loaded = device::load_profile_text(text.str(), "reference");
    if (!loaded) return loaded.error();
    device_ = std::move(loaded.value());
    server_ = std::make_unique<server::TcpServer>(
        io_, *device_, options,
        server::rtu_session_starter(options, server::device_line_hooks(*device_)));
    auto port = server_->start({asio::ip::address_v4::loopback(), 0});
    if (!port) return port.error();
    port_ = *port;
    thread_ = std::thread([this] { io_.run(); });
    return {};
}

DeviceOnRtuTcp::~DeviceOnRtuTcp() {
    if (!thread_.joinable()) return;
    asio::post(io_, [this] { server_->stop(); });
    thread_.join();
}

DeviceOnLine::~DeviceOnLine() {
    server_.stop();  // before the device and the ptys go
}

std::string DeviceOnLine::ask(std::string_view address_and_pdu_hex,
                              std::chrono::milliseconds timeout) {
    if (ascii_) return master_->transact_text(ascii(address_and_pdu_hex), timeout);
    return master_->transact(rtu(address_and_pdu_hex), timeout);
}

std::string DeviceOnLine::wire(std::string_view address_and_pdu_hex) const {
    return ascii_ ? ascii(address_and_pdu_hex) : rtu(address_and_pdu_hex);
}

void DeviceOnLine::send_raw_hex(std::string_view bytes_hex) {
    auto bytes = hex(bytes_hex);
    send_raw_text(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

void DeviceOnLine::send_raw_text(std::string_view text) {
    master_->send(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
    // Far more than t3.5 (and than a scheduling hiccup).
    std::this_thread::sleep_for(60ms);
}

int run_command(const std::vector<std::string>& argv, std::string& output,
                std::chrono::seconds timeout) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return -1;
    pid_t pid = spawn(argv, fds[1]);
    ::close(fds[1]);
    if (pid < 0) {
        ::close(fds[0]);
        return -1;
    }
    auto deadline = Clock::now() + timeout;
    char buffer[1024];
    bool timed_out = false;
    for (;;) {
        if (!readable(fds[0], deadline)) {
            timed_out = Clock::now() >= deadline;
            if (timed_out) break;
            continue;
        }
        auto n = ::read(fds[0], buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        output.append(buffer, static_cast<std::size_t>(n));
    }
    ::close(fds[0]);
    if (timed_out) {
        end_child(pid);
        output += "\n(killed after timeout)";
        return -1;
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace mblab::test
