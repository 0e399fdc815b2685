#pragma once

#include <functional>
#include <string>

#include "cli/serve_http.hpp"
#include "server/state_keeper.hpp"

// What `mblab serve` keeps of its devices: the state files, the saves, and REST writes made the
// way the keeper keeps Modbus writes.
namespace mblab::cli {

// "mblab serve: MESSAGE" on standard error.
void report(const std::string& message);

// REST writes made as the keeper keeps them: with --durable, journaled before their answer.
void write_values_through(LiveDevice& live, server::StateKeeper* keeper);
// What POST /api/state/save does: the same file the periodic saves write.
std::function<bool(std::string&)> state_saver_for_http(server::StateKeeper* keeper);

}  // namespace mblab::cli
