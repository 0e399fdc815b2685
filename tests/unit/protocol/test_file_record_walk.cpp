// The file record and device identification walkers stay inside their views even when handed
// bytes the decoder never validated.
#include <gtest/gtest.h>

#include "pdu_test_support.hpp"

namespace mblab::protocol {
namespace {

using test::hex;

TEST(FileRecordWalk, ReadRequestAtPastTheEndIsEmpty) {
    const auto subs = hex("06 00 04 00 01 00 02");
    const ReadFileRecordRequest request{subs};
    ASSERT_EQ(request.count(), 1u);
    EXPECT_EQ(request.at(0).file, 4);
    const FileRecordRef past = request.at(1);
    EXPECT_EQ(past.file, 0);
    EXPECT_EQ(past.record, 0);
    EXPECT_EQ(past.length, 0);
}

TEST(FileRecordWalk, WriteRequestStopsAtATruncatedSubRequest) {
    // One whole sub-request, then one whose data is cut short, then a partial header.
    const auto whole = hex("06 00 01 00 00 00 01 12 34");
    const auto cut = hex("06 00 01 00 00 00 01 12 34 06 00 02 00 00 00 02 56 78");
    const auto partial = hex("06 00 01 00 00 00 01 12 34 06 00");
    for (const auto* subs : {&whole, &cut, &partial}) {
        const WriteFileRecordRequest request{*subs};
        std::size_t offset = 0;
        FileRecordData record;
        ASSERT_TRUE(request.next(offset, record));
        EXPECT_EQ(record.data[0], 0x1234);
        EXPECT_EQ(offset, 9u);
        EXPECT_FALSE(request.next(offset, record));
        EXPECT_EQ(offset, 9u);
    }
}

TEST(FileRecordWalk, ReadResponseStopsAtAnOverrunningLength) {
    const auto subs = hex("03 06 12 34 09 06 56 78");
    const ReadFileRecordResponse response{subs};
    std::size_t offset = 0;
    RegisterView data;
    ASSERT_TRUE(response.next(offset, data));
    EXPECT_EQ(data[0], 0x1234);
    EXPECT_FALSE(response.next(offset, data));
    EXPECT_EQ(offset, 4u);
}

TEST(DeviceIdWalk, StopsAtAnOverrunningObject) {
    const auto objects = hex("00 01 41 01 09 42");
    ReadDeviceIdResponse response;
    response.objects = objects;
    std::size_t offset = 0;
    DeviceIdObject object;
    ASSERT_TRUE(response.next(offset, object));
    EXPECT_EQ(object.id, 0);
    EXPECT_EQ(object.value.size(), 1u);
    EXPECT_FALSE(response.next(offset, object));
    EXPECT_EQ(offset, 3u);
}

}  // namespace
}  // namespace mblab::protocol
