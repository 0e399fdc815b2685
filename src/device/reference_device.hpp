#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "device/behaviour_engine.hpp"
#include "device/comm_state.hpp"
#include "device/profile.hpp"
#include "device/profile_loader.hpp"
#include "device/request_handler.hpp"
#include "device/unit_model.hpp"
#include "support/prng.hpp"

// The reference device: a profile's units behind the RequestHandler seam. It routes by unit id
// (serial broadcast and foreign addresses, TCP unit 0 / 0xFF), applies listen-only mode and the
// fault rules, serves the request in [APP]'s check order (function 01, values 03, map 02,
// execution 04), encodes the answer and keeps the FC 08 / 0B / 0C counters and log.
// Calls are serialized by an internal mutex, so several sessions may share one device.
namespace mblab::device {

struct UnitStats {
    std::uint8_t unit = 0;
    CommCounters counters;
    std::uint16_t event_count = 0;
    bool listen_only = false;
};

// What a tester is told about a unit before it runs (CTP 6.4-6.6).
struct UnitDeclaration {
    std::uint8_t unit = 0;
    std::uint16_t max_read_registers = 125;
    std::uint16_t max_read_bits = 2000;
    // Holding registers readable from address 0 without a hole: what a 7.5.2 sweep covers.
    std::uint32_t holding_registers = 0;
    std::optional<std::uint16_t> semi_signature;  // holding address of the SEMI signature
    bool object_messaging = false;                // FC 5B served
    std::array<bool, 256> functions{};
};

// The writable data of a device at one moment (see ReferenceDevice::snapshot_state).
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

class ReferenceDevice final : public RequestHandler {
  public:
    explicit ReferenceDevice(Profile profile);

    Reply handle(const RequestContext& context, std::span<const std::uint8_t> request,
                 std::span<std::uint8_t> response) override;

    // Line events the serial server sees before a frame reaches handle(); every unit on the
    // line counts them (FC 08 sub 0C and 12).
    void count_crc_error();  // CRC-16 or LRC mismatch
    void count_parity_error();
    void count_short_frame();  // fewer than 3 bytes, or cut by a t1.5 gap
    void count_overrun();
    // The server answered exception 06 itself (too many requests in flight) for `unit`.
    void count_busy_reply(std::uint8_t unit);

    const Profile& profile() const { return profile_; }
    std::vector<std::uint8_t> unit_ids() const;
    // Which unit ids (TCP) or addresses (a line) are answered, as route() decides it: "unit 1
    // (0 and 255 answer as 1; other unit ids are not answered)". For `mblab serve`'s banner.
    std::string addressing(Link link) const;
    // nullopt when the profile has no such unit.
    std::optional<UnitDeclaration> declaration(std::uint8_t unit) const;
    UnitDeclaration declaration() const;  // of the first unit
    std::optional<UnitStats> stats(std::uint8_t unit) const;
    // The FC 08 sub 03 delimiter the ASCII framer should expect (default LF).
    std::uint8_t ascii_delimiter(std::uint8_t unit) const;

    // Data access without Modbus, for the CLI and tests; nullopt / false for holes.
    std::optional<std::uint16_t> value(std::uint8_t unit, BankKind kind,
                                       std::uint16_t address) const;
    bool set_value(std::uint8_t unit, BankKind kind, std::uint16_t address, std::uint16_t value);

    // What the HTTP API (src/web) changes while the device serves, each under the device's lock
    // so a request sees a range either before or after (reference_device_live.cpp). nullopt /
    // false for a unit the profile lacks; a hole reads as nullopt and makes a write refused whole.
    std::optional<std::vector<std::optional<std::uint16_t>>> values(std::uint8_t unit,
                                                                    BankKind kind,
                                                                    std::uint32_t start,
                                                                    std::uint32_t count) const;
    bool set_values(std::uint8_t unit, BankKind kind, std::uint32_t start,
                    std::span<const std::uint16_t> values);
    std::optional<std::vector<FaultSpec>> fault_rules(std::uint8_t unit) const;
    // Replaces the unit's rules; their "every" counts start again.
    bool set_fault_rules(std::uint8_t unit, std::vector<FaultSpec> rules);
    // The FC 08 counters and event counter, as sub-function 0A clears them; the log stays.
    bool clear_counters(std::uint8_t unit);
    // The FC 0C event log, newest first.
    std::optional<std::vector<std::uint8_t>> event_log(std::uint8_t unit) const;

    // Writable data (coils, holding registers, file records) as JSON, and back; see
    // docs/profiles.md "State files". load_state changes nothing unless the whole text fits
    // the profile.
    std::string save_state() const;
    // The same data copied under the lock, to be turned into the file's text elsewhere: a copy
    // takes well under a millisecond where the text of the reference profile's 1.36 MB took up
    // to 25 ms on the server's thread.
    StateSnapshot snapshot_state() const;
    bool load_state(std::string_view text, std::string& error);

    // Moves the values of the profile's behaviours to `now` (BehaviourEngine::advance), under
    // the lock that requests take, so no request sees a value half-updated. The server calls
    // it from a timer when behaviour_deadline() comes, never from a request.
    void advance(std::chrono::steady_clock::time_point now,
                 std::chrono::system_clock::time_point wall);
    // When advance() is next due: min() before the first call, max() when no value moves.
    std::chrono::steady_clock::time_point behaviour_deadline() const;

    // Requests that changed the writable data (coils, holding registers, file records) so far: a
    // journal compares it before and after handle() to know what to record.
    std::uint64_t state_writes() const;
    // Executes a recorded request again, as at restart from a journal: routed like handle(), but
    // without fault rules, counters or an answer. The writes are absolute (a mask write too), so
    // replaying one already in the state changes nothing. False when it cannot be executed.
    bool replay_write(const RequestContext& context, std::span<const std::uint8_t> request);

  private:
    enum class RouteKind : std::uint8_t { Unit, Broadcast, Silent, Gateway };
    struct Route {
        RouteKind kind = RouteKind::Silent;
        UnitModel* unit = nullptr;
        protocol::ExceptionCode gateway = protocol::ExceptionCode::GatewayPathUnavailable;
    };
    Route route(const RequestContext& context);
    UnitModel* find_unit(std::uint8_t id);
    const UnitModel* find_unit(std::uint8_t id) const;

    Reply serve(UnitModel& unit, std::span<const std::uint8_t> request,
                std::span<std::uint8_t> response, bool broadcast);
    Reply answer(UnitModel& unit, std::uint8_t function, const MaybeResponse& outcome,
                 std::span<std::uint8_t> response, bool counts_as_event);
    Reply garbage(std::size_t size, std::span<std::uint8_t> response);
    void count_bus_error();

    Profile profile_;
    std::vector<UnitModel> units_;
    std::vector<BehaviourEngine> behaviours_;  // one per unit, in the same order
    std::array<std::int16_t, 256> unit_index_{};
    Prng prng_;
    std::array<std::uint8_t, 256> scratch_{};
    std::uint64_t state_writes_ = 0;
    mutable std::mutex mutex_;
};

Loaded<std::unique_ptr<ReferenceDevice>> load_profile(const std::filesystem::path& path);
Loaded<std::unique_ptr<ReferenceDevice>> load_profile_text(std::string_view text,
                                                           std::string_view name);

}  // namespace mblab::device
