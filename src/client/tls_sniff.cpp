#include "client/tls_sniff.hpp"

#include <algorithm>
#include <map>
#include <mutex>

#include "client/hex_text.hpp"

namespace mblab::client {

namespace {

constexpr std::uint8_t kAlert = 0x15;
constexpr std::uint8_t kHandshake = 0x16;
constexpr std::uint8_t kMajor = 0x03;
constexpr std::uint8_t kHighestMinor = 0x04;  // TLS 1.3's record layer still says 03 03
constexpr std::size_t kShownBytes = 5;        // a record header: type, version, length
constexpr std::string_view kAdvice = ": use mbaps://";

void put16(std::vector<std::uint8_t>& out, std::size_t value) {
    out.push_back(static_cast<std::uint8_t>(value >> 8));
    out.push_back(static_cast<std::uint8_t>(value));
}

// `body` preceded by its length in `width` bytes.
void put_sized(std::vector<std::uint8_t>& out, const std::vector<std::uint8_t>& body,
               std::size_t width) {
    for (std::size_t i = width; i-- > 0;)
        out.push_back(static_cast<std::uint8_t>(body.size() >> (8 * i)));
    out.insert(out.end(), body.begin(), body.end());
}

std::string host_port(const Endpoint& endpoint) {
    const bool ipv6 = endpoint.host.find(':') != std::string::npos;
    const std::string host = ipv6 ? "[" + endpoint.host + "]" : endpoint.host;
    return host + ":" + std::to_string(endpoint.port);
}

}  // namespace

bool looks_like_tls(std::span<const std::uint8_t> bytes) {
    constexpr std::size_t kAlertLength = 2;      // level and description
    constexpr std::size_t kHandshakeHeader = 4;  // type and a 3-byte length
    constexpr std::size_t kLongestRecord = (1U << 14) + 2048;
    if (bytes.size() < kShownBytes || bytes[1] != kMajor || bytes[2] > kHighestMinor) return false;
    // The record's length tells it from an MBAP header: there those bytes are the protocol id's
    // low byte (0) and the length's high byte (0), a length no alert or handshake record has.
    const std::size_t length = std::size_t{bytes[3]} << 8 | bytes[4];
    if (bytes[0] == kAlert) return length == kAlertLength;
    return bytes[0] == kHandshake && length >= kHandshakeHeader && length <= kLongestRecord;
}

std::string tls_answer_text(const Endpoint& endpoint, std::span<const std::uint8_t> bytes) {
    const auto shown = bytes.first(std::min(bytes.size(), kShownBytes));
    return "the server at " + host_port(endpoint) + " answered with TLS bytes (" +
           hex_bytes(shown) + (bytes.size() > shown.size() ? " ...)" : ")") + std::string(kAdvice);
}

bool is_tls_answer_text(std::string_view detail) {
    return detail.starts_with("the server at ") && detail.ends_with(kAdvice);
}

std::vector<std::uint8_t> tls_client_hello() {
    std::vector<std::uint8_t> hello = {0x03, 0x03};  // client_version: TLS 1.2
    hello.insert(hello.end(), 32, 0x4D);             // random: any 32 bytes do for a probe
    hello.push_back(0x00);                           // no session id
    // TLS_AES_128_GCM_SHA256, TLS_AES_256_GCM_SHA384, ECDHE-ECDSA and ECDHE-RSA with AES-GCM.
    put_sized(hello, {0x13, 0x01, 0x13, 0x02, 0xC0, 0x2B, 0xC0, 0x2C, 0xC0, 0x2F, 0xC0, 0x30}, 2);
    hello.insert(hello.end(), {0x01, 0x00});  // compression: null only
    std::vector<std::uint8_t> extensions;
    put16(extensions, 0x000A);                                       // supported_groups
    put_sized(extensions, {0x00, 0x04, 0x00, 0x17, 0x00, 0x1D}, 2);  // secp256r1, x25519
    put16(extensions, 0x000B);                                       // ec_point_formats
    put_sized(extensions, {0x01, 0x00}, 2);                          // uncompressed
    put16(extensions, 0x000D);                                       // signature_algorithms
    // ecdsa_secp256r1_sha256, rsa_pss_rsae_sha256, rsa_pkcs1_sha256
    put_sized(extensions, {0x00, 0x06, 0x04, 0x03, 0x08, 0x04, 0x04, 0x01}, 2);
    put_sized(hello, extensions, 2);
    std::vector<std::uint8_t> handshake = {0x01};  // client_hello
    put_sized(handshake, hello, 3);
    std::vector<std::uint8_t> record = {kHandshake, kMajor, 0x01};  // record version: TLS 1.0
    put_sized(record, handshake, 2);
    return record;
}

std::optional<std::string> sniff_tls(const Endpoint& endpoint, std::chrono::milliseconds timeout) {
    static std::mutex mutex;
    static std::map<std::string, std::optional<std::string>> asked;
    const std::string key = host_port(endpoint);
    {
        std::lock_guard lock(mutex);
        if (auto found = asked.find(key); found != asked.end()) return found->second;
    }
    Endpoint plain{endpoint.host, endpoint.port, nullptr};
    std::optional<std::string> answer;
    if (auto link = RawLink::connect(plain, timeout)) {
        LinkError error;
        const auto hello = tls_client_hello();
        if (link->send(hello, error)) {
            const Received got = link->receive_frame(timeout);
            if (looks_like_tls(got.bytes)) answer = tls_answer_text(endpoint, got.bytes);
        }
    }
    std::lock_guard lock(mutex);
    asked.emplace(key, answer);
    return answer;
}

}  // namespace mblab::client
