#include "device/unit_model.hpp"

#include <algorithm>

#include "device/device_identification.hpp"
#include "device/diagnostics.hpp"
#include "device/object_messaging.hpp"
#include "protocol/limits.hpp"

namespace mblab::device {

namespace {

using protocol::ExceptionCode;
using protocol::FunctionCode;

constexpr std::uint8_t code(FunctionCode fc) {
    return static_cast<std::uint8_t>(fc);
}

MaybeResponse refused(FunctionCode fc, ExceptionCode why) {
    return exception_response(code(fc), why);
}

// A write answered with the echo of its request, unless storing it was refused.
template <class Answer>
MaybeResponse echo_unless(std::optional<ExceptionCode> why, const Answer& echo) {
    if (why) return refused(Answer::kFunction, *why);
    return protocol::Response{echo};
}

}  // namespace

UnitModel::UnitModel(const UnitSpec& spec)
    : spec_(spec), files_(spec.files), faults_(spec.faults), points_(spec.point_rules) {
    for (std::size_t kind = 0; kind < kBankKinds; ++kind) {
        banks_[kind] = DataBank(spec.banks[kind]);
        // The bank holds the values now; the spec keeps the map for queries.
        for (auto& range : spec_.banks[kind])
            std::vector<std::uint16_t>().swap(range.values);
    }
    std::vector<FileSpec>().swap(spec_.files);
    comm_.diagnostic_register = spec.diagnostics.diagnostic_register;
}

UnitModel::Permit UnitModel::permit(bool mapped, bool crosses, std::optional<ExceptionCode> policy,
                                    Access closed) {
    if (!mapped) return {ExceptionCode::IllegalDataAddress, std::nullopt};
    if (!crosses) return {};
    if (policy) return {policy, std::nullopt};
    return {std::nullopt, closed};
}

UnitModel::Permit UnitModel::may_read(BankKind kind, std::uint32_t address,
                                      std::uint32_t count) const {
    const auto span = bank(kind).find(address, count);
    return permit(span.mapped, span.has_write_only, spec_.access_policy.read_write_only,
                  Access::WriteOnly);
}

UnitModel::Permit UnitModel::may_write(BankKind kind, std::uint32_t address,
                                       std::uint32_t count) const {
    const auto span = bank(kind).find(address, count);
    return permit(span.mapped, span.has_read_only, spec_.access_policy.write_read_only,
                  Access::ReadOnly);
}

std::optional<ExceptionCode> UnitModel::store(BankKind kind, std::uint32_t address,
                                              std::span<const std::uint16_t> values) {
    const Permit permit = may_write(kind, address, static_cast<std::uint32_t>(values.size()));
    if (permit.refusal) return permit.refusal;
    return write_permitted(kind, address, values, permit.skip);
}

std::optional<ExceptionCode> UnitModel::write_permitted(BankKind kind, std::uint32_t address,
                                                        std::span<const std::uint16_t> values,
                                                        std::optional<Access> skip) {
    if (kind != BankKind::HoldingRegisters || points_.empty()) {
        bank(kind).write(address, values, skip);
        return std::nullopt;
    }
    if (auto why = points_.check_write(address, values, bank(kind))) return why;
    std::vector<std::uint16_t> kept(values.begin(), values.end());
    points_.keep_unapplied(address, kept, bank(kind));
    bank(kind).write(address, kept, skip);
    return std::nullopt;
}

std::optional<ExceptionCode> UnitModel::load_registers(BankKind kind, std::uint32_t address,
                                                       std::uint32_t count,
                                                       std::span<std::uint8_t> out) const {
    const Permit permit = may_read(kind, address, count);
    if (permit.refusal) return permit.refusal;
    if (kind == BankKind::HoldingRegisters) {
        if (auto why = points_.check_read(address, count)) return why;
    }
    bank(kind).read_be(address, out.first(2 * count), permit.skip);
    return std::nullopt;
}

MaybeResponse UnitModel::read_bits(const protocol::ReadBitsRequest& request,
                                   std::span<std::uint8_t> scratch) {
    if (request.quantity > spec_.max_read_bits) {
        return refused(request.function, ExceptionCode::IllegalDataValue);
    }
    const BankKind kind =
        request.function == FunctionCode::ReadCoils ? BankKind::Coils : BankKind::DiscreteInputs;
    const Permit permit = may_read(kind, request.address, request.quantity);
    if (permit.refusal) return refused(request.function, *permit.refusal);
    std::array<std::uint16_t, protocol::limits::kMaxReadBits> bits{};
    bank(kind).read(request.address, std::span(bits).first(request.quantity), permit.skip);
    const std::size_t bytes = (request.quantity + 7u) / 8u;
    std::fill_n(scratch.begin(), bytes, 0);
    for (std::size_t i = 0; i < request.quantity; ++i) {
        if (bits[i]) scratch[i / 8] = static_cast<std::uint8_t>(scratch[i / 8] | 1u << (i % 8));
    }
    return protocol::Response{protocol::ReadBitsResponse{request.function, scratch.first(bytes)}};
}

MaybeResponse UnitModel::read_registers(const protocol::ReadRegistersRequest& request,
                                        std::span<std::uint8_t> scratch) {
    if (request.quantity > spec_.max_read_registers) {
        return refused(request.function, ExceptionCode::IllegalDataValue);
    }
    const BankKind kind = request.function == FunctionCode::ReadHoldingRegisters
                              ? BankKind::HoldingRegisters
                              : BankKind::InputRegisters;
    if (auto why = load_registers(kind, request.address, request.quantity, scratch)) {
        return refused(request.function, *why);
    }
    return protocol::Response{protocol::ReadRegistersResponse{
        request.function, protocol::RegisterView(scratch.first(2u * request.quantity))}};
}

MaybeResponse UnitModel::write_coil(const protocol::WriteSingleCoilRequest& request) {
    const std::uint16_t value = request.on() ? 1 : 0;
    return echo_unless(store(BankKind::Coils, request.address, std::span(&value, 1)),
                       protocol::WriteSingleCoilResponse{request});
}

MaybeResponse UnitModel::write_register(const protocol::WriteSingleRegisterRequest& request) {
    return echo_unless(
        store(BankKind::HoldingRegisters, request.address, std::span(&request.value, 1)),
        protocol::WriteSingleRegisterResponse{request});
}

MaybeResponse UnitModel::write_coils(const protocol::WriteMultipleCoilsRequest& request) {
    std::array<std::uint16_t, protocol::limits::kMaxWriteCoils> bits{};
    for (std::size_t i = 0; i < request.quantity; ++i)
        bits[i] = request.values[i] ? 1 : 0;
    return echo_unless(
        store(BankKind::Coils, request.address, std::span(bits).first(request.quantity)),
        protocol::WriteMultipleCoilsResponse{request.address, request.quantity});
}

MaybeResponse UnitModel::write_registers(const protocol::WriteMultipleRegistersRequest& request) {
    std::array<std::uint16_t, protocol::limits::kMaxWriteRegisters> values{};
    for (std::size_t i = 0; i < request.quantity; ++i)
        values[i] = request.values[i];
    return echo_unless(store(BankKind::HoldingRegisters, request.address,
                             std::span(values).first(request.quantity)),
                       protocol::WriteMultipleRegistersResponse{request.address, request.quantity});
}

MaybeResponse UnitModel::mask_write(const protocol::MaskWriteRegisterRequest& request) {
    const Permit permit = may_write(BankKind::HoldingRegisters, request.address, 1);
    if (permit.refusal) return refused(FunctionCode::MaskWriteRegister, *permit.refusal);
    const DataBank& holding = bank(BankKind::HoldingRegisters);
    const std::uint16_t now = holding.at(holding.find(request.address, 1).index);
    const auto value = static_cast<std::uint16_t>((now & request.and_mask) |
                                                  (request.or_mask & ~request.and_mask));
    return echo_unless(write_permitted(BankKind::HoldingRegisters, request.address,
                                       std::span(&value, 1), permit.skip),
                       protocol::MaskWriteRegisterResponse{request});
}

MaybeResponse UnitModel::read_write(const protocol::ReadWriteMultipleRegistersRequest& request,
                                    std::span<std::uint8_t> scratch) {
    constexpr auto fc = FunctionCode::ReadWriteMultipleRegisters;
    constexpr auto kind = BankKind::HoldingRegisters;
    if (request.read_quantity > spec_.max_read_registers) {
        return refused(fc, ExceptionCode::IllegalDataValue);
    }
    // Both ranges are checked before the write (CVE-2022-0367 checked only the read range).
    const Permit write = may_write(kind, request.write_address, request.write_quantity);
    if (write.refusal) return refused(fc, *write.refusal);
    const Permit read = may_read(kind, request.read_address, request.read_quantity);
    if (read.refusal) return refused(fc, *read.refusal);
    if (auto why = points_.check_read(request.read_address, request.read_quantity)) {
        return refused(fc, *why);
    }
    std::array<std::uint16_t, protocol::limits::kMaxReadWriteWrite> values{};
    for (std::size_t i = 0; i < request.write_quantity; ++i)
        values[i] = request.values[i];
    if (auto why = write_permitted(kind, request.write_address,
                                   std::span(values).first(request.write_quantity), write.skip)) {
        return refused(fc, *why);
    }
    load_registers(kind, request.read_address, request.read_quantity, scratch);
    return protocol::Response{protocol::ReadWriteMultipleRegistersResponse{
        protocol::RegisterView(scratch.first(2u * request.read_quantity))}};
}

MaybeResponse UnitModel::read_fifo(const protocol::ReadFifoQueueRequest& request,
                                   std::span<std::uint8_t> scratch) {
    constexpr auto fc = FunctionCode::ReadFifoQueue;
    constexpr auto kind = BankKind::HoldingRegisters;
    if (!std::binary_search(spec_.fifos.begin(), spec_.fifos.end(), request.address)) {
        return refused(fc, ExceptionCode::IllegalDataAddress);
    }
    const DataBank& holding = bank(kind);
    const std::uint16_t count = holding.at(holding.find(request.address, 1).index);
    if (count > protocol::limits::kMaxFifoCount)
        return refused(fc, ExceptionCode::IllegalDataValue);
    if (count > 0) {
        if (auto why = load_registers(kind, request.address + 1u, count, scratch)) {
            return refused(fc, *why);
        }
    }
    return protocol::Response{
        protocol::ReadFifoQueueResponse{protocol::RegisterView(scratch.first(2u * count))}};
}

MaybeResponse UnitModel::report_server_id(std::span<std::uint8_t> scratch) const {
    const auto& id = spec_.server_id;
    std::size_t used = 0;
    for (char c : id.id)
        scratch[used++] = static_cast<std::uint8_t>(c);
    scratch[used++] = id.running ? 0xFF : 0x00;
    for (char c : id.extra)
        scratch[used++] = static_cast<std::uint8_t>(c);
    return protocol::Response{protocol::ReportServerIdResponse{scratch.first(used)}};
}

MaybeResponse UnitModel::serve(const protocol::Request& request, std::span<std::uint8_t> scratch) {
    using namespace protocol;
    return std::visit(
        [&](const auto& r) -> MaybeResponse {
            using T = std::decay_t<decltype(r)>;
            if constexpr (std::is_same_v<T, ReadBitsRequest>) {
                return read_bits(r, scratch);
            } else if constexpr (std::is_same_v<T, ReadRegistersRequest>) {
                return read_registers(r, scratch);
            } else if constexpr (std::is_same_v<T, WriteSingleCoilRequest>) {
                return write_coil(r);
            } else if constexpr (std::is_same_v<T, WriteSingleRegisterRequest>) {
                return write_register(r);
            } else if constexpr (std::is_same_v<T, ReadExceptionStatusRequest>) {
                return Response{ReadExceptionStatusResponse{spec_.exception_status}};
            } else if constexpr (std::is_same_v<T, DiagnosticsRequest>) {
                return serve_diagnostics(r, spec_.diagnostics, comm_, scratch);
            } else if constexpr (std::is_same_v<T, GetCommEventCounterRequest>) {
                return serve_event_counter(comm_);
            } else if constexpr (std::is_same_v<T, GetCommEventLogRequest>) {
                return serve_event_log(comm_, scratch);
            } else if constexpr (std::is_same_v<T, WriteMultipleCoilsRequest>) {
                return write_coils(r);
            } else if constexpr (std::is_same_v<T, WriteMultipleRegistersRequest>) {
                return write_registers(r);
            } else if constexpr (std::is_same_v<T, ReportServerIdRequest>) {
                return report_server_id(scratch);
            } else if constexpr (std::is_same_v<T, ReadFileRecordRequest>) {
                return files_.read(r, scratch);
            } else if constexpr (std::is_same_v<T, WriteFileRecordRequest>) {
                return files_.write(r);
            } else if constexpr (std::is_same_v<T, MaskWriteRegisterRequest>) {
                return mask_write(r);
            } else if constexpr (std::is_same_v<T, ReadWriteMultipleRegistersRequest>) {
                return read_write(r, scratch);
            } else if constexpr (std::is_same_v<T, ReadFifoQueueRequest>) {
                return read_fifo(r, scratch);
            } else if constexpr (std::is_same_v<T, ReadDeviceIdRequest>) {
                return serve_device_identification(r, spec_.identification, scratch);
            } else if constexpr (std::is_same_v<T, ObjectMessagingRequest>) {
                return serve_object_messaging(r, spec_.objects);
            } else {
                // MEI types other than 0E (CANopen 0D) and codes without a typed request.
                return exception_response(function_of(request), ExceptionCode::IllegalFunction);
            }
        },
        request);
}

}  // namespace mblab::device
