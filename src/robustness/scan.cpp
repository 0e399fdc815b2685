#include "robustness/scan.hpp"

#include <fmt/core.h>

#include <algorithm>

#include "conformance/plain_requests.hpp"
#include "conformance/session.hpp"
#include "protocol/limits.hpp"
#include "robustness/session_ask.hpp"

namespace mblab::robustness {

namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr std::array<std::uint8_t, kTableCount> kReadFunction{0x01, 0x02, 0x03, 0x04};
// Per read, as [APP] 6.1-6.4 allow.
constexpr std::array<std::uint16_t, kTableCount> kMostPerRead{
    protocol::limits::kMaxReadBits, protocol::limits::kMaxReadBits,
    protocol::limits::kMaxReadRegisters, protocol::limits::kMaxReadRegisters};
constexpr std::uint32_t kAddressSpace = 65536;
// CTP 7.13.1: class 1, instance 1, get attribute 1: a read.
constexpr std::array<std::uint8_t, 11> kGetAttribute{0x5B, 0x09, 0x00, 0x00, 0x01, 0x00,
                                                     0x01, 0x00, 0x07, 0x00, 0x01};
constexpr std::array<std::uint16_t, 3> kSemiSignature{0x5345, 0x4D49, 0x5F72};
constexpr std::uint8_t kLastLineAddress = 247;  // [SER 2.2]

Bytes read_pdu(Table table, std::uint16_t address, std::uint16_t quantity) {
    return {kReadFunction[static_cast<std::size_t>(table)], static_cast<std::uint8_t>(address >> 8),
            static_cast<std::uint8_t>(address), static_cast<std::uint8_t>(quantity >> 8),
            static_cast<std::uint8_t>(quantity)};
}

bool is_exception(const std::optional<Bytes>& answer, std::uint8_t function) {
    return answer && answer->size() >= 2 && (*answer)[0] == (function | 0x80);
}

// Reads of one table of one unit, each answer checked against its request.
class TableReader {
  public:
    TableReader(const Ask& ask, std::uint8_t unit, Table table)
        : ask_(ask), unit_(unit), table_(table) {}

    // Whether `quantity` items from `address` came back as data; the registers' values are
    // kept in `words` when given.
    bool read(std::uint32_t address, std::uint32_t quantity, std::vector<std::uint16_t>* words) {
        const auto pdu = read_pdu(table_, static_cast<std::uint16_t>(address),
                                  static_cast<std::uint16_t>(quantity));
        const auto answer = ask_(unit_, pdu);
        AnsweredRanges scratch;
        if (!answer || !note_answered(pdu, *answer, scratch)) return false;
        if (words != nullptr) {
            for (std::size_t i = 2; i + 1 < answer->size(); i += 2)
                words->push_back(static_cast<std::uint16_t>((*answer)[i] << 8 | (*answer)[i + 1]));
        }
        return true;
    }
    bool one(std::uint32_t address) { return read(address, 1, nullptr); }

