#include "robustness/class_choice.hpp"

#include <fmt/core.h>

#include "support/comma_list.hpp"

namespace mblab::robustness {

namespace {

std::string every_class() {
    std::string out;
    for (std::size_t i = 0; i < kBadInputCount; ++i)
        out += fmt::format("{}{}", i == 0 ? "" : ", ", class_name(static_cast<BadInput>(i)));
    return out;
}

// Sets `to` for each class named in `entries`; the unknown name, or "".
std::string mark(const std::vector<std::string>& entries, bool to, ClassChoice& choice) {
    for (const auto& entry : entries) {
        for (const auto& name : comma_items(entry)) {
            const auto kind = class_named(name);
            if (!kind) return name;
            choice[static_cast<std::size_t>(*kind)] = to;
        }
    }
    return {};
}

}  // namespace

protocol::Result<ClassChoice, std::string> choose_classes(const std::vector<std::string>& only,
                                                          const std::vector<std::string>& skip) {
    ClassChoice choice{};
    choice.fill(only.empty());
    if (auto unknown = mark(only, true, choice); !unknown.empty())
        return fmt::format("--class '{}' is not a class; the classes are {}", unknown,
                           every_class());
    if (auto unknown = mark(skip, false, choice); !unknown.empty())
        return fmt::format("--skip-class '{}' is not a class; the classes are {}", unknown,
                           every_class());
    return choice;
}

}  // namespace mblab::robustness
