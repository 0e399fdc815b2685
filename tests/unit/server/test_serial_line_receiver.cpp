// The serial receiver without I/O, on a manual clock: where frames end (layout, t3.5, CRC),
// what a t1.5 gap and the ASCII timeout do, and how line errors are counted.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "server/serial_line_receiver.hpp"
#include "support/hex.hpp"
#include "support/serial_frames.hpp"

namespace mblab::test {
namespace {

using server::LineClock;
using server::LineError;
using server::LineEvent;
using server::LineFraming;
using server::LineTiming;
using server::SerialLineReceiver;
using std::chrono::microseconds;

// What came out of the receiver, one line per event: "frame 01 03 ..", "error crc: why",
// "error short: why", "error (counted already)".
std::string describe(const LineEvent& event) {
    if (event.is_frame()) return "frame " + to_hex(event.frame.adu);
    switch (event.error) {
        case LineError::Checksum:
            return "error crc";
        case LineError::ShortFrame:
            return "error short";
        case LineError::None:
            break;
    }
    return "error (counted already)";
}

class Receiver {
  public:
    explicit Receiver(LineFraming framing = LineFraming::Rtu, LineTiming timing = {},
                      protocol::RtuFramer::UnknownLength unknown =
                          protocol::RtuFramer::UnknownLength::AwaitSilence)
        : receiver_(framing, timing, protocol::Direction::Request, unknown) {}

    // Bytes at `at` microseconds; returns the events they give.
    std::vector<std::string> bytes(std::string_view hex_bytes, long at) {
        input_ = hex(hex_bytes);
        receiver_.receive(input_, time(at));
        std::vector<std::string> out;
        for (auto event = receiver_.next(); !event.empty(); event = receiver_.next())
            out.push_back(describe(event));
        return out;
    }
    std::vector<std::string> text(std::string_view chars, long at) {
        std::string as_hex;
        for (unsigned char c : chars) {
            char digits[4];
            std::snprintf(digits, sizeof digits, "%02X ", c);
            as_hex += digits;
        }
        return bytes(as_hex, at);
    }
    // The clock reaches `at`; the event silence gives, or "" for none.
    std::string clock(long at) {
        auto event = receiver_.on_timeout(time(at));
        return event.empty() ? "" : describe(event);
    }
    long deadline() const {
        auto d = receiver_.deadline();
        if (d == LineClock::time_point::max()) return -1;
        return static_cast<long>(
            std::chrono::duration_cast<microseconds>(d - LineClock::time_point{}).count());
    }
    SerialLineReceiver& get() { return receiver_; }

  private:
    static LineClock::time_point time(long us) {
        return LineClock::time_point{} + microseconds(us);
    }

