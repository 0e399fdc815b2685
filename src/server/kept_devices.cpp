#include "server/kept_devices.hpp"

#include "server/state_file.hpp"

namespace mblab::server {

std::filesystem::path device_state_path(const std::filesystem::path& file, std::size_t index,
                                        std::size_t count) {
    if (count == 1) return file;
    return file.parent_path() /
           (file.stem().string() + "-" + std::to_string(index + 1) + file.extension().string());
}

protocol::Result<std::unique_ptr<KeptDevices>, std::string> KeptDevices::open(
    const KeptDevicesOptions& options, StateKeeper::Report report) {
    std::unique_ptr<KeptDevices> kept(new KeptDevices(std::move(report)));
    for (std::size_t i = 0; i < options.count; ++i) {
        auto loaded = device::load_profile(options.profile);
        if (!loaded) return loaded.error();
        kept->devices_.push_back(std::move(loaded.value()));
    }
    if (options.state.empty()) return kept;
    std::string error;
    for (std::size_t i = 0; i < options.count; ++i) {
        const auto path = device_state_path(options.state, i, options.count);
        auto text = read_state_file(path, error);
        if (!error.empty()) return error;
        if (text && !kept->devices_[i]->state().load(*text, error)) {
            return "state file " + path.string() + ": " + error;
        }
        if (!check_state_writable(path, error)) return "--state: " + error;
        if (!replay_journal(*kept->devices_[i], path, kept->report_, error)) {
            return error;
        }
    }
    for (std::size_t i = 0; i < options.count; ++i) {
        const auto path = device_state_path(options.state, i, options.count);
        std::unique_ptr<Journal> journal;
        if (options.durable) {
            auto made = Journal::create(journal_path_of(path));
            if (!made) return made.error();
            journal = std::move(made.value());
        }
        kept->keepers_.push_back(std::make_unique<StateKeeper>(
            *kept->devices_[i], path, kept->saver_, std::move(journal), kept->report_));
        kept->journaled_.push_back(
            options.durable ? std::make_unique<JournaledDevice>(*kept->keepers_[i]) : nullptr);
    }
    return kept;
}

KeptDevices::~KeptDevices() {
    close();
}

device::RequestHandler& KeptDevices::handler(std::size_t i) {
    if (i < journaled_.size() && journaled_[i]) return *journaled_[i];
    return *devices_[i];
}

void KeptDevices::save_soon() {
    for (auto& keeper : keepers_)
        keeper->save_soon();
}

bool KeptDevices::save_all() {
    saver_.wait_idle();
    bool saved = true;
    for (const auto& keeper : keepers_) {
        std::string error;
        if (!keeper->save_now(error)) {
            report_("cannot save state: " + error);
            saved = false;
        }
    }
    return saved;
}

void KeptDevices::close() {
    journaled_.clear();
    keepers_.clear();
}

}  // namespace mblab::server
