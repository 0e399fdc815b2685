#include <arpa/inet.h>
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "child_process.hpp"
#include "support/sanitizer.hpp"
#include "support/temp_path.hpp"

// A device that, once asked anything, sends bytes without end: `mblab conform` must keep what it
// holds per exchange bounded (the first bytes and a count), say how much came, and stay small,
// instead of growing with the flood (issue 17, item 2: 5.7 GB RSS and 1.6 GB reports before).
namespace mblab::test {
namespace {

using ::testing::HasSubstr;

class FloodingDevice {
  public:
    FloodingDevice() {
        listener_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t length = sizeof address;
        if (::bind(listener_, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
            ::listen(listener_, 8) == 0 &&
            ::getsockname(listener_, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
            port_ = ntohs(address.sin_port);
        }
        thread_ = std::thread([this] { serve(); });
    }
    ~FloodingDevice() {
        stop_ = true;
        thread_.join();
        ::close(listener_);
    }
    std::uint16_t port() const { return port_; }

  private:
    void serve() {
        while (!stop_) {
            pollfd ready{listener_, POLLIN, 0};
            if (::poll(&ready, 1, 50) <= 0) continue;
            const int fd = ::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
            if (fd < 0) continue;
            flood(fd);
            ::close(fd);
        }
    }

    // After the first request bytes, everything that fits, until the client hangs up.
    void flood(int fd) {
        std::array<std::uint8_t, 65536> noise{};
        for (std::size_t i = 0; i < noise.size(); ++i)
            noise[i] = static_cast<std::uint8_t>(0xA5 ^ i);
        bool asked = false;
        while (!stop_) {
            pollfd io{fd, static_cast<short>(asked ? POLLIN | POLLOUT : POLLIN), 0};
            if (::poll(&io, 1, 50) <= 0) continue;
            if ((io.revents & (POLLHUP | POLLERR)) != 0) return;
            if ((io.revents & POLLIN) != 0) {
                std::array<std::uint8_t, 1024> in{};
                if (::recv(fd, in.data(), in.size(), 0) <= 0) return;
                asked = true;
            }
            if ((io.revents & POLLOUT) != 0 &&
                ::send(fd, noise.data(), noise.size(), MSG_NOSIGNAL) < 0 && errno != EAGAIN) {
                return;
            }
        }
    }

    int listener_ = -1;
    std::uint16_t port_ = 0;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

TEST(ConformFlood, AFloodingDeviceIsReportedWithBoundedMemoryAndReports) {
    FloodingDevice device;
    ASSERT_NE(device.port(), 0);
    const std::string json = temp_path("flood.json");
    ChildProcess child({MBLAB_BINARY, "conform", "tcp://127.0.0.1:" + std::to_string(device.port()),
                        "--suite", "mbap", "--timeout", "300", "--json", json});
    std::string out;
    while (auto line = child.read_stdout_line(std::chrono::seconds(60)))
        out += *line + "\n";
    EXPECT_EQ(child.wait_exit(std::chrono::seconds(60)), 1) << out << child.drain_stderr();
    // mbap.5's first step expects 300 ms of silence: the flood is counted, not kept.
    EXPECT_THAT(out, HasSubstr("bytes when silence was expected"));
    EXPECT_LT(out.size(), 1U << 20);
    EXPECT_LT(std::filesystem::file_size(json), 1U << 20);
    // This child's own peak: RUSAGE_CHILDREN would count the largest child any earlier test of
    // the same process waited for.
    const long peak = child.peak_rss_kb();
    RecordProperty("max_rss_kib", static_cast<int>(peak));
    std::printf("mblab conform against a flood: max RSS %ld KiB, console %zu bytes\n", peak,
                out.size());
    EXPECT_GT(peak, 0);
    EXPECT_LT(peak, 100L * 1024 + kSanitizerKb) << "max RSS of mblab conform in KiB";
    std::filesystem::remove(json);
}

}  // namespace
}  // namespace mblab::test
