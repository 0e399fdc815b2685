#include "device/data_bank.hpp"

#include <algorithm>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace mblab::device {

namespace {

// Writes n registers as Modbus puts them on the wire, high byte first.
void copy_big_endian(const std::uint16_t* from, std::uint8_t* to, std::size_t n) {
#if defined(__SSE2__)
    // Eight registers at a time (a read of 125 is most of a request's own work): swap the bytes
    // of each 16-bit lane with two shifts.
    const auto eight = [from, to](std::size_t at) {
        __m128i lanes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(from + at));
        lanes = _mm_or_si128(_mm_slli_epi16(lanes, 8), _mm_srli_epi16(lanes, 8));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(to + 2 * at), lanes);
    };
    if (n >= 8) {
        std::size_t i = 0;
        for (; i + 16 <= n; i += 16) {
            eight(i);
            eight(i + 8);
        }
        if (i + 8 <= n) eight(i);
        // The last few as one more step over the last eight: the registers it writes again get
        // the same bytes, and no one-at-a-time tail is left.
        eight(n - 8);
        return;
    }
#endif
    for (std::size_t i = 0; i < n; ++i) {
        to[2 * i] = static_cast<std::uint8_t>(from[i] >> 8);
        to[2 * i + 1] = static_cast<std::uint8_t>(from[i] & 0xFF);
    }
}

}  // namespace

DataBank::DataBank(const std::vector<RangeSpec>& ranges) {
    std::size_t total = 0;
    for (const auto& range : ranges)
        total += range.count;
    values_.reserve(total);
    for (const auto& range : ranges) {
        segments_.push_back({range.start, range.start + range.count, range.access,
                             static_cast<std::uint32_t>(values_.size())});
        values_.insert(values_.end(), range.values.begin(), range.values.end());
    }
}

std::size_t DataBank::segment_of(std::uint32_t address) const {
    auto it = std::upper_bound(segments_.begin(), segments_.end(), address,
                               [](std::uint32_t a, const Segment& s) { return a < s.start; });
    if (it == segments_.begin()) return segments_.size();
    --it;
    if (address >= it->end) return segments_.size();
    return static_cast<std::size_t>(it - segments_.begin());
}

DataBank::Span DataBank::find(std::uint32_t address, std::uint32_t count) const {
    Span span;
    std::size_t i = segment_of(address);
    if (i == segments_.size() || count == 0) return span;
    span.index = segments_[i].index + (address - segments_[i].start);
    const std::uint32_t end = address + count;
    for (;; ++i) {
        const Segment& s = segments_[i];
        span.has_read_only |= s.access == Access::ReadOnly;
        span.has_write_only |= s.access == Access::WriteOnly;
        if (end <= s.end) break;
        if (i + 1 == segments_.size() || segments_[i + 1].start != s.end) return span;
    }
    span.mapped = true;
    return span;
}

template <class Visit>
void DataBank::each_part(std::uint32_t address, std::uint32_t count, Visit visit) const {
    std::size_t i = segment_of(address);
    std::uint32_t done = 0;
    while (done < count) {
        const Segment& s = segments_[i++];
        const std::uint32_t from = address + done - s.start;
        const std::uint32_t n = std::min(s.end - s.start - from, count - done);
        visit(s, s.index + from, done, n);
        done += n;
    }
}

void DataBank::read(std::uint32_t address, std::span<std::uint16_t> out,
                    std::optional<Access> skip) const {
    each_part(address, static_cast<std::uint32_t>(out.size()),
              [&](const Segment& s, std::uint32_t stored, std::uint32_t done, std::uint32_t n) {
                  if (skip && s.access == *skip) {
                      std::fill_n(out.begin() + done, n, 0);
                  } else {
                      std::copy_n(values_.begin() + stored, n, out.begin() + done);
                  }
              });
}

void DataBank::read_be(std::uint32_t address, std::span<std::uint8_t> out,
                       std::optional<Access> skip) const {
    each_part(address, static_cast<std::uint32_t>(out.size() / 2),
              [&](const Segment& s, std::uint32_t stored, std::uint32_t done, std::uint32_t n) {
                  std::uint8_t* to = out.data() + 2 * done;
                  if (skip && s.access == *skip) {
                      std::fill_n(to, 2 * n, 0);
                      return;
                  }
                  copy_big_endian(values_.data() + stored, to, n);
              });
}

void DataBank::write(std::uint32_t address, std::span<const std::uint16_t> values,
                     std::optional<Access> skip) {
    each_part(address, static_cast<std::uint32_t>(values.size()),
              [&](const Segment& s, std::uint32_t stored, std::uint32_t done, std::uint32_t n) {
                  if (skip && s.access == *skip) return;
                  std::copy_n(values.begin() + done, n, values_.begin() + stored);
              });
}

std::uint32_t DataBank::contiguous_from_zero() const {
    std::uint32_t end = 0;
    for (const auto& s : segments_) {
        if (s.start != end || s.access == Access::WriteOnly) break;
        end = s.end;
    }
    return end;
}

}  // namespace mblab::device
