// The server calls handle() for every request: the common paths must not touch the heap.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdlib>
#include <new>

#include "device_harness.hpp"
#include "support/hex.hpp"

namespace {
std::atomic<bool> counting{false};
std::atomic<int> allocations{0};
}  // namespace

// A counting replacement of the global allocator; GCC cannot see that new and delete here pair
// malloc with free.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

namespace {
void* counted_malloc(std::size_t size) noexcept {
    if (counting) ++allocations;
    return std::malloc(size ? size : 1);
}
}  // namespace

// Every form is replaced so that no allocation pairs ours with a sanitizer's.
void* operator new(std::size_t size) {
    if (void* p = counted_malloc(size)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
    return operator new(size);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    return counted_malloc(size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
    return counted_malloc(size);
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete[](void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
    std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
    std::free(p);
}

namespace mblab::test {
namespace {

TEST(NoAllocation, HandleServesWithoutHeapAllocation) {
    auto device = shipped_device("reference");
    const std::array<std::vector<std::uint8_t>, 5> requests = {
        hex("03 00 00 00 7D"), hex("10 00 10 00 02 04 12 34 56 78"), hex("01 00 00 07 D0"),
        hex("2B 0E 03 00"), hex("03 00 00 FF FF")};
    std::array<std::uint8_t, 253> response{};
    counting = true;
    for (const auto& request : requests) {
        const auto reply = device->handle({1, device::Link::Tcp}, request, response);
        EXPECT_EQ(reply.action, device::ReplyAction::Answer);
    }
    counting = false;
    EXPECT_EQ(allocations.load(), 0);
}

}  // namespace
}  // namespace mblab::test
