#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "conformance/pattern.hpp"
#include "protocol/result.hpp"
#include "security/tls_context.hpp"

// What is declared about the device under test (CTP section 6, plus the facts extended
// suites need). Anything not declared stays empty, and cases that need it are N/A.
namespace mblab::conformance {

// Modbus/TCP Security, for the security suite (docs/security.md): the client certificates the
// tester presents, and what the device's rights database gives which role.
struct SecurityDut {
    // The tester's own certificate, one the device accepts; its role should be allowed reads of
    // holding register 0, as every suite run over mbaps:// asks for them.
    security::TlsFiles client;
    // A directory in `mblab pki`'s layout (client-norole.pem, client-expired.pem, ...): the
    // certificates the device must refuse or treat as the NULL role, and client-ROLE.pem.
    std::string pki;
    std::string read_only_role;  // may read holding register 0x0010 (FC 03) and may not write it
    std::string write_role;      // may write holding register 0x0010 (FC 06)
    // The device's rights database gives the NULL role (a certificate without a role) some
    // rights ([SEC] ), so its requests are not all answered 01.
    bool null_role_granted = false;
};

struct Dut {
    // 6.4 asks the vendor for a unit id other than 0. mblab's one default for every command and
    // framing is 1: the serial address most devices ship with, and the id most TCP devices
    // answer; the policy lab's 0 is `--unit 0`.
    std::uint8_t unit = 1;
    std::optional<std::uint32_t> registers;  // 6.6: holding registers, 1..65536
    std::uint16_t max_read = 125;            // 6.6: most registers one FC 03 may read
    bool object_messaging = false;           // 6.5: FC 5B
    bool alternate_encoding = false;         // 6.5: SEMI signature in the registers

    std::optional<std::uint32_t> coils;
    std::optional<std::uint32_t> discrete_inputs;
    std::optional<std::uint32_t> input_registers;
    std::optional<std::uint16_t> read_only_register;
    std::optional<std::uint16_t> read_only_coil;
    std::optional<std::uint16_t> fifo_address;
    bool fifo_count_writable = false;  // FC 06 may set the FIFO's count register (fc18.2)
    std::optional<std::uint16_t> file_number;
    std::optional<std::uint16_t> echo_max_words;  // FC 08/00 data limit (INSTR 5.7.1: 100)

    // On a serial line [SER 2.2, 2.4.1]: an address no device on the line answers (the serial
    // suite's "another address"; a multi-drop line knows which are free), and the delay the
    // device needs after a broadcast before the master may ask again.
    std::optional<std::uint8_t> other_address;
    std::optional<std::uint32_t> turnaround_ms;
    // Line settings to try when the device is silent at the target's, each in the serial URL's
    // form: "baud=9600&parity=N&stop=2" [SER 2.5.1, 2.5.2].
    std::vector<std::string> line_settings;

    // Empty over Modbus/TCP; "RTU", "ASCII" or "RTU over TCP" when the tester reaches the device
    // over a serial framing, where cases that require "mbap" are N/A.
    std::string serial_framing;

    SecurityDut security;

    std::string declared_by = "defaults";  // "flags", "dut.toml", "profile reference.toml"
};

// On RTU and ASCII framings a device answers at an address from 1 to 247 (0 is the broadcast,
// never answered). A unit nobody declared becomes 1; a declared one outside 1..247 gives the
// one-line error, naming `target`.
std::optional<std::string> settle_serial_unit(Dut& dut, bool declared, std::string_view target);

// Keys of a DUT file, which are also the names `requires` and placeholders may use.
const std::vector<std::string_view>& dut_keys();

// What `dut` declares for one of dut_keys(), as reports show it (line settings joined by ", ");
// std::monostate for a key left undeclared or unknown.
using DutValue = std::variant<std::monostate, bool, std::uint32_t, std::string>;
DutValue dut_value(const Dut& dut, std::string_view key);

// Loads a DUT file (TOML, the keys above at top level). Errors name the file, line and reason.
protocol::Result<Dut, std::string> load_dut_file(const std::string& path);

// Facts as placeholders see them: {unit} (1 byte) and 16-bit values, plus computed ones:
//   {out_of_range_registers}  offset and count for CTP 9.1.2 (4 bytes)
//   {echo_max_data} / {echo_over_data}  FC 08 data words at and one past the echo limit
class DutFacts : public FactSource {
  public:
    explicit DutFacts(const Dut& dut) : dut_(dut) {}
    std::optional<std::vector<std::uint8_t>> fact(std::string_view name) const override;

  private:
    const Dut& dut_;
};

bool is_known_fact(std::string_view name);

// A `requires` entry: a fact name, optionally compared with a number ("coils >= 2000"), or
// "mbap": the case tests the MBAP header or the TCP stream and needs a Modbus/TCP device; "line":
// it tests a serial line's rules and needs RTU, ASCII or RTU over TCP; "ascii": ASCII framing.
struct Requirement {
    std::string fact;
    std::string op;  // "", ">=", "<=", ">", "<", "==", "!="
    std::int64_t value = 0;
    std::string text;
};

protocol::Result<Requirement, std::string> parse_requirement(std::string_view text);

// Why a requirement is not met, for the N/A line.
struct Unmet {
    std::string reason;
    // The DUT key whose declaration is missing ("" when the declared value does not meet the
    // requirement, or it is not a declaration at all): the summary counts these.
    std::string undeclared;
};

// Nothing when the DUT meets the requirement.
std::optional<Unmet> unmet(const Requirement& requirement, const Dut& dut);

}  // namespace mblab::conformance
