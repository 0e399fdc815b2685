#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "device/reference_device.hpp"
#include "serial_test_support.hpp"

// A serial slave built wrong on purpose, for the serial suite to catch: the reference device's
// answers, framed by hand on a pty end so that one rule of the line can be broken at a time.
// Unless its fault says otherwise it keeps the rules: address 1 only, broadcasts executed and not
// answered, a frame with a wrong CRC or LRC or with lower-case hex dropped.
namespace mblab::test {

enum class SlaveFault : std::uint8_t {
    None,
    AnswersOtherAddress,     // serves every address as if it were its own
    AnswersBroadcast,        // answers address 0 as if it were its own
    ExecutesBadChecksum,     // takes a frame whose CRC or LRC is wrong
    LowerCaseAnswer,         // ASCII: answers in lower-case hex
    WrongLrc,                // ASCII: answers with its LRC plus one
    CrWithoutLf,             // ASCII: ends its answers with CR alone
    CrcHighByteFirst,        // RTU: answers with the CRC's bytes swapped
    ForeignAddressInAnswer,  // answers its own requests carrying address 2
    JoinsBrokenFrame,        // RTU: joins the parts of a frame broken by a silence
    GapInAnswer,             // sends each answer in two parts, 10 ms apart
    SetTo9600N2              // keeps the rules, but at 9600 baud, no parity, two stop bits
};

class WrongSerialSlave {
  public:
    // "" or what failed. The slave serves `pty`'s server end until destroyed.
    std::string start(const PtyPair& pty, bool ascii, SlaveFault fault);
    ~WrongSerialSlave();

  private:
    struct Request {
        std::uint8_t address = 0;
        std::vector<std::uint8_t> pdu;
        bool checksum_ok = false;
        bool lower_case = false;
    };
    std::optional<Request> decode(const std::vector<std::uint8_t>& bytes) const;
    std::vector<std::uint8_t> encode(std::uint8_t address, std::span<const std::uint8_t> pdu) const;
    void serve();
    void take(const Request& request);

    // SetTo9600N2: whether the master's end is set as this slave is. A pty passes bytes on
    // whatever the settings, where a real line would garble them, so the slave looks.
    bool master_set_alike() const;

    bool ascii_ = false;
    std::string master_end_;
    SlaveFault fault_ = SlaveFault::None;
    std::unique_ptr<device::ReferenceDevice> device_;
    std::unique_ptr<RawSerialMaster> port_;  // raw bytes on the slave's end
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace mblab::test
