#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <initializer_list>
#include <memory>

#include "blocking_client.hpp"
#include "device/profile_paths.hpp"
#include "device/reference_device.hpp"
#include "device/request_handler.hpp"
#include "server/background_server.hpp"
#include "server/server_options.hpp"

namespace mblab::test {

// One request and the answer it must get, both as hex.
struct Exchange {
    const char* request;
    const char* answer;
};

inline void expect_exchanges(BlockingClient& client, std::initializer_list<Exchange> exchanges) {
    for (const auto& exchange : exchanges) {
        EXPECT_EQ(client.transact(exchange.request), exchange.answer)
            << "request " << exchange.request;
    }
}

// Runs a server on 127.0.0.1 and an ephemeral port, in-process on its own thread.
class ServerFixture : public ::testing::Test {
  protected:
    void start_server(device::RequestHandler& handler, server::ServerOptions options = {}) {
        server_ = std::make_unique<server::BackgroundServer>(handler, std::move(options));
        auto port = server_->start();
        ASSERT_TRUE(port) << port.error();
        port_ = *port;
    }
    // The shipped reference profile behind the server.
    void start_reference_server(server::ServerOptions options = {}) {
        auto loaded = device::load_profile(device::default_profile_path());
        ASSERT_TRUE(loaded) << loaded.error();
        device_ = std::move(loaded.value());
        start_server(*device_, std::move(options));
    }
    BlockingClient connect(int receive_buffer = 0) const {
        return BlockingClient(port_, receive_buffer);
    }
    const server::ServerStats& stats() const { return server_->stats(); }

    std::unique_ptr<device::ReferenceDevice> device_;  // outlives the server
    std::unique_ptr<server::BackgroundServer> server_;
    std::uint16_t port_ = 0;
};

}  // namespace mblab::test
