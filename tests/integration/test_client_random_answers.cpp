#include <gtest/gtest.h>

#include <random>

#include "client/client.hpp"
#include "client/target.hpp"
#include "device/profile_paths.hpp"
#include "device/reference_device.hpp"
#include "support/malicious_server.hpp"
#include "test_client_support.hpp"

// Thousands of damaged answers through the typed client in-process: the reference device's
// right answer with bytes flipped, cut short, lengthened, or its byte count changed. The client
// must never crash (run it under the sanitizers) and never report success for an answer that
// does not hold what was asked.
namespace mblab::test {
namespace {

using namespace std::chrono_literals;

class DamagedAnswers {
  public:
    explicit DamagedAnswers(device::ReferenceDevice& device) : device_(device) {}

    Answer operator()(std::span<const std::uint8_t> request, int) {
        std::array<std::uint8_t, 260> answer{};
        const auto reply =
            device_.handle({request[6], device::Link::Tcp}, request.subspan(7), answer);
        std::vector<std::uint8_t> pdu(answer.begin(),
                                      answer.begin() + static_cast<long>(reply.size));
        damage(pdu);
        return Answer{mbap_answer(request, pdu)};
    }

  private:
    void damage(std::vector<std::uint8_t>& pdu) {
        std::uniform_int_distribution<int> kind(0, 4);
        std::uniform_int_distribution<int> byte(0, 255);
        auto at = [&](std::size_t size) {
            return std::uniform_int_distribution<std::size_t>(0, size - 1)(random_);
        };
        switch (kind(random_)) {
            case 0:  // flip a byte (the function code too)
                pdu[at(pdu.size())] = static_cast<std::uint8_t>(byte(random_));
                break;
            case 1:  // cut short
                pdu.resize(at(pdu.size()) + 1);
                break;
            case 2:  // bytes after the end
                pdu.insert(pdu.end(), static_cast<std::size_t>(byte(random_) % 8 + 1), 0x55);
                break;
            case 3:  // a count field (the second byte of most answers)
                if (pdu.size() > 1) pdu[1] = static_cast<std::uint8_t>(byte(random_));
                break;
            default:  // left right: the client must still accept it
                break;
        }
        if (pdu.size() > 253) pdu.resize(253);
    }

    device::ReferenceDevice& device_;
    std::mt19937 random_{20230326};
};

TEST(ClientRandomAnswers, NeverCrashesAndNeverAcceptsAWrongCount) {
    auto loaded = device::load_profile(device::default_profile_path());
    ASSERT_TRUE(loaded) << loaded.error();
    DamagedAnswers damaged(**loaded);
    MaliciousServer server(std::ref(damaged));
    const auto port = server.start();
    ASSERT_NE(port, 0);
    auto target = client::parse_target(tcp_target(port));
    ASSERT_TRUE(target);
    client::Transactor transactor(target->name, [&] { return client::open_link(*target, 1s); },
                                  {1, std::chrono::milliseconds(500), 0});
    client::Client client(transactor);

    int accepted = 0;
    int refused = 0;
    auto tally = [&](const auto& outcome, auto&& valid) {
        if (outcome) {
            ++accepted;
            EXPECT_TRUE(valid(*outcome));
        } else {
            ++refused;
            EXPECT_FALSE(outcome.error().message.empty());
            EXPECT_NE(outcome.error().kind, client::ErrorKind::Timeout);
        }
    };
    const std::vector<std::uint16_t> values = {1, 2, 3};
    for (int round = 0; round < 300; ++round) {
        const auto count = static_cast<std::uint16_t>(round % 20 + 1);
        tally(client.read_holding_registers(0, count), [&](auto& v) { return v.size() == count; });
        tally(client.read_coils(0, count), [&](auto& v) { return v.size() == count; });
        tally(client.write_multiple_registers(100, values), [](auto&) { return true; });
        tally(client.read_write_multiple_registers(0, count, 200, values),
              [&](auto& v) { return v.size() == count; });
        tally(client.read_device_identification(3), [](auto& id) { return !id.objects.empty(); });
        const protocol::FileRecordRef ref{1, 0, count};
        tally(client.read_file_records(std::span(&ref, 1)),
              [&](auto& r) { return r.size() == 1 && r[0].size() == count; });
        tally(client.read_fifo_queue(0x4000), [](auto& v) { return v.size() <= 31; });
        tally(client.get_comm_event_log(), [](auto& log) { return log.events.size() <= 64; });
        tally(client.diagnostics(0, std::vector<std::uint8_t>{1, 2}), [](auto& d) {
            return d.data == std::vector<std::uint8_t>{1, 2};
        });
    }
    // Both outcomes occur, so the damage reached the client and right answers still pass.
    EXPECT_GT(accepted, 100);
    EXPECT_GT(refused, 1000);
}

}  // namespace
}  // namespace mblab::test
