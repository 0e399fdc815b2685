#pragma once

#include <asio/ip/address.hpp>
#include <asio/ip/network_v4.hpp>
#include <asio/ip/network_v6.hpp>
#include <string>
#include <string_view>
#include <vector>

// Client addresses a server admits: networks in CIDR form ("192.168.1.0/24") or single
// addresses. An empty list admits everyone.
namespace mblab::transport {

class AllowList {
  public:
    // Adds "ADDRESS" or "ADDRESS/PREFIX"; on a malformed entry returns false and sets `error`.
    bool add(std::string_view entry, std::string& error);

    bool empty() const { return v4_.empty() && v6_.empty(); }
    // IPv4-mapped IPv6 peers (a dual-stack listener) are matched as the IPv4 address they carry.
    bool allows(const asio::ip::address& peer) const;

  private:
    std::vector<asio::ip::network_v4> v4_;
    std::vector<asio::ip::network_v6> v6_;
};

}  // namespace mblab::transport
