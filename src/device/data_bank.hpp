#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "device/profile.hpp"

// One data bank of a unit (coils, discrete inputs, holding or input registers): the ranges of
// the profile, each with its access, over one vector holding every mapped address. Ranges are
// laid out in address order, so a request covering adjacent ranges is one contiguous slice.
namespace mblab::device {

class DataBank {
  public:
    DataBank() = default;
    explicit DataBank(const std::vector<RangeSpec>& ranges);  // sorted, not overlapping

    // What a request over [address, address + count) touches.
    struct Span {
        bool mapped = false;  // every address is in some range (no hole)
        bool has_read_only = false;
        bool has_write_only = false;
        std::uint32_t index = 0;  // storage index of `address` when mapped
    };
    Span find(std::uint32_t address, std::uint32_t count) const;

    // Copy out / in a span that find() reported mapped. `skip` leaves addresses of that access
    // alone: reads give 0 for them, writes keep their value.
    void read(std::uint32_t address, std::span<std::uint16_t> out,
              std::optional<Access> skip) const;
    void write(std::uint32_t address, std::span<const std::uint16_t> values,
               std::optional<Access> skip);
    // As read(), straight into big-endian bytes, two per address, as register answers carry them.
    void read_be(std::uint32_t address, std::span<std::uint8_t> out,
                 std::optional<Access> skip) const;

    std::uint16_t at(std::uint32_t index) const { return values_[index]; }
    std::uint16_t& at(std::uint32_t index) { return values_[index]; }

    struct Segment {
        std::uint32_t start = 0;
        std::uint32_t end = 0;  // one past the last address
        Access access = Access::ReadWrite;
        std::uint32_t index = 0;
    };
    const std::vector<Segment>& segments() const { return segments_; }
    // The addresses mapped, counting from 0 without a hole (what a register sweep may read).
    std::uint32_t contiguous_from_zero() const;
    std::uint32_t mapped_count() const { return static_cast<std::uint32_t>(values_.size()); }

  private:
    // The segment holding `address`, or segments_.size().
    std::size_t segment_of(std::uint32_t address) const;
    // Calls visit(segment, storage index, offset in the request, length) for each segment a
    // mapped span crosses.
    template <class Visit>
    void each_part(std::uint32_t address, std::uint32_t count, Visit visit) const;

    std::vector<Segment> segments_;
    std::vector<std::uint16_t> values_;
};

}  // namespace mblab::device
