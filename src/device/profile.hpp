#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "device/behaviour_spec.hpp"
#include "device/role_rules.hpp"
#include "protocol/exception_code.hpp"

// A device profile after loading and validation: plain data, no TOML. docs/profiles.md is the
// user's reference for every field; the loader (profile_loader.hpp) guarantees the invariants
// noted here, so the device never re-checks them.
namespace mblab::device {

enum class Access : std::uint8_t { ReadOnly, ReadWrite, WriteOnly };

enum class BankKind : std::uint8_t { Coils, DiscreteInputs, HoldingRegisters, InputRegisters };
inline constexpr std::size_t kBankKinds = 4;

// Typed names document what a range holds; u32/f32 take two registers (high word first),
// a string two characters per register (first character in the high byte).
enum class ValueType : std::uint8_t { Bit, U16, I16, U32, F32, String };

struct RangeSpec {
    std::uint32_t start = 0;
    std::uint32_t count = 0;  // start + count <= 65536; ranges of one bank never overlap
    Access access = Access::ReadWrite;
    std::vector<std::uint16_t> values;  // initial value of each address (bits are 0 or 1)
    ValueType type = ValueType::U16;
    std::string name;
    std::string description;
};

// What a unit answers when a request touches a range its access forbids. No value means the
// lenient behaviour: writes to read-only addresses are accepted and ignored, reads of write-only
// addresses return zeros.
struct AccessPolicy {
    std::optional<protocol::ExceptionCode> write_read_only =
        protocol::ExceptionCode::IllegalDataAddress;
    std::optional<protocol::ExceptionCode> read_write_only =
        protocol::ExceptionCode::IllegalDataAddress;
};

// A holding-register point whose value is checked on write (the SunSpec chain lays them,
// sunspec_chain.hpp): a write that leaves it outside its values is refused with 03.
struct PointRule {
    std::uint32_t start = 0;
    std::uint16_t count = 1;  // registers, high word first
    bool is_signed = false;
    std::vector<std::int64_t> allowed = {};  // an enum's symbols; empty: any value in min..max
    std::optional<std::int64_t> min = {};
    std::optional<std::int64_t> max = {};
    // A read or write that takes only some of its registers is refused with 02.
    bool whole = false;
    // Writes are answered but not kept (a device built wrong on purpose, to test the tester).
    bool applied = true;
};

struct IdentityObject {
    std::uint8_t id = 0;
    std::string value;
};

struct IdentitySpec {
    std::vector<IdentityObject> objects;  // sorted by id, ids unique, values <= 244 bytes
    std::array<bool, 5> read_codes{false, true, true, true, true};  // index = read device id code
    // Stream access (codes 01..03) naming an object the device lacks: restart at object 0 as
    // [APP] says, or answer exception 02 as the instrument of [INSTR 5.7.1] does.
    bool unknown_object_restarts = true;
};

struct DiagnosticsSpec {
    std::vector<std::uint16_t> sub_functions;  // supported, sorted; others answer exception 01
    // Sub-function 00 data length in 16-bit words; outside: exception 03 (INSTR 5.7.1: 1..100).
    std::optional<std::uint16_t> echo_min_words;
    std::optional<std::uint16_t> echo_max_words;
    std::uint16_t diagnostic_register = 0;
};

struct ServerIdSpec {  // FC 11
    std::string id = "mblab";
    bool running = true;
    std::string extra;
};

struct FileSpec {  // FC 14/15: one register per record
    std::uint16_t number = 1;
    std::vector<std::uint16_t> records;  // record count <= 10000
};

struct ObjectAttribute {
    std::uint16_t id = 0;
    std::vector<std::uint8_t> value;
};

struct SemiObject {  // FC 5B
    std::uint16_t class_id = 0;
    std::uint16_t instance_id = 0;
    std::vector<ObjectAttribute> attributes;
};

enum class FaultAction : std::uint8_t { Delay, Drop, Exception, Garbage, Close };

struct FaultSpec {
    FaultAction action = FaultAction::Drop;
    std::chrono::milliseconds delay{0};
    protocol::ExceptionCode exception = protocol::ExceptionCode::ServerDeviceFailure;
    std::uint8_t garbage_bytes = 8;
    std::vector<std::uint8_t> functions;         // empty: every function code
    std::optional<std::uint16_t> first_address;  // inclusive address filter: the request's
    std::optional<std::uint16_t> last_address;   // data range must overlap it
    std::uint32_t every = 0;   // fire on every Nth matching request; 0: not counted
    double probability = 1.0;  // else fire with this probability
};

struct UnitSpec {
    std::uint8_t id = 1;
    std::string name;
    std::array<std::vector<RangeSpec>, kBankKinds> banks;  // each sorted by start
    AccessPolicy access_policy;
    std::array<bool, 256> functions{};  // supported function codes
    std::uint16_t max_read_registers = 125;
    std::uint16_t max_read_bits = 2000;
    std::uint8_t exception_status = 0;            // FC 07
    std::optional<std::uint16_t> semi_signature;  // holding address of "SE" "MI" checksum
    std::vector<std::uint16_t> fifos;             // holding addresses of FIFO count registers
    ServerIdSpec server_id;
    DiagnosticsSpec diagnostics;
    IdentitySpec identification;
    std::vector<FileSpec> files;
    std::vector<SemiObject> objects;
    std::vector<FaultSpec> faults;
    std::vector<BehaviourSpec> behaviours;
    std::vector<PointRule> point_rules;  // sorted by start, not overlapping
};

// Which unit answers a TCP unit id no unit of the profile has (0 and 0xFF always go to the
// first unit, as on a direct server).
enum class UnmatchedUnit : std::uint8_t { FirstUnit, Ignore, PathUnavailable, TargetFailed };

struct Profile {
    std::string name;
    std::string description;
    std::string source;           // file name or the name given to the text
    std::vector<UnitSpec> units;  // at least one, unique ids inside [min_address, max_address]
    std::uint64_t fault_seed = 1;
    std::uint64_t behaviour_seed = 1;  // random and random-walk behaviours draw from it
    UnmatchedUnit unmatched_unit = UnmatchedUnit::Ignore;
    std::uint8_t min_address = 1;
    std::uint8_t max_address = 247;
    // [[role]] tables: what each Modbus/TCP Security role may do (mbaps:// only).
    std::vector<RoleRule> roles;
    // [tls]: the server's certificate, its key and the CA of client certificates, for
    // `serve --listen mbaps://` when --cert/--key/--ca do not name them; relative paths are
    // relative to the profile's file. Empty when not given.
    struct TlsFiles {
        std::string cert;
        std::string key;
        std::string ca;
    } tls;
};

}  // namespace mblab::device
