#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "device/comm_state.hpp"
#include "device/data_bank.hpp"
#include "device/fault_rules.hpp"
#include "device/file_store.hpp"
#include "device/maybe_response.hpp"
#include "device/point_rules.hpp"
#include "device/profile.hpp"
#include "protocol/request.hpp"

// One unit id of a profile: its data map, identity and communication state. serve() runs a
// decoded request past the unit's limits (03) and map (02) and executes it; routing, listen-only
// mode, faults and counting are the device's (reference_device.hpp).
namespace mblab::device {

class UnitModel {
  public:
    explicit UnitModel(const UnitSpec& spec);

    const UnitSpec& spec() const { return spec_; }
    bool supports(std::uint8_t function) const { return spec_.functions[function]; }

    // `scratch` (at least 253 bytes) holds response data the outcome points into.
    MaybeResponse serve(const protocol::Request& request, std::span<std::uint8_t> scratch);

    CommState& comm() { return comm_; }
    const CommState& comm() const { return comm_; }
    FaultRules& faults() { return faults_; }
    const FaultRules& faults() const { return faults_; }
    DataBank& bank(BankKind kind) { return banks_[static_cast<std::size_t>(kind)]; }
    const DataBank& bank(BankKind kind) const { return banks_[static_cast<std::size_t>(kind)]; }
    FileStore& files() { return files_; }
    const FileStore& files() const { return files_; }

  private:
    // Why the span cannot be read or written (02 or the profile's code), or the access whose
    // addresses the operation passes over (read as zeros, writes ignored), if any.
    struct Permit {
        std::optional<protocol::ExceptionCode> refusal;
        std::optional<Access> skip;
    };
    Permit may_read(BankKind kind, std::uint32_t address, std::uint32_t count) const;
    Permit may_write(BankKind kind, std::uint32_t address, std::uint32_t count) const;
    // Either of them, for a span that is `mapped` and `crosses` addresses of the `closed` access:
    // refused with the profile's `policy` for such a span, if it has one.
    static Permit permit(bool mapped, bool crosses, std::optional<protocol::ExceptionCode> policy,
                         Access closed);

    MaybeResponse read_bits(const protocol::ReadBitsRequest& request,
                            std::span<std::uint8_t> scratch);
    MaybeResponse read_registers(const protocol::ReadRegistersRequest& request,
                                 std::span<std::uint8_t> scratch);
    MaybeResponse write_coil(const protocol::WriteSingleCoilRequest& request);
    MaybeResponse write_register(const protocol::WriteSingleRegisterRequest& request);
    MaybeResponse write_coils(const protocol::WriteMultipleCoilsRequest& request);
    MaybeResponse write_registers(const protocol::WriteMultipleRegistersRequest& request);
    MaybeResponse mask_write(const protocol::MaskWriteRegisterRequest& request);
    MaybeResponse read_write(const protocol::ReadWriteMultipleRegistersRequest& request,
                             std::span<std::uint8_t> scratch);
    MaybeResponse read_fifo(const protocol::ReadFifoQueueRequest& request,
                            std::span<std::uint8_t> scratch);
    MaybeResponse report_server_id(std::span<std::uint8_t> scratch) const;

    // Writes `values` after may_write() allowed it; returns the refusal otherwise.
    std::optional<protocol::ExceptionCode> store(BankKind kind, std::uint32_t address,
                                                 std::span<const std::uint16_t> values);
    // The write itself, once permitted: holding-register points checked and kept as their rules
    // say (point_rules.hpp).
    std::optional<protocol::ExceptionCode> write_permitted(BankKind kind, std::uint32_t address,
                                                           std::span<const std::uint16_t> values,
                                                           std::optional<Access> skip);
    // Reads registers as big-endian bytes into `out` after may_read() allowed it.
    std::optional<protocol::ExceptionCode> load_registers(BankKind kind, std::uint32_t address,
                                                          std::uint32_t count,
                                                          std::span<std::uint8_t> out) const;

    UnitSpec spec_;
    std::array<DataBank, kBankKinds> banks_;
    FileStore files_;
    CommState comm_;
    FaultRules faults_;
    PointRules points_;
};

}  // namespace mblab::device
