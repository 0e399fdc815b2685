#pragma once

#include <asio/any_io_executor.hpp>
#include <asio/ip/tcp.hpp>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "protocol/result.hpp"
#include "transport/allow_list.hpp"
#include "transport/connection_table.hpp"

// Accepts TCP connections under limits: the allow-list is checked first, then the connection
// count, where a full table gives up its oldest stalled, or else idle, connection to admit the
// newcomer.
namespace mblab::transport {

struct ListenerLimits {
    std::size_t max_connections = 0;  // 0: no limit
    AllowList allow;                  // empty: everyone
};

struct ListenerCounters {
    std::atomic<std::uint64_t> accepted{0};
    std::atomic<std::uint64_t> refused_address{0};  // not on the allow-list
    std::atomic<std::uint64_t> refused_full{0};     // at the limit and nobody idle
    std::atomic<std::uint64_t> evicted_idle{0};     // closed to admit a newer connection
    std::atomic<std::uint64_t> evicted_stalled{0};  // likewise, a client that trickles or stalls
    std::atomic<std::uint64_t> evicted_handshaking{0};  // likewise, one still in its TLS handshake

    std::uint64_t evicted() const {
        return evicted_idle.load() + evicted_stalled.load() + evicted_handshaking.load();
    }
};

class TcpListener : public std::enable_shared_from_this<TcpListener> {
  public:
    // Receives each admitted socket; it must add the connection to connections().
    using AdmitHandler = std::function<void(asio::ip::tcp::socket)>;

    static std::shared_ptr<TcpListener> create(asio::any_io_executor executor,
                                               ListenerLimits limits);

    // Binds and listens; returns the bound port (an ephemeral one for port 0).
    protocol::Result<std::uint16_t, std::string> listen(const asio::ip::tcp::endpoint& endpoint);
    // Runs the accept loop on the executor until stop().
    void start(AdmitHandler on_admitted);
    // Stops accepting and closes every admitted connection. Call on the executor's thread.
    void stop();

    ConnectionTable& connections() { return connections_; }
    const ListenerCounters& counters() const { return counters_; }
    asio::ip::tcp::endpoint local_endpoint() const;

  private:
    TcpListener(asio::any_io_executor executor, ListenerLimits limits);
    bool admit(asio::ip::tcp::socket& socket);

    asio::ip::tcp::acceptor acceptor_;
    ListenerLimits limits_;
    ConnectionTable connections_;
    ListenerCounters counters_;
};

}  // namespace mblab::transport