  private:
    const Ask& ask_;
    std::uint8_t unit_;
    Table table_;
};

// The run of addresses answered single reads, from the first probe address that answers:
// where it ends (and starts, when not at 0) is found by halving, which assumes no holes.
std::optional<AddressRange> single_read_run(TableReader& reader) {
    std::int64_t before = -1;  // an address known not to answer, or -1
    for (std::uint16_t candidate : kProbeAddresses) {
        if (!reader.one(candidate)) {
            before = candidate;
            continue;
        }
        std::int64_t low = before;  // does not answer
        std::int64_t high = candidate;
        while (high - low > 1) {
            const std::int64_t middle = (low + high) / 2;
            (reader.one(static_cast<std::uint32_t>(middle)) ? high : low) = middle;
        }
        const std::int64_t first = high;
        low = candidate;
        high = kAddressSpace;  // past the end
        while (high - low > 1) {
            const std::int64_t middle = (low + high) / 2;
            (reader.one(static_cast<std::uint32_t>(middle)) ? low : high) = middle;
        }
        return AddressRange{static_cast<std::uint16_t>(first), static_cast<std::uint16_t>(low)};
    }
    return std::nullopt;
}

// The run read whole, in the largest reads the table allows: it ends before the first address
// no read reaches. A read refused whole is retried shorter (the device's own limit per read may
// be below the protocol's).
AddressRange confirmed(TableReader& reader, AddressRange run, std::uint16_t most,
                       std::vector<std::uint16_t>* words) {
    std::uint32_t at = run.first;
    const std::uint32_t end = std::uint32_t{run.last} + 1;
    while (at < end) {
        const std::uint32_t quantity = std::min<std::uint32_t>(most, end - at);
        if (reader.read(at, quantity, words)) {
            at += quantity;
            continue;
        }
        std::uint32_t good = 0;
        std::uint32_t bad = quantity;
        while (bad - good > 1) {
            const std::uint32_t middle = (good + bad) / 2;
            (reader.read(at, middle, nullptr) ? good : bad) = middle;
        }
        if (good == 0) break;
        if (words != nullptr && !reader.read(at, good, words)) break;
        most = static_cast<std::uint16_t>(good);
        at += good;
    }
    return {run.first, static_cast<std::uint16_t>(at - 1)};
}

std::optional<std::uint16_t> signature_at(const std::vector<std::uint16_t>& words,
                                          std::uint16_t first) {
    const auto found =
        std::search(words.begin(), words.end(), kSemiSignature.begin(), kSemiSignature.end());
    if (found == words.end()) return std::nullopt;
    return static_cast<std::uint16_t>(first + (found - words.begin()));
}

Bytes echo_pdu(std::uint16_t words) {
    Bytes pdu{0x08, 0x00, 0x00};
    for (std::uint16_t i = 0; i < words; ++i) {
        pdu.push_back(static_cast<std::uint8_t>(0xA0 + (i >> 8)));
        pdu.push_back(static_cast<std::uint8_t>(i));
    }
    return pdu;
}

EchoScan scan_echo(const Ask& ask, std::uint8_t unit) {
    EchoScan echo;
    echo.asked = true;
    const auto echoed = [&](std::uint16_t words) {
        const auto pdu = echo_pdu(words);
        const auto answer = ask(unit, pdu);
        return answer && *answer == pdu;
    };
    if (!echoed(1)) return echo;
    std::uint16_t good = 1;
    std::uint16_t bad = kMaxEchoWords + 1;
    if (echoed(kMaxEchoWords)) {
        good = kMaxEchoWords;
    } else {
        bad = kMaxEchoWords;
    }
    while (bad - good > 1) {
        const auto middle = static_cast<std::uint16_t>((good + bad) / 2);
        (echoed(middle) ? good : bad) = middle;
    }
    echo.echoed = good;
    if (good == kMaxEchoWords) return echo;
    const auto answer = ask(unit, echo_pdu(static_cast<std::uint16_t>(good + 1)));
    if (is_exception(answer, 0x08)) {
        echo.refusal = (*answer)[1];
    } else {
        echo.data_refused = answer.has_value();
    }
    return echo;
}

// Whether the harmless request of `function` was answered with data rather than an exception.
bool answers_data(const Ask& ask, std::uint8_t unit, std::uint8_t function) {
    const auto request = conformance::harmless_request_pdu(function);
    if (!request) return false;
    const auto answer = ask(unit, *request);
    return answer && !answer->empty() && (*answer)[0] == function;
}

bool answers(const std::optional<Bytes>& answer) {
    if (!answer || answer->empty()) return false;
    // 0A and 0B are a gateway's: no device answered behind it ([APP] 7).
    const bool exception = ((*answer)[0] & 0x80) != 0 && answer->size() >= 2;
    return !(exception && ((*answer)[1] == 0x0A || (*answer)[1] == 0x0B));
}

void scan_unit(const Ask& ask, DeviceScan& out) {
    const std::uint8_t unit = out.recon.unit;
    ReconOptions recon_options;
    recon_options.unit = unit;
    recon_options.reads_only = true;
    if (auto failed = reconnoitre(ask, recon_options, out.recon)) out.recon_failure = *failed;
    for (std::size_t i = 0; i < kTableCount; ++i) {
        const auto table = static_cast<Table>(i);
        if (!out.recon.serves(kReadFunction[i])) continue;
        TableReader reader(ask, unit, table);
        const auto run = single_read_run(reader);
        if (!run) continue;
        const bool holding = table == Table::HoldingRegisters;
        const std::uint16_t most =
            holding && out.recon_failure.empty() ? out.recon.max_read : kMostPerRead[i];
        std::vector<std::uint16_t> words;
        out.tables[i] = confirmed(reader, *run, most, holding ? &words : nullptr);
        if (holding) out.semi_signature = signature_at(words, run->first);
    }
    if (out.recon.serves(0x08)) out.echo = scan_echo(ask, unit);
    const auto messaging = ask(unit, kGetAttribute);
    out.object_messaging_silent = !messaging || messaging->empty();
    out.object_messaging =
        !out.object_messaging_silent && !(is_exception(messaging, 0x5B) && (*messaging)[1] == 0x01);
    if (out.recon.serves(0x14) && answers_data(ask, unit, 0x14)) out.file_number = 1;
    if (out.recon.serves(0x18) && answers_data(ask, unit, 0x18)) out.fifo_address = 0;
}

}  // namespace

