#include "transport/bad_address.hpp"

namespace mblab::transport {

std::string bad_address(std::string_view url, std::string_view why, std::string_view expected) {
    std::string out = "bad address '";
    out.append(url);
    out += "': ";
    out.append(why);
    out += " (";
    out.append(expected);
    out += ')';
    return out;
}

}  // namespace mblab::transport
