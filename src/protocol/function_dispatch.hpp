#pragma once

#include <cstdint>

#include "protocol/field_reader.hpp"
#include "protocol/function_code.hpp"

// The one place that maps a function code to its decoder (not part of the public API).
namespace mblab::protocol::detail {

// `Decoders` is the request or the response side: a struct naming its variant (`Message`), the
// type that carries unknown codes (`Raw`), and one static decoder for each public function code.
// The switch stays a switch: its cases name functions, not data, and -Wswitch makes it name every
// FunctionCode. test_function_table.cpp checks that it decodes exactly the codes with a row.
template <class Decoders>
Result<typename Decoders::Message> decode_by_function(std::uint8_t code, FieldReader& in) {
    const auto function = static_cast<FunctionCode>(code);
    switch (function) {
        case FunctionCode::ReadCoils:
        case FunctionCode::ReadDiscreteInputs:
            return Decoders::read_bits(function, in);
        case FunctionCode::ReadHoldingRegisters:
        case FunctionCode::ReadInputRegisters:
            return Decoders::read_registers(function, in);
        case FunctionCode::WriteSingleCoil:
            return Decoders::write_single_coil(in);
        case FunctionCode::WriteSingleRegister:
            return Decoders::write_single_register(in);
        case FunctionCode::ReadExceptionStatus:
            return Decoders::read_exception_status(in);
        case FunctionCode::Diagnostics:
            return Decoders::diagnostics(in);
        case FunctionCode::GetCommEventCounter:
            return Decoders::comm_event_counter(in);
        case FunctionCode::GetCommEventLog:
            return Decoders::comm_event_log(in);
        case FunctionCode::WriteMultipleCoils:
            return Decoders::write_multiple_coils(in);
        case FunctionCode::WriteMultipleRegisters:
            return Decoders::write_multiple_registers(in);
        case FunctionCode::ReportServerId:
            return Decoders::report_server_id(in);
        case FunctionCode::ReadFileRecord:
            return Decoders::read_file_record(in);
        case FunctionCode::WriteFileRecord:
            return Decoders::write_file_record(in);
        case FunctionCode::MaskWriteRegister:
            return Decoders::mask_write_register(in);
        case FunctionCode::ReadWriteMultipleRegisters:
            return Decoders::read_write_multiple_registers(in);
        case FunctionCode::ReadFifoQueue:
            return Decoders::read_fifo_queue(in);
        case FunctionCode::EncapsulatedInterface:
            return Decoders::encapsulated(in);
        case FunctionCode::ObjectMessaging:
            return Decoders::object_messaging(in);
    }
    return decode_raw<typename Decoders::Message, typename Decoders::Raw>(code, in);
}

}  // namespace mblab::protocol::detail
