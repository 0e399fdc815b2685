#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cli/serve_http.hpp"
#include "server/state_keeper.hpp"

// What `mblab serve` keeps of its devices: the state files, the saves, and REST writes made the
// way the keeper keeps Modbus writes.
namespace mblab::cli {

using Keepers = std::vector<std::unique_ptr<server::StateKeeper>>;

// "mblab serve: MESSAGE" on standard error.
void report(const std::string& message);

// The state file of device `index` of `count`: FILE itself for one device; for several, one file
// each, numbered from 1 in port order: lab.json -> lab-1.json, lab-2.json, ...
std::filesystem::path device_state_path(const std::filesystem::path& file, std::size_t index,
                                        std::size_t count);
// Saves every device's state; false when any save failed (each failure is reported).
bool save_states(const Keepers& keepers);
// REST writes made as the keeper keeps them: with --durable, journaled before their answer.
void write_values_through(LiveDevice& live, server::StateKeeper* keeper);
// What POST /api/state/save does: the same file the periodic saves write.
std::function<bool(std::string&)> state_saver_for_http(server::StateKeeper* keeper);

}  // namespace mblab::cli