std::string units_text(const std::vector<std::uint8_t>& units, const char* last_joint) {
    std::vector<std::string> parts;
    for (std::size_t i = 0; i < units.size();) {
        std::size_t j = i;
        while (j + 1 < units.size() && units[j + 1] == units[j] + 1)
            ++j;
        parts.push_back(j - i >= 2 ? fmt::format("{}-{}", units[i], units[j])
                                   : std::to_string(units[i]));
        if (j - i == 1) parts.push_back(std::to_string(units[j]));
        i = j + 1;
    }
    std::string out;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        if (i > 0) out += i + 1 == parts.size() ? last_joint : ", ";
        out += parts[i];
    }
    return out;
}

protocol::Result<DeviceScan, std::string> scan_device(const Ask& device,
                                                      const ScanOptions& options) {
    DeviceScan out;
    out.identity.reason = "not asked";
    const Ask ask = [&](std::uint8_t unit,
                        std::span<const std::uint8_t> pdu) -> std::optional<Bytes> {
        if (options.line && (unit == 0 || unit > kLastLineAddress)) return std::nullopt;
        ++out.requests;
        return device(unit, pdu);
    };
    const auto probe = read_pdu(Table::HoldingRegisters, 0, 1);
    for (std::uint8_t unit : options.units) {
        if (options.line && (unit == 0 || unit > kLastLineAddress)) continue;
        out.tried.push_back(unit);
        if (answers(ask(unit, probe))) out.answering.push_back(unit);
    }
    if (out.answering.empty()) {
        return fmt::format(
            "no answer on unit {} to {} request{} (FC 03, holding register 0): check the port "
            "and --units",
            units_text(out.tried, " or "), out.tried.size(), out.tried.size() == 1 ? "" : "s");
    }
    // 0 and 255 reach a Modbus/TCP device itself when it is not a gateway: another unit that
    // answers is its own address.
    const auto own = std::find_if(out.answering.begin(), out.answering.end(),
                                  [](std::uint8_t unit) { return unit != 0 && unit != 0xFF; });
    out.recon.unit = own != out.answering.end() ? *own : out.answering.front();
    scan_unit(ask, out);
    return out;
}

protocol::Result<DeviceScan, std::string> scan_target(const client::Target& target,
                                                      const ScanOptions& options,
                                                      std::chrono::milliseconds timeout) {
    conformance::Dut dut;
    conformance::EngineOptions engine;
    engine.timeout = timeout;
    engine.connect_timeout = std::max(timeout, std::chrono::milliseconds(3000));
    protocol::Result<DeviceScan, std::string> scan = std::string();
    {
        conformance::Session session(target, dut, engine);
        client::LinkError error;
        if (!session.connect(error)) return fmt::format("{}: {}", target.name, error.message);
        scan = scan_device(session_ask(session, timeout), options);
        session.close();
    }
    if (!scan) return fmt::format("{}: {}", target.name, scan.error());
    // A session of its own, since the identity is asked of the unit the session declares.
    dut.unit = scan->recon.unit;
    conformance::Session session(target, dut, engine);
    scan->identity = conformance::ask_device_identity(session);
    scan->requests += session.requests();
    session.close();
    return scan;
}

}  // namespace mblab::robustness
