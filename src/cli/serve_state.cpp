#include "cli/serve_state.hpp"

#include <fmt/format.h>

#include <cstdio>

namespace mblab::cli {

void report(const std::string& message) {
    fmt::print(stderr, "mblab serve: {}\n", message);
}

// The state file of device `index` of `count`: FILE itself for one device; for several, one file
// each, numbered from 1 in port order: lab.json -> lab-1.json, lab-2.json, ...
std::filesystem::path device_state_path(const std::filesystem::path& file, std::size_t index,
                                        std::size_t count) {
    if (count == 1) return file;
    return file.parent_path() /
           (file.stem().string() + "-" + std::to_string(index + 1) + file.extension().string());
}

// Saves every device's state; false when any save failed (each failure is reported).
bool save_states(const Keepers& keepers) {
    bool saved = true;
    for (const auto& keeper : keepers) {
        std::string error;
        if (!keeper->save_now(error)) {
            report("cannot save state: " + error);
            saved = false;
        }
    }
    return saved;
}

// REST writes made as the keeper keeps them: with --durable, journaled before their answer.
void write_values_through(LiveDevice& live, server::StateKeeper* keeper) {
    if (!keeper || !keeper->journal()) return;
    live.write_values_with([keeper](std::uint8_t unit, device::BankKind kind, std::uint32_t start,
                                    std::span<const std::uint16_t> values) {
        switch (keeper->write_values(unit, kind, start, values)) {
            case server::StateKeeper::Write::Done:
                return web::ValueWrite::Written;
            case server::StateKeeper::Write::Unmapped:
                return web::ValueWrite::Unmapped;
            case server::StateKeeper::Write::NotDurable:
                break;
        }
        return web::ValueWrite::NotDurable;
    });
}

// What POST /api/state/save does: the same file the periodic saves write.
std::function<bool(std::string&)> state_saver_for_http(server::StateKeeper* keeper) {
    if (!keeper) return {};
    return [keeper](std::string& file_or_error) {
        if (!keeper->save_now(file_or_error)) return false;
        file_or_error = keeper->state().string();
        return true;
    };
}

}  // namespace mblab::cli
