#include "robustness/storm_requests.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>

#include "protocol/cursor.hpp"
#include "protocol/function_table.hpp"
#include "protocol/request_template.hpp"
#include "protocol/response.hpp"

namespace mblab::robustness {

namespace {

using Bytes = std::vector<std::uint8_t>;
using protocol::FunctionCode;

// FC 08 sub-function 0000 echoes its data ([APP] 6.8.1).
constexpr std::array<std::uint8_t, 2> kEchoData{0x12, 0x34};

// The table a storm's request names, as its request template says (FC 17's: the registers it
// writes).
std::optional<Table> table_of(std::uint8_t function) {
    const auto* request = protocol::find_template(function);
    const auto table = request != nullptr ? request->table : protocol::DataTable::None;
    constexpr std::pair<protocol::DataTable, Table> kTables[] = {
        {protocol::DataTable::Coils, Table::Coils},
        {protocol::DataTable::DiscreteInputs, Table::DiscreteInputs},
        {protocol::DataTable::HoldingRegisters, Table::HoldingRegisters},
        {protocol::DataTable::InputRegisters, Table::InputRegisters},
    };
    for (const auto& [from, to] : kTables) {
        if (from == table) return to;
    }
    return std::nullopt;
}

// The most places a write tries before it is set aside.
constexpr std::size_t kMostPlaces = 16;

// The files an FC 14 or FC 15 storm tries (record 0 of each), after one a DUT file declared.
constexpr std::array<std::uint16_t, 4> kFileProbes{1, 2, 3, 4};

// What a storm's place is called.
const char* place_noun(StormKind kind) {
    if (kind == StormKind::Fc01 || kind == StormKind::Fc05 || kind == StormKind::Fc0F)
        return "coil";
    if (kind == StormKind::Fc02) return "discrete input";
    if (kind == StormKind::Fc04) return "input register";
    if (kind == StormKind::Fc14 || kind == StormKind::Fc15) return "file";
    return kind == StormKind::Fc18 ? "FIFO" : "holding register";
}

// The places an FC 14, 15 or 18 storm tries in turn: the DUT file's first, then the usual ones.
std::vector<std::uint16_t> probed_places(StormKind kind, const Recon& recon) {
    const bool files = kind != StormKind::Fc18;
    std::vector<std::uint16_t> out;
    if (const auto declared = files ? recon.file_number : recon.fifo_address)
        out.push_back(*declared);
    const std::span<const std::uint16_t> usual =
        files ? std::span<const std::uint16_t>(kFileProbes) : std::span(kProbeAddresses);
    for (const auto place : usual) {
        if (std::find(out.begin(), out.end(), place) == out.end()) out.push_back(place);
    }
    return out;
}

// "1, 2, 3 or 4".
std::string places_text(const std::vector<std::uint16_t>& places) {
    std::string out;
    for (std::size_t i = 0; i < places.size(); ++i) {
        if (i > 0) out += i + 1 == places.size() ? " or " : ", ";
        out += std::to_string(places[i]);
    }
    return out;
}

// A write's places: inside the writable range, or where the reconnaissance was answered when
// writes are allowed anywhere; never the monitor's register (nor the coil at its address, for a
// device that maps one onto the other).
std::vector<std::uint16_t> write_places(Table table, const Recon& recon, const WritePolicy& policy,
                                        std::uint16_t monitor) {
    std::vector<std::uint16_t> out;
    const auto add_range = [&](std::uint32_t first, std::uint32_t last) {
        for (std::uint32_t a = first; a <= last && a <= 0xFFFF && out.size() < kMostPlaces; ++a) {
            if (a != monitor) out.push_back(static_cast<std::uint16_t>(a));
        }
    };
    if (policy.writable) {
        if (policy.writable->count > 0)
            add_range(policy.writable->start,
                      std::uint32_t{policy.writable->start} + policy.writable->count - 1);
    } else if (policy.allow_writes) {
        for (const auto& range : recon.ranges.of(table))
            add_range(range.first, range.last);
    }
    return out;
}

// The read whose answer is the value write storm `kind` at `address` writes back.
std::vector<std::uint8_t> read_of(StormKind kind, std::uint16_t address) {
    const auto reader = kind == StormKind::Fc15                              ? StormKind::Fc14
                        : kind == StormKind::Fc05 || kind == StormKind::Fc0F ? StormKind::Fc01
                                                                             : StormKind::Fc03;
    return storm_request(reader, address);
}

// Record 0's first register in an FC 14 answer of one register.
std::optional<std::uint16_t> record_value(const protocol::Response& decoded) {
    const auto* file = std::get_if<protocol::ReadFileRecordResponse>(&decoded);
    protocol::RegisterView data;
    std::size_t offset = 0;
    if (file == nullptr || !file->next(offset, data) || data.size() != 1) return std::nullopt;
    return data[0];
}

std::string not_served(std::uint8_t function, const Recon& recon) {
    const auto in = [&](const std::vector<std::uint8_t>& list) {
        return std::find(list.begin(), list.end(), function) != list.end();
    };
    if (in(recon.not_served))
        return fmt::format("not served: the device answered FC {:02X} with exception 01", function);
    if (in(recon.silent))
        return fmt::format(
            "not served: the device did not answer FC {:02X} in the "
            "reconnaissance",
            function);
    if (in(recon.not_asked))
        return fmt::format("FC {:02X} writes and was not asked in the reconnaissance", function);
    return fmt::format("not served: FC {:02X} is not among the codes the reconnaissance found",
                       function);
}

}  // namespace

Bytes storm_request(StormKind kind, std::uint16_t address, std::uint16_t value) {
    const auto code = static_cast<FunctionCode>(storm_words(kind).function);
    // Values as the wire carries them: a register's two bytes, a coil's bit 0.
    const std::array<std::uint8_t, 2> word{static_cast<std::uint8_t>(value >> 8),
                                           static_cast<std::uint8_t>(value)};
    const std::array<std::uint8_t, 1> bit{static_cast<std::uint8_t>(value != 0 ? 1 : 0)};
    // A file storm's one sub-request: record 0 of file `address`, one register.
    std::array<std::uint8_t, 9> sub{};
    protocol::WriteCursor file(sub);
    const protocol::FileRecordRef record{address, 0, 1};
    switch (kind) {
        case StormKind::Fc01:
        case StormKind::Fc02:
            return protocol::encoded_pdu(protocol::ReadBitsRequest{code, address, 1});
        case StormKind::Fc03:
        case StormKind::Fc04:
            return protocol::encoded_pdu(protocol::ReadRegistersRequest{code, address, 1});
        case StormKind::Fc05:
            return protocol::encoded_pdu(protocol::WriteSingleCoilRequest{
                address, static_cast<std::uint16_t>(value != 0 ? 0xFF00 : 0x0000)});
        case StormKind::Fc06:
            return protocol::encoded_pdu(protocol::WriteSingleRegisterRequest{address, value});
        case StormKind::Fc08:
            return protocol::encoded_pdu(protocol::DiagnosticsRequest{0x0000, kEchoData});
        case StormKind::Fc0F:
            return protocol::encoded_pdu(protocol::WriteMultipleCoilsRequest{address, 1, {bit, 1}});
        case StormKind::Fc10:
            return protocol::encoded_pdu(
                protocol::WriteMultipleRegistersRequest{address, 1, protocol::RegisterView(word)});
        case StormKind::Fc17:
            return protocol::encoded_pdu(protocol::ReadWriteMultipleRegistersRequest{
                address, 1, address, 1, protocol::RegisterView(word)});
        case StormKind::Fc2B:
            return protocol::encoded_pdu(protocol::ReadDeviceIdRequest{1, 0});
        case StormKind::Fc07:
            return protocol::encoded_pdu(protocol::ReadExceptionStatusRequest{});
        case StormKind::Fc0B:
            return protocol::encoded_pdu(protocol::GetCommEventCounterRequest{});
        case StormKind::Fc0C:
            return protocol::encoded_pdu(protocol::GetCommEventLogRequest{});
        case StormKind::Fc11:
            return protocol::encoded_pdu(protocol::ReportServerIdRequest{});
        case StormKind::Fc14:
            protocol::encode_file_record_ref(file, record);
            return protocol::encoded_pdu(protocol::ReadFileRecordRequest{file.written()});
        case StormKind::Fc15:
            protocol::encode_file_record_data(file, {record, protocol::RegisterView(word)});
            return protocol::encoded_pdu(protocol::WriteFileRecordRequest{file.written()});
        case StormKind::Fc16:
            // (value AND FFFF) OR (0000 AND NOT FFFF) is the value itself ([APP] 6.16): the
            // register is written with what it holds, with no read needed for it.
            return protocol::encoded_pdu(
                protocol::MaskWriteRegisterRequest{address, 0xFFFF, 0x0000});
        case StormKind::Fc18:
            return protocol::encoded_pdu(protocol::ReadFifoQueueRequest{address});
        case StormKind::Opens:
        case StormKind::SlowReaders:
        case StormKind::HalfOpen:
            break;
    }
    return {};
}

RequestPlan plan_request_storm(StormKind kind, const Recon& recon, const WritePolicy& policy,
                               std::uint16_t monitor) {
    RequestPlan plan;
    const std::uint8_t function = storm_words(kind).function;
    if (function == 0) {
        plan.not_run = fmt::format("{} is no request storm", storm_key(kind));
        return plan;
    }
    // The monitor's register answers FC 03 (the monitor needs it): served whatever was probed.
    if (kind == StormKind::Fc03) {
        plan.address = monitor;
        plan.pdu = storm_request(kind, monitor);
        return plan;
    }
    if (!recon.serves(function)) {
        plan.not_run = not_served(function, recon);
        return plan;
    }
    // A file or a FIFO is not found by reading tables: the places are probed before the storm.
    if (kind == StormKind::Fc14 || kind == StormKind::Fc18) {
        plan.places = probed_places(kind, recon);
        return plan;
    }
    if (kind == StormKind::Fc15) {
        // may_send: file records lie in no --writable range of holding registers.
        if (!policy.allow_writes) {
            plan.not_run =
                "file records lie outside --writable (holding registers): only --allow-writes "
                "lets FC 15 write one back";
            return plan;
        }
        plan.places = probed_places(kind, recon);
        plan.address = plan.places.front();
        plan.read_first = read_of(kind, plan.address);
        return plan;
    }
    const auto table = table_of(function);
    if (!protocol::writes(function)) {
        // A place the reconnaissance read with data; without one, the usual places are asked
        // before the storm, so that a storm of exception answers is never reported as held.
        if (table && recon.ranges.of(*table).empty()) {
            plan.places.assign(kProbeAddresses.begin(), kProbeAddresses.end());
            return plan;
        }
        if (table) plan.address = recon.ranges.of(*table).front().first;
        plan.pdu = storm_request(kind, plan.address);
        return plan;
    }
    plan.places = write_places(*table, recon, policy, monitor);
    if (plan.places.empty()) {
        plan.not_run = fmt::format(
            "no {} it may write other than the monitor's register {}: --writable START:COUNT "
            "(outside it) or --allow-writes lets it write one back{}",
            *table == Table::Coils ? "coil" : "holding register", monitor,
            kind == StormKind::Fc17 ? " (FC 17 has no read-only form: its write quantity is 1 to "
                                      "121, MODBUS Application Protocol V1.1b3 6.17)"
                                    : "");
        return plan;
    }
    plan.address = plan.places.front();
    plan.read_first = read_of(kind, plan.address);
    // The write must pass the policy the cases pass.
    if (!may_send(storm_request(kind, plan.address), policy)) {
        plan.not_run =
            fmt::format("the write policy does not let FC {:02X} write {}", function, plan.address);
        plan.read_first.clear();
    }
    return plan;
}

void write_back(StormKind kind, RequestPlan& plan,
                const std::optional<std::vector<std::uint8_t>>& answer) {
    if (plan.read_first.empty() || !plan.not_run.empty()) return;
    const bool coil = plan.read_first[0] == 0x01;
    const auto what = fmt::format("{} {} does not answer FC {:02X}: no value to write back",
                                  place_noun(kind), plan.address, plan.read_first[0]);
    if (!answer) {
        plan.not_run = what;
        return;
    }
    const auto decoded = protocol::decode_response(*answer);
    if (!decoded) {
        plan.not_run = what;
        return;
    }
    if (const auto* bits = std::get_if<protocol::ReadBitsResponse>(&*decoded);
        coil && bits != nullptr && !bits->packed.empty()) {
        plan.pdu = storm_request(kind, plan.address, bits->packed[0] & 0x01);
        return;
    }
    if (const auto* registers = std::get_if<protocol::ReadRegistersResponse>(&*decoded);
        !coil && registers != nullptr && registers->values.size() == 1) {
        plan.pdu = storm_request(kind, plan.address, registers->values[0]);
        return;
    }
    if (const auto value = record_value(*decoded); kind == StormKind::Fc15 && value) {
        plan.pdu = storm_request(kind, plan.address, *value);
        return;
    }
    plan.not_run = what;
}

void choose_write_place(StormKind kind, RequestPlan& plan, const StormAsk& ask) {
    if (plan.read_first.empty() || !plan.not_run.empty()) return;
    std::string why;
    for (const auto place : plan.places) {
        RequestPlan tried = plan;
        tried.address = place;
        tried.read_first = read_of(kind, place);
        write_back(kind, tried, ask(tried.read_first));
        if (!tried.not_run.empty()) {
            why = tried.not_run;
            continue;
        }
        const auto echo = ask(tried.pdu);
        if (echo && !echo->empty() && (*echo)[0] == tried.pdu[0]) {
            plan = std::move(tried);
            return;
        }
        why = fmt::format("{} {} refused the write of its own value ({})", place_noun(kind), place,
                          !echo || echo->empty() ? std::string("no answer")
                          : echo->size() >= 2    ? fmt::format("exception {:02X}", (*echo)[1])
                                                 : std::string("an answer of another function"));
    }
    plan.pdu.clear();
    plan.not_run = plan.places.size() > 1
                       ? fmt::format("none of the {} places tried takes a write back; the last: {}",
                                     plan.places.size(), why)
                       : why;
}

void choose_read_place(StormKind kind, RequestPlan& plan, const StormAsk& ask) {
    if (!plan.pdu.empty() || !plan.not_run.empty()) return;
    const std::uint8_t function = storm_words(kind).function;
    for (const auto place : plan.places) {
        auto pdu = storm_request(kind, place);
        const auto answer = ask(pdu);
        if (answer && !answer->empty() && (*answer)[0] == function) {
            plan.address = place;
            plan.pdu = std::move(pdu);
            return;
        }
    }
    const bool declarable = kind == StormKind::Fc14 || kind == StormKind::Fc18;
    plan.not_run =
        fmt::format("no {} answered FC {:02X} with data at {}{}", place_noun(kind), function,
                    places_text(plan.places),
                    !declarable               ? ""
                    : kind == StormKind::Fc18 ? " (a DUT file's fifo_address names one: --dut)"
                                              : " (a DUT file's file_number names one: --dut)");
}

void choose_place(StormKind kind, RequestPlan& plan, const StormAsk& ask) {
    if (!plan.read_first.empty()) {
        choose_write_place(kind, plan, ask);
    } else {
        choose_read_place(kind, plan, ask);
    }
}

bool names_address(StormKind kind) {
    return table_of(storm_words(kind).function).has_value();
}

}  // namespace mblab::robustness
