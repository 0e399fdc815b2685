#include "transport/allow_list.hpp"

#include <algorithm>

namespace mblab::transport {

namespace {

bool contains(const asio::ip::network_v4& network, const asio::ip::address_v4& address) {
    auto mask = network.netmask().to_uint();
    return (address.to_uint() & mask) == (network.address().to_uint() & mask);
}

bool contains(const asio::ip::network_v6& network, const asio::ip::address_v6& address) {
    auto want = network.address().to_bytes();
    auto have = address.to_bytes();
    unsigned bits = network.prefix_length();
    for (std::size_t i = 0; i < want.size() && bits > 0; ++i) {
        unsigned take = std::min(bits, 8U);
        auto mask = static_cast<unsigned char>(0xFFU << (8 - take));
        if ((want[i] & mask) != (have[i] & mask)) return false;
        bits -= take;
    }
    return true;
}

}  // namespace

bool AllowList::add(std::string_view entry, std::string& error) {
    std::string text(entry);
    asio::error_code ec;
    bool has_prefix = text.find('/') != std::string::npos;
    if (text.find(':') == std::string::npos) {
        auto network = has_prefix ? asio::ip::make_network_v4(text, ec)
                                  : asio::ip::network_v4(asio::ip::make_address_v4(text, ec), 32);
        if (!ec) {
            v4_.push_back(network);
            return true;
        }
    } else {
        auto network = has_prefix ? asio::ip::make_network_v6(text, ec)
                                  : asio::ip::network_v6(asio::ip::make_address_v6(text, ec), 128);
        if (!ec) {
            v6_.push_back(network);
            return true;
        }
    }
    error = "bad --allow entry '" + text +
            "' (expected an IP address or a network such as 192.168.1.0/24)";
    return false;
}

bool AllowList::allows(const asio::ip::address& peer) const {
    if (empty()) return true;
    if (peer.is_v6() && peer.to_v6().is_v4_mapped()) {
        return allows(asio::ip::make_address_v4(asio::ip::v4_mapped, peer.to_v6()));
    }
    if (peer.is_v4()) {
        auto v4 = peer.to_v4();
        return std::any_of(v4_.begin(), v4_.end(), [&](const auto& n) { return contains(n, v4); });
    }
    auto v6 = peer.to_v6();
    return std::any_of(v6_.begin(), v6_.end(), [&](const auto& n) { return contains(n, v6); });
}

}  // namespace mblab::transport
