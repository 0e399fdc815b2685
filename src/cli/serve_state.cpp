#include "cli/serve_state.hpp"

#include <fmt/format.h>

#include <cstdio>

namespace mblab::cli {

void report(const std::string& message) {
    fmt::print(stderr, "mblab serve: {}\n", message);
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
