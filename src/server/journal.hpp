#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "protocol/result.hpp"
#include "server/journal_file.hpp"
#include "server/work_thread.hpp"

// The write journal of `mblab serve --durable`: every acknowledged write is appended to a file
// and made durable before its answer goes out. Records are lines of text, each sealed with its
// checksum (journal_file.hpp); a thread of its own writes and fdatasyncs them in groups (group
// commit: the records appended while one fdatasync runs share the next), so many writes pay for one
// sync. Each save of the state file compacts it: rotate() before the state is taken moves the
// records so far to PATH.old, drop_old() after the state file is safely written removes them. A
// failure anywhere (a full disk) leaves the records where replay finds them: an append that fails
// is cut off again and reported as not written, a rotation that fails moves nothing.
namespace mblab::server {

class Journal {
  public:
    // Told whether the record reached the disk. Called on the journal's thread.
    using Durable = std::function<void(bool written)>;

    // Starts an empty journal at `path` (replay an existing one first: it is truncated).
    static protocol::Result<std::unique_ptr<Journal>, std::string> create(
        const std::filesystem::path& path);
    // Makes everything appended durable, then stops the thread.
    ~Journal();
    Journal(const Journal&) = delete;
    Journal& operator=(const Journal&) = delete;

    // `record` must not hold a newline. `done` may be empty.
    void append(std::string record, Durable done);
    // Records appended from now on start a new file; the earlier ones are kept in PATH.old.
    // Returns the rotation's number, for drop_old().
    std::uint64_t rotate();
    // The state file now holds every record up to `rotation`: PATH.old is removed, unless a
    // later rotation added records to it that a later save must cover first.
    void drop_old(std::uint64_t rotation);

    // fdatasync calls so far (for tests and benchmarks: fewer than the records under load).
    std::uint64_t syncs() const;

  private:
    struct Item {
        enum class Kind : std::uint8_t { Record, Rotate, DropOld } kind = Kind::Record;
        std::string record;
        Durable done;
        std::uint64_t rotation = 0;
    };

    Journal(std::filesystem::path path, int fd);
    void push(Item item);
    // On the worker's thread; `lock` is held on entry and on return.
    void write_queued(WorkThread::Lock& lock);
    void flush();
    bool do_rotate();

    std::filesystem::path path_;
    std::filesystem::path old_path_;
    int fd_;
    off_t good_size_ = 0;  // the end of the last record made durable
    bool torn_ = false;    // a failed append could not be cut off yet
    bool old_exists_ = false;
    bool appending_to_old_ = false;    // a rotation failed half-way: fd_ writes to PATH.old
    std::uint64_t rotations_ = 0;      // asked for, on the caller's side
    std::uint64_t last_rotation_ = 0;  // done, on the journal's thread
    std::vector<Item> batch_;          // the journal's thread's, as the two below
    std::string buffer_;
    std::vector<Durable> waiting_;
    std::vector<Item> queue_;  // under worker_.mutex(), as syncs_
    std::uint64_t syncs_ = 0;
    WorkThread worker_;  // last: it stops before what it works on goes
};

// Removes PATH and PATH.old, once the state file holds their records.
void remove_journal(const std::filesystem::path& path);

}  // namespace mblab::server
