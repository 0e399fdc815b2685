#include "server/state_keeper.hpp"

#include <future>

#include "server/journaled_device.hpp"
#include "server/state_file.hpp"

namespace mblab::server {

namespace {

// What a record costs in the file beyond its text: "*CRC" and the newline.
constexpr std::uint64_t kSealBytes = 10;

std::uint64_t size_or_zero(const std::filesystem::path& path) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    return ec ? 0 : size;
}

}  // namespace

std::filesystem::path journal_path_of(const std::filesystem::path& state) {
    auto path = state;
    path += ".journal";
    return path;
}

StateKeeper::StateKeeper(device::ReferenceDevice& device, std::filesystem::path state,
                         StateSaver& saver, std::unique_ptr<Journal> journal, Report report,
                         std::uint64_t journal_bound)
    : device_(device),
      state_(std::move(state)),
      saver_(saver),
      journal_(std::move(journal)),
      report_(std::move(report)),
      bound_(journal_bound) {}

StateKeeper::~StateKeeper() {
    saver_.wait_idle();
}

void StateKeeper::append_locked(std::string record, Journal::Durable done) {
    since_rotation_ += record.size() + kSealBytes;
    journal_->append(std::move(record), std::move(done));
    if (since_rotation_ > bound_) save_soon_locked();
}

void StateKeeper::save_soon() {
    std::lock_guard order(order_);
    save_soon_locked();
}

void StateKeeper::save_soon_locked() {
    // The rotation and the snapshot under one lock: the records moved aside are exactly the
    // writes the snapshot holds, so dropping them once it is saved loses none.
    const auto rotation = journal_ ? journal_->rotate() : 0;
    since_rotation_ = 0;
    saver_.save(state_, device_.state().snapshot(),
                [this, rotation](bool saved, const std::string& error) {
                    if (!saved) {
                        if (report_) report_("cannot save state: " + error);
                    } else if (journal_) {
                        journal_->drop_old(rotation);
                    }
                });
}

bool StateKeeper::save_now(std::string& error) {
    std::uint64_t rotation = 0;
    device::StateSnapshot snapshot;
    {
        std::lock_guard order(order_);
        rotation = journal_ ? journal_->rotate() : 0;
        since_rotation_ = 0;
        snapshot = device_.state().snapshot();
    }
    // The text outside the lock: writes go on meanwhile (into the rotated journal).
    if (!write_file_atomically(state_, snapshot.to_json(), error)) return false;
    if (journal_) journal_->drop_old(rotation);
    return true;
}

StateKeeper::Write StateKeeper::write_values(std::uint8_t unit, device::BankKind kind,
                                             std::uint32_t start,
                                             std::span<const std::uint16_t> values) {
    std::promise<bool> written;
    {
        std::lock_guard order(order_);
        if (!device_.data().set_values(unit, kind, start, values)) return Write::Unmapped;
        const bool kept =
            kind == device::BankKind::Coils || kind == device::BankKind::HoldingRegisters;
        if (!journal_ || !kept) return Write::Done;
        append_locked(values_record(unit, kind, start, values),
                      [&written](bool ok) { written.set_value(ok); });
    }
    return written.get_future().get() ? Write::Done : Write::NotDurable;
}

bool replay_journal(device::ReferenceDevice& device, const std::filesystem::path& state,
                    const StateKeeper::Report& warn, std::string& error) {
    const auto path = journal_path_of(state);
    if (size_or_zero(path) == 0 && size_or_zero(journal_old_path(path)) == 0) {
        // Nothing to replay: an empty journal is what a clean exit leaves.
        return true;
    }
    const OnRecord apply = [&](std::string_view record, const RecordPlace& place,
                               std::string& why) {
        if (replay_record(device, record)) return true;
        const auto what = "journal " + place.file.string() + " line " + std::to_string(place.line) +
                          ": not a journal record ('" + std::string(record.substr(0, 40)) + "')";
        if (place.last) {
            if (warn)
                warn(what + "; left out: as the file's last record it was never acknowledged");
            return true;
        }
        why = what + "; restore the line, or delete it (its write is then lost) and start again";
        return false;
    };
    if (!read_journal(path, apply, warn, error)) return false;
    if (!write_file_atomically(state, device.state().save(), error)) return false;
    remove_journal(path);
    return true;
}

}  // namespace mblab::server
