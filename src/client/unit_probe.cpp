#include "client/unit_probe.hpp"

#include <vector>

namespace mblab::client {

std::string probe_units(Framing framing, std::uint8_t asked,
                        const std::function<bool(std::uint8_t unit)>& answers) {
    const std::vector<std::uint8_t> others = framing == Framing::Mbap
                                                 ? std::vector<std::uint8_t>{1, 255, 0}
                                                 : std::vector<std::uint8_t>{1};
    if (answers(asked)) return {};
    std::vector<std::string> tried;
    for (std::uint8_t unit : others) {
        if (unit == asked) continue;
        if (answers(unit)) {
            return "; the device answers unit " + std::to_string(unit) + ": try --unit " +
                   std::to_string(unit);
        }
        tried.push_back(std::to_string(unit));
    }
    if (tried.empty()) return {};
    std::string list = tried.front();
    for (std::size_t i = 1; i < tried.size(); ++i) {
        list += (i + 1 == tried.size() ? " and " : ", ") + tried[i];
    }
    return (tried.size() > 1 ? "; units " : "; unit ") + list + " did not answer either";
}

}  // namespace mblab::client
