#pragma once

#include <cstdint>
#include <vector>

#include "cli/read_query.hpp"
#include "client/client.hpp"

// The answers of the serial-line diagnostics reads ([APP] 6.7, 6.9, 6.10, 6.13), field by field
// with what each value means.
namespace mblab::cli {

Reading exception_status_reading(std::uint8_t status);
Reading event_counter_reading(const client::EventCounter& counter);
Reading event_log_reading(const client::EventLog& log);
Reading server_id_reading(const std::vector<std::uint8_t>& data);

}  // namespace mblab::cli
