#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <thread>
#include <vector>

// A Modbus/TCP "device" on 127.0.0.1 whose answers a test writes byte by byte, to show the client
// survives hostile ones (CVE-2023-26793): wrong lengths, byte counts past the frame, wrong
// function codes and transaction ids, silence, closed connections, floods. It reads each request
// as an MBAP frame and hands it to the script, which says what to send back.
namespace mblab::test {

struct Answer {
    std::vector<std::uint8_t> bytes;     // written as they are (nothing: no answer)
    std::chrono::milliseconds delay{0};  // before writing
    bool close = false;                  // close the connection after writing
};

// `request` is the whole ADU; `index` counts requests from 0 across connections.
using AnswerScript = std::function<Answer(std::span<const std::uint8_t> request, int index)>;

class MaliciousServer {
  public:
    explicit MaliciousServer(AnswerScript script);
    ~MaliciousServer();
    MaliciousServer(const MaliciousServer&) = delete;
    MaliciousServer& operator=(const MaliciousServer&) = delete;

    // Listens on 127.0.0.1, an ephemeral port; 0 when it cannot.
    std::uint16_t start();
    void stop();
    int requests() const { return requests_.load(); }

  private:
    void run();
    // Serves one connection until the peer leaves, the script closes it, or stop().
    void converse(int fd);
    // Waits for `fd` to be readable; false when stop() was called or the wait timed out.
    bool readable(int fd);
    bool read_exact(int fd, std::uint8_t* out, std::size_t size);

    AnswerScript script_;
    int listen_fd_ = -1;
    int stop_pipe_[2] = {-1, -1};
    std::atomic<int> requests_{0};
    std::thread thread_;
};

// Helpers for scripts: an MBAP frame answering `request` with `pdu` (its transaction id and unit
// copied), and the same with chosen header fields.
std::vector<std::uint8_t> mbap_answer(std::span<const std::uint8_t> request,
                                      std::span<const std::uint8_t> pdu);
std::vector<std::uint8_t> mbap_frame(std::uint16_t transaction_id, std::uint16_t protocol_id,
                                     std::uint16_t length, std::uint8_t unit,
                                     std::span<const std::uint8_t> pdu);

}  // namespace mblab::test
