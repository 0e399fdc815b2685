#pragma once

#include <map>
#include <string>
#include <vector>

// A strict reader of the Prometheus text format (0.0.4) for the tests: it refuses what a
// scraper would, and checks what the format promises about histograms.
namespace mblab::test {

struct PromSample {
    std::string name;
    std::map<std::string, std::string> labels;
    double value = 0;
};

struct PromFamily {
    std::string name;
    std::string type;
    std::string help;
    std::vector<PromSample> samples;
};

// The families in order; on the first fault, empty with `error` naming the line.
std::vector<PromFamily> parse_prometheus(const std::string& text, std::string& error);

}  // namespace mblab::test
