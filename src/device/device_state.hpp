#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "device/device_units.hpp"

// The device's writable data (coils, holding registers, file records) as a whole: saved and
// loaded as a state file (docs/profiles.md "State files"), and the writes a journal records and
// replays at restart. Each call takes the device's lock once (device_units.hpp).
namespace mblab::device {

// The writable data of a device at one moment (see DeviceState::snapshot).
struct StateSnapshot {
    struct Range {
        BankKind kind = BankKind::HoldingRegisters;
        std::uint32_t start = 0;
        std::vector<std::uint16_t> values;
    };
    struct Unit {
        std::uint8_t id = 0;
        std::vector<Range> ranges;
        std::vector<FileSpec> files;
    };
    std::string profile;
    std::vector<Unit> units;

    // The state file's text (docs/profiles.md "State files").
    std::string to_json() const;
};

class DeviceState {
  public:
    explicit DeviceState(DeviceUnits& units) : units_(units) {}

    // The writable data as JSON, and back. load() changes nothing unless the whole text fits
    // the profile.
    std::string save() const;
    // The same data copied under the lock, to be turned into the file's text elsewhere: a copy
    // takes well under a millisecond where the text of the reference profile's 1.36 MB took up
    // to 25 ms on the server's thread.
    StateSnapshot snapshot() const;
    bool load(std::string_view text, std::string& error);

    // Requests that changed the writable data so far: a journal compares it before and after
    // handle() to know what to record.
    std::uint64_t writes() const;
    // Executes a recorded request again, as at restart from a journal: routed like handle(), but
    // without fault rules, counters or an answer. The writes are absolute (a mask write too), so
    // replaying one already in the state changes nothing. False when it cannot be executed.
    bool replay_write(const RequestContext& context, std::span<const std::uint8_t> request);

  private:
    StateSnapshot copy_of(const UnitTable& table) const;
    bool load_into(UnitTable& table, std::string_view text, std::string& error);

    DeviceUnits& units_;
};

}  // namespace mblab::device
