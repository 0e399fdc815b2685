#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "device/reference_device.hpp"
#include "device/request_handler.hpp"
#include "protocol/result.hpp"
#include "server/journaled_device.hpp"
#include "server/state_keeper.hpp"
#include "server/state_saver.hpp"

// The devices one `mblab serve` runs, each with what keeps its writes: at start its state file is
// read and its journal replayed; then a keeper saves it, and with `durable` a journal holds every
// write before its answer. Nothing here opens a socket or a line.
namespace mblab::server {

struct KeptDevicesOptions {
    std::filesystem::path profile;
    std::size_t count = 1;
    std::filesystem::path state;  // empty: the devices keep nothing
    bool durable = false;         // needs `state`
};

// The state file of device `index` of `count`: FILE itself for one device; for several, one file
// each, numbered from 1 in port order: lab.json -> lab-1.json, lab-2.json, ...
std::filesystem::path device_state_path(const std::filesystem::path& file, std::size_t index,
                                        std::size_t count);

class KeptDevices {
  public:
    // Loads `count` devices from the profile and restores each one's state. One line in the
    // error when a profile, a state file or a journal cannot be used, or a state file cannot
    // be written (found now rather than at the first save, which may be minutes away).
    static protocol::Result<std::unique_ptr<KeptDevices>, std::string> open(
        const KeptDevicesOptions& options, StateKeeper::Report report);
    ~KeptDevices();
    KeptDevices(const KeptDevices&) = delete;
    KeptDevices& operator=(const KeptDevices&) = delete;

    std::size_t size() const { return devices_.size(); }
    device::ReferenceDevice& device(std::size_t i) { return *devices_[i]; }
    // What answers Modbus for device i: its journal's face with `durable`, else the device.
    device::RequestHandler& handler(std::size_t i);
    // Null when the devices keep nothing.
    StateKeeper* keeper(std::size_t i) { return keepers_.empty() ? nullptr : keepers_[i].get(); }
    bool keeps_state() const { return !keepers_.empty(); }

    void save_soon();
    // Waits for the saves under way, then saves every device now; false when any save failed
    // (each failure is reported).
    bool save_all();
    // Ends the journals' threads. They post answers to the server's io_context: close before it
    // goes.
    void close();

  private:
    explicit KeptDevices(StateKeeper::Report report) : report_(std::move(report)) {}

    StateKeeper::Report report_;
    std::vector<std::unique_ptr<device::ReferenceDevice>> devices_;
    // Before the keepers, whose saves it runs.
    StateSaver saver_;
    std::vector<std::unique_ptr<StateKeeper>> keepers_;
    std::vector<std::unique_ptr<JournaledDevice>> journaled_;
};

}  // namespace mblab::server
