#include "web/metrics_text.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>

namespace mblab::web {

namespace {

constexpr std::array<double, 17> kBounds{0.00005, 0.0001, 0.00025, 0.0005, 0.001, 0.0025,
                                         0.005,   0.01,   0.025,   0.05,   0.1,   0.25,
                                         0.5,     1,      2.5,     5,      10};

std::string escaped(const std::string& value) {
    std::string out;
    for (char c : value) {
        if (c == '\\' || c == '"') {
            out += '\\';
            out += c;
        } else if (c == '\n') {
            out += "\\n";
        } else {
            out += c;
        }
    }
    return out;
}

std::string label_text(const Labels& labels) {
    if (labels.empty()) return {};
    std::string out = "{";
    for (std::size_t i = 0; i < labels.size(); ++i) {
        out += fmt::format("{}{}=\"{}\"", i ? "," : "", labels[i].first, escaped(labels[i].second));
    }
    return out + "}";
}

// Integers as integers (counters are), the rest in the shortest form that reads back the same.
std::string number_text(double value) {
    if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
    if (std::isnan(value)) return "NaN";
    return fmt::format("{}", value);
}

}  // namespace

std::span<const double> latency_bounds_seconds() {
    return kBounds;
}

void MetricsText::family(const std::string& name, const std::string& type,
                         const std::string& help) {
    text_ += fmt::format("# HELP {} {}\n# TYPE {} {}\n", name, help, name, type);
}

void MetricsText::sample(const std::string& name, const Labels& labels, double value) {
    text_ += fmt::format("{}{} {}\n", name, label_text(labels), number_text(value));
}

void MetricsText::histogram(const std::string& name, const Labels& labels,
                            std::span<const std::uint64_t> cumulative, std::uint64_t count,
                            double sum_seconds) {
    for (std::size_t i = 0; i < cumulative.size() && i < kBounds.size(); ++i) {
        auto with_le = labels;
        with_le.emplace_back("le", number_text(kBounds[i]));
        sample(name + "_bucket", with_le, static_cast<double>(cumulative[i]));
    }
    auto with_inf = labels;
    with_inf.emplace_back("le", "+Inf");
    sample(name + "_bucket", with_inf, static_cast<double>(count));
    sample(name + "_sum", labels, sum_seconds);
    sample(name + "_count", labels, static_cast<double>(count));
}

}  // namespace mblab::web
