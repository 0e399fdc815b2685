#include "prometheus_parser.hpp"

#include <cmath>
#include <regex>
#include <set>
#include <sstream>

namespace mblab::test {

namespace {

const std::regex kName("[a-zA-Z_:][a-zA-Z0-9_:]*");
const std::regex kLabelName("[a-zA-Z_][a-zA-Z0-9_]*");

bool parse_value(const std::string& text, double& value) {
    if (text == "+Inf") return value = INFINITY, true;
    if (text == "-Inf") return value = -INFINITY, true;
    if (text == "NaN") return value = NAN, true;
    std::size_t used = 0;
    try {
        value = std::stod(text, &used);
    } catch (...) {
        return false;
    }
    return used == text.size();
}

// name{label="value",...} value
bool parse_sample(const std::string& line, PromSample& sample) {
    std::size_t at = 0;
    while (at < line.size() && line[at] != '{' && line[at] != ' ')
        ++at;
    sample.name = line.substr(0, at);
    if (!std::regex_match(sample.name, kName)) return false;
    if (at < line.size() && line[at] == '{') {
        ++at;
        while (at < line.size() && line[at] != '}') {
            const auto eq = line.find('=', at);
            if (eq == std::string::npos) return false;
            const std::string label = line.substr(at, eq - at);
            if (!std::regex_match(label, kLabelName) || sample.labels.count(label)) return false;
            if (eq + 1 >= line.size() || line[eq + 1] != '"') return false;
            std::string value;
            std::size_t i = eq + 2;
            for (; i < line.size() && line[i] != '"'; ++i) {
                if (line[i] == '\\') {
                    if (++i >= line.size()) return false;
                    if (line[i] == 'n') {
                        value += '\n';
                    } else if (line[i] == '\\' || line[i] == '"') {
                        value += line[i];
                    } else {
                        return false;
                    }
                } else {
                    value += line[i];
                }
            }
            if (i >= line.size()) return false;
            sample.labels[label] = value;
            at = i + 1;
            if (at < line.size() && line[at] == ',') ++at;
        }
        if (at >= line.size()) return false;
        ++at;
    }
    if (at >= line.size() || line[at] != ' ') return false;
    return parse_value(line.substr(at + 1), sample.value);
}

bool belongs(const PromFamily& family, const std::string& sample) {
    if (sample == family.name) return family.type != "histogram";
    if (family.type != "histogram") return false;
    for (const char* suffix : {"_bucket", "_sum", "_count"}) {
        if (sample == family.name + suffix) return true;
    }
    return false;
}

// Buckets cumulative, ascending le, ending at +Inf equal to _count, per label set.
bool check_histogram(const PromFamily& family, std::string& error) {
    std::map<std::map<std::string, std::string>, std::vector<const PromSample*>> series;
    std::map<std::map<std::string, std::string>, double> counts;
    for (const auto& sample : family.samples) {
        auto labels = sample.labels;
        if (sample.name == family.name + "_bucket") {
            labels.erase("le");
            series[labels].push_back(&sample);
        } else if (sample.name == family.name + "_count") {
            counts[labels] = sample.value;
        }
    }
    for (const auto& [labels, buckets] : series) {
        double last_le = -INFINITY, last_count = 0;
        for (const auto* bucket : buckets) {
            double le = 0;
            if (!bucket->labels.count("le") || !parse_value(bucket->labels.at("le"), le) ||
                le <= last_le || bucket->value < last_count) {
                error = family.name + ": buckets not cumulative in ascending le";
                return false;
            }
            last_le = le;
            last_count = bucket->value;
        }
        if (!std::isinf(last_le) || !counts.count(labels) || counts[labels] != last_count) {
            error = family.name + ": the +Inf bucket is missing or differs from _count";
            return false;
        }
    }
    return true;
}

}  // namespace

std::vector<PromFamily> parse_prometheus(const std::string& text, std::string& error) {
    std::vector<PromFamily> families;
    std::set<std::string> seen;
    std::istringstream in(text);
    std::string line;
    std::string help_for, help;
    int number = 0;
    const auto fail = [&](const std::string& why) {
        error = "line " + std::to_string(number) + ": " + why + ": " + line;
        return std::vector<PromFamily>{};
    };
    if (!text.empty() && text.back() != '\n') return fail("the text does not end with a newline");
    while (std::getline(in, line)) {
        ++number;
        if (line.rfind("# HELP ", 0) == 0) {
            const auto space = line.find(' ', 7);
            help_for = line.substr(7, space - 7);
            help = space == std::string::npos ? "" : line.substr(space + 1);
            if (!std::regex_match(help_for, kName)) return fail("bad name in HELP");
        } else if (line.rfind("# TYPE ", 0) == 0) {
            std::istringstream words(line.substr(7));
            PromFamily family;
            words >> family.name >> family.type;
            if (!std::regex_match(family.name, kName) || seen.count(family.name))
                return fail("bad or repeated family");
            if (family.type != "counter" && family.type != "gauge" && family.type != "histogram")
                return fail("unknown type");
            if (help_for != family.name) return fail("TYPE without its HELP just before");
            family.help = help;
            seen.insert(family.name);
            families.push_back(family);
        } else if (line.empty() || line[0] == '#') {
            return fail("an empty line or unknown comment");
        } else {
            PromSample sample;
            if (!parse_sample(line, sample)) return fail("not a sample");
            if (families.empty() || !belongs(families.back(), sample.name))
                return fail("a sample outside its family");
            if (families.back().type == "counter" && (sample.value < 0 || std::isnan(sample.value)))
                return fail("a negative counter");
            families.back().samples.push_back(sample);
        }
    }
    for (const auto& family : families) {
        if (family.type == "histogram" && !check_histogram(family, error)) return {};
    }
    return families;
}

}  // namespace mblab::test
