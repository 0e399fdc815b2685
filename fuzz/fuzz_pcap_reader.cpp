// The capture reader and the learner on arbitrary files: never a crash or a read out of bounds;
// an error is one line; what is learned is consistent with itself.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>

#include "robustness/learn.hpp"
#include "robustness/pcap_reader.hpp"

namespace {

void require(bool condition, const char* what) {
    if (!condition) {
        std::fprintf(stderr, "pcap reader contract broken: %s\n", what);
        std::abort();
    }
}

void check_ranges(const mblab::robustness::AnsweredRanges& ranges) {
    for (std::size_t t = 0; t < mblab::robustness::kTableCount; ++t) {
        const auto& list = ranges.of(static_cast<mblab::robustness::Table>(t));
        for (std::size_t i = 0; i < list.size(); ++i) {
            require(list[i].first <= list[i].last, "a range ends before it starts");
            require(i == 0 || list[i].first > list[i - 1].last + 1U, "ranges not merged");
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto capture = mblab::robustness::read_pcap(std::span(data, size));
    if (!capture) {
        require(capture.error().find('\n') == std::string::npos, "error of several lines");
        require(capture.error().find("offset") != std::string::npos, "error without an offset");
        return 0;
    }
    require(capture->segments.size() <= capture->packets, "more segments than packets");
    for (std::uint16_t port : {502, 1502}) {
        const auto recon = mblab::robustness::learn_recon(*capture, port, "fuzz.pcap");
        if (!recon) {
            require(recon.error().find('\n') == std::string::npos, "error of several lines");
            continue;
        }
        require(recon->max_read >= 1 && recon->max_read <= 125, "max_read out of 1..125");
        require(recon->serves(0x03), "a read answered, yet FC 03 not served");
        bool checked = false;
        for (const auto& r : recon->ranges.of(mblab::robustness::Table::HoldingRegisters))
            checked |= r.first <= recon->check_address && recon->check_address <= r.last;
        require(checked, "the liveness register is in no answered range");
        check_ranges(recon->ranges);
    }
    return 0;
}
