#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <string>

#include "device/reference_device.hpp"
#include "server/journal.hpp"
#include "server/state_saver.hpp"

// What `mblab serve --state FILE` does to keep one device's writable data: the saves (periodic,
// on the saver's thread; at exit, at once), and with --durable the journal that holds every
// acknowledged write between saves. One lock orders the device's changes, the journal's records
// and the snapshots the saves take, so that the journal replays the writes as the device made
// them, and a rotation moves aside exactly the records a snapshot holds.
namespace mblab::server {

// The journal's size past which a save compacts it, with or without --save-interval: the
// journal on disk stays within about twice this, and a restart replays at most that much.
inline constexpr std::uint64_t kJournalBound = 64ULL << 20;

std::filesystem::path journal_path_of(const std::filesystem::path& state);

class StateKeeper {
  public:
    using Report = std::function<void(const std::string& message)>;
    enum class Write : std::uint8_t { Done, Unmapped, NotDurable };

    // `journal` is null without --durable. `report` is told of saves that failed.
    StateKeeper(device::ReferenceDevice& device, std::filesystem::path state, StateSaver& saver,
                std::unique_ptr<Journal> journal, Report report,
                std::uint64_t journal_bound = kJournalBound);
    // Waits for the saves handed over, whose completions come back here.
    ~StateKeeper();
    StateKeeper(const StateKeeper&) = delete;
    StateKeeper& operator=(const StateKeeper&) = delete;

    device::ReferenceDevice& device() { return device_; }
    Journal* journal() { return journal_.get(); }

    // Held while the device changes and the change's record is appended.
    std::unique_lock<std::mutex> lock_order() { return std::unique_lock(order_); }
    // With lock_order() held: appends a record (see Journal::append). Past the bound, a save
    // starts, so that the journal is compacted even with --save-interval 0.
    void append_locked(std::string record, Journal::Durable done);

    // A save on the saver's thread: the snapshot now, the file later.
    void save_soon();
    // A save now (at exit, or asked for over HTTP); false with `error` when it failed.
    bool save_now(std::string& error);
    const std::filesystem::path& state() const { return state_; }

    // A write of values from the REST API: made, journaled and durable before it returns. The
    // state file keeps coils and holding registers, and so does the journal; a write to the
    // read-only banks is made and kept by neither.
    Write write_values(std::uint8_t unit, device::BankKind kind, std::uint32_t start,
                       std::span<const std::uint16_t> values);

  private:
    void save_soon_locked();

    device::ReferenceDevice& device_;
    std::filesystem::path state_;
    StateSaver& saver_;
    std::unique_ptr<Journal> journal_;
    Report report_;
    std::uint64_t bound_;
    std::mutex order_;
    std::uint64_t since_rotation_ = 0;  // bytes appended, under order_
};

// Makes the writes a journal holds (FILE.journal.old's, then FILE.journal's) again on `device`,
// a record at a time, saves the state and removes the journal, so that it can start empty. Any
// journal is replayed, with --durable or not, so a restart without it loses nothing either.
// `warn` is told of a torn last record left out. False with one line in `error` when a record
// is damaged (the line names the file and the line) or the state cannot be saved.
bool replay_journal(device::ReferenceDevice& device, const std::filesystem::path& state,
                    const StateKeeper::Report& warn, std::string& error);

}  // namespace mblab::server