    SerialLineReceiver receiver_;
    std::vector<std::uint8_t> input_;
};

using Events = std::vector<std::string>;

TEST(SerialLineReceiver, SplitsBackToBackRtuFramesByLayoutWithoutSilence) {
    Receiver rx;
    EXPECT_EQ(rx.bytes(rtu("01 03 00 00 00 01") + rtu("02 06 00 10 AB CD"), 1000),
              (Events{"frame " + rtu("01 03 00 00 00 01"), "frame " + rtu("02 06 00 10 AB CD")}));
}

TEST(SerialLineReceiver, EndsAFrameOfUnknownLengthAtT35) {
    LineTiming timing;
    timing.silence = microseconds(1750);
    Receiver rx(LineFraming::Rtu, timing);
    EXPECT_EQ(rx.bytes(rtu("01 08 00 00 12 34"), 1000), Events{});  // FC 08 echo: any length
    EXPECT_EQ(rx.deadline(), 2750);
    EXPECT_EQ(rx.clock(2749), "");
    EXPECT_EQ(rx.clock(2750), "frame " + rtu("01 08 00 00 12 34"));
    EXPECT_EQ(rx.deadline(), -1);
}

TEST(SerialLineReceiver, AppliesASilenceThatPassedBeforeLateBytes) {
    Receiver rx;
    EXPECT_EQ(rx.bytes("01 08 00 00 12", 0), Events{});
    // These bytes came 5 ms later: the silence before them ended the first 5 bytes.
    EXPECT_EQ(rx.bytes(rtu("01 03 00 00 00 01"), 5000),
              (Events{"error crc", "frame " + rtu("01 03 00 00 00 01")}));
}

TEST(SerialLineReceiver, CountsANoiseBurstOnceHoweverItFallsApart) {
    Receiver rx;
    // FC 03 announces 8 bytes: the first 8 fail their CRC, the next 8 too, and the last 4 are
    // cut short by the silence. One burst, one counted error.
    EXPECT_EQ(rx.bytes("01 03 00 00 00 01 00 00 01 03 00 00 00 01 00 00 01 03 00 00", 0),
              (Events{"error crc", "error (counted already)"}));
    EXPECT_EQ(rx.clock(1750), "error (counted already)");
    // After the silence, a new burst counts again.
    EXPECT_EQ(rx.bytes("01 03", 10000), Events{});
    EXPECT_EQ(rx.clock(11750), "error short");
}

TEST(SerialLineReceiver, DropsAFrameSpoiledByAGapOverT15WhenAsked) {
    LineTiming timing;
    timing.silence = microseconds(1750);
    timing.char_gap = microseconds(750);
    Receiver rx(LineFraming::Rtu, timing);
    const auto frame = hex(rtu("01 03 00 00 00 01"));
    const auto head = to_hex(std::span(frame).first(3));
    const auto tail = to_hex(std::span(frame).subspan(3));
    EXPECT_EQ(rx.bytes(head, 0), Events{});
    EXPECT_EQ(rx.bytes(tail, 1000), Events{"error short"});  // 1 ms gap: over t1.5
    EXPECT_EQ(rx.clock(2750), "");
    EXPECT_EQ(rx.bytes(head, 10000), Events{});
    EXPECT_EQ(rx.bytes(tail, 10500), Events{"frame " + rtu("01 03 00 00 00 01")});
}

TEST(SerialLineReceiver, IgnoresGapsInsideFramesByDefault) {
    Receiver rx;
    EXPECT_EQ(rx.bytes("01 03 00", 0), Events{});
    EXPECT_EQ(rx.bytes("00 00 01 84 0A", 1500), Events{"frame 01 03 00 00 00 01 84 0A"});
}

TEST(SerialLineReceiver, EndsUnknownLengthAtTheCrcOverTcp) {
    Receiver rx(LineFraming::Rtu, {}, protocol::RtuFramer::UnknownLength::EndOnCrcMatch);
    EXPECT_EQ(rx.bytes(rtu("01 08 00 00 12 34"), 0), Events{"frame " + rtu("01 08 00 00 12 34")});
}

TEST(SerialLineReceiver, DropsAnUnfinishedAsciiFrameAfterTheCharacterTimeout) {
    LineTiming timing;
    timing.silence = std::chrono::seconds(1);
    Receiver rx(LineFraming::Ascii, timing);
    EXPECT_EQ(rx.deadline(), -1);
    EXPECT_EQ(rx.text(":0103", 0), Events{});
    EXPECT_EQ(rx.deadline(), 1'000'000);
    EXPECT_EQ(rx.text("0000", 900'000), Events{});  // a slow sender: 0.9 s is within the timeout
    EXPECT_EQ(rx.clock(1'899'999), "");
    EXPECT_EQ(rx.clock(1'900'000), "error crc");
    EXPECT_EQ(rx.deadline(), -1);
}

TEST(SerialLineReceiver, CountsEveryBadAsciiFrame) {
    Receiver rx(LineFraming::Ascii);
    EXPECT_EQ(rx.text(":01030010000100\r\n:01030G100001EB\r\n:010300100001EB\r\n", 0),
              (Events{"error crc", "error crc",
                      "frame 3A 30 31 30 33 30 30 31 30 30 30 30 31 45 42 0D 0A"}));
}

TEST(SerialLineReceiver, FollowsTheAsciiDelimiterItIsGiven) {
    Receiver rx(LineFraming::Ascii);
    rx.get().set_ascii_delimiter('!');
    EXPECT_EQ(rx.get().ascii_delimiter(), '!');
    EXPECT_EQ(rx.text(":010300100001EB\r!", 0),
              Events{"frame 3A 30 31 30 33 30 30 31 30 30 30 30 31 45 42 0D 21"});
}

}  // namespace
}  // namespace mblab::test
