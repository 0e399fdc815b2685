#pragma once

#include <string_view>

namespace mblab::security {

// Why `text` cannot be a role name, or nullptr when it can. A role is a name people read in rules
// and logs, so it must be well-formed UTF-8 without control characters: a rule file and a log
// line then show the same role the certificate carries.
const char* role_text_problem(std::string_view text);

}  // namespace mblab::security
