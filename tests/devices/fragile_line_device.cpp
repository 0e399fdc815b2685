// An RTU device on a serial line for the tests of `mblab fuzz` over rtu://: at address 1 it
// answers FC 03 (zeros) and ignores everything else, until it sees a frame with a bad CRC
// addressed to 247 (0xF7): from then on it answers nobody, as a device whose receiver is wedged.
// Frames are cut by 3 ms of silence. Its own code, not the project's, so the CRC is computed here.
// Usage: fragile_line_device PATH PIDFILE
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <vector>

namespace {

std::uint16_t crc(const std::vector<std::uint8_t>& bytes, std::size_t size) {
    std::uint16_t value = 0xFFFF;
    for (std::size_t i = 0; i < size; ++i) {
        value ^= bytes[i];
        for (int bit = 0; bit < 8; ++bit)
            value = (value & 1) ? static_cast<std::uint16_t>((value >> 1) ^ 0xA001)
                                : static_cast<std::uint16_t>(value >> 1);
    }
    return value;
}

void append_crc(std::vector<std::uint8_t>& frame) {
    const auto value = crc(frame, frame.size());
    frame.push_back(static_cast<std::uint8_t>(value));
    frame.push_back(static_cast<std::uint8_t>(value >> 8));
}

bool g_deaf = false;

void serve(int fd, const std::vector<std::uint8_t>& frame) {
    if (g_deaf || frame.size() < 4) return;
    const auto value = crc(frame, frame.size() - 2);
    const bool good = frame[frame.size() - 2] == static_cast<std::uint8_t>(value) &&
                      frame[frame.size() - 1] == static_cast<std::uint8_t>(value >> 8);
    if (!good) {
        g_deaf = frame[0] == 0xF7;
        return;
    }
    if (frame[0] != 1 || frame.size() != 8 || frame[1] != 0x03) return;
    const unsigned quantity = frame[4] << 8 | frame[5];
    if (quantity == 0 || quantity > 125) return;
    std::vector<std::uint8_t> answer = {1, 0x03, static_cast<std::uint8_t>(quantity * 2)};
    answer.resize(3 + quantity * 2, 0);
    append_crc(answer);
    if (::write(fd, answer.data(), answer.size()) < 0) return;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: fragile_line_device PATH PIDFILE\n");
        return 2;
    }
    const int fd = ::open(argv[1], O_RDWR | O_NOCTTY);
    if (fd < 0) {
        std::perror(argv[1]);
        return 1;
    }
    termios settings{};
    ::tcgetattr(fd, &settings);
    ::cfmakeraw(&settings);
    ::tcsetattr(fd, TCSANOW, &settings);
    ::tcflush(fd, TCIOFLUSH);
    if (FILE* pid = std::fopen(argv[2], "w")) {
        std::fprintf(pid, "%d\n", static_cast<int>(::getpid()));
        std::fclose(pid);
    }
    std::vector<std::uint8_t> frame;
    while (true) {
        pollfd wait{fd, POLLIN, 0};
        const int ready = ::poll(&wait, 1, frame.empty() ? -1 : 3);
        if (ready == 0) {
            serve(fd, frame);
            frame.clear();
            continue;
        }
        std::uint8_t chunk[512];
        const ssize_t got = ::read(fd, chunk, sizeof chunk);
        if (got > 0) frame.insert(frame.end(), chunk, chunk + got);
    }
}
