#include "protocol/round_trip.hpp"

#include <algorithm>
#include <array>

#include "protocol/limits.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"

namespace mblab::protocol {

namespace {

template <class... Visitors>
struct Overloaded : Visitors... {
    using Visitors::operator()...;
};
template <class... Visitors>
Overloaded(Visitors...) -> Overloaded<Visitors...>;

// The views a decoder hands out must walk to exactly their end: that is what "validated" means
// to the device and the client that walk them.
bool views_walk(const Request& request) {
    return std::visit(Overloaded{
                          [](const WriteMultipleCoilsRequest& r) {
                              return (r.values.size() + 7) / 8 == r.values.bytes().size();
                          },
                          [](const ReadFileRecordRequest& r) {
                              return r.count() * limits::kFileRecordSubRequestSize ==
                                     r.sub_requests.size();
                          },
                          [](const WriteFileRecordRequest& r) {
                              std::size_t offset = 0;
                              FileRecordData record;
                              while (r.next(offset, record)) {
                              }
                              return offset == r.sub_requests.size();
                          },
                          [](const auto&) { return true; },
                      },
                      request);
}

bool views_walk(const Response& response) {
    return std::visit(Overloaded{
                          [](const ReadFileRecordResponse& r) {
                              std::size_t offset = 0;
                              RegisterView data;
                              while (r.next(offset, data)) {
                              }
                              return offset == r.sub_responses.size();
                          },
                          [](const WriteFileRecordResponse& r) {
                              return views_walk(Request{WriteFileRecordRequest{r.sub_requests}});
                          },
                          [](const ReadDeviceIdResponse& r) {
                              std::size_t offset = 0;
                              std::size_t count = 0;
                              DeviceIdObject object;
                              while (r.next(offset, object))
                                  ++count;
                              return offset == r.objects.size() && count == r.object_count;
                          },
                          [](const auto&) { return true; },
                      },
                      response);
}

template <class Message>
RoundTrip round_trip(std::span<const std::uint8_t> pdu,
                     Result<Message> (*decode)(std::span<const std::uint8_t>),
                     bool (*encode)(const Message&, WriteCursor&)) {
    const auto decoded = decode(pdu);
    if (!decoded) return RoundTrip::Rejected;
    if (!views_walk(*decoded)) return RoundTrip::Differs;
    std::array<std::uint8_t, limits::kMaxPdu> buffer{};
    WriteCursor out(buffer);
    if (!encode(*decoded, out)) return RoundTrip::Differs;
    const auto written = out.written();
    if (!std::equal(written.begin(), written.end(), pdu.begin(), pdu.end())) {
        return RoundTrip::Differs;
    }
    return decode(written) ? RoundTrip::Same : RoundTrip::Differs;
}

}  // namespace

RoundTrip request_round_trip(std::span<const std::uint8_t> pdu) {
    return round_trip<Request>(pdu, decode_request, encode_request);
}

RoundTrip response_round_trip(std::span<const std::uint8_t> pdu) {
    return round_trip<Response>(pdu, decode_response, encode_response);
}

}  // namespace mblab::protocol
