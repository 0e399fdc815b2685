#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "child_process.hpp"

// What the tests of `mblab conform-client` share: its run with the JSON report on standard
// output, read back as a verdict per scenario.
namespace mblab::test {

inline const std::string kModbusClient =
    std::string(MBLAB_SOURCE_DIR) + "/tests/clients/modbus_client.py";

// tests/clients/modbus_client.py's command line, timeout 0.3 s, with `defect` unless empty.
inline std::vector<std::string> python_client(unsigned retries, const std::string& defect) {
    std::vector<std::string> argv = {"python3",
                                     kModbusClient,
                                     "{host}",
                                     "{port}",
                                     "{unit}",
                                     "{address}",
                                     "{count}",
                                     "--timeout",
                                     "0.3",
                                     "--retries",
                                     std::to_string(retries)};
    if (!defect.empty()) argv.insert(argv.end(), {"--defect", defect});
    return argv;
}

struct ClientVerdicts {
    int status = -1;
    std::map<std::string, std::string> by_case;  // id -> PASS, FAIL, N/A
    std::string console;
};

// `argv` must ask for the JSON report on standard output ("--json -").
inline ClientVerdicts client_verdicts(const std::vector<std::string>& argv) {
    const auto ran = run_program(argv, std::chrono::seconds(240));
    ClientVerdicts verdicts{ran.status, {}, ran.err};
    const auto report = nlohmann::json::parse(ran.out, nullptr, false);
    if (report.is_discarded()) {
        ADD_FAILURE() << "no JSON report: " << ran.out << ran.err;
        return verdicts;
    }
    EXPECT_EQ(report["tool"], "mblab conform-client");
    for (const auto& c : report["suites"][0]["cases"])
        verdicts.by_case[c["id"].get<std::string>()] = c["verdict"].get<std::string>();
    return verdicts;
}

// `cases` cases ran; every one is PASS but those in `failing` (FAIL) and `na` (N/A).
inline void expect_verdicts(const ClientVerdicts& verdicts, std::size_t cases,
                            const std::vector<std::string>& failing,
                            const std::vector<std::string>& na) {
    ASSERT_EQ(verdicts.by_case.size(), cases) << verdicts.console;
    for (const auto& [id, verdict] : verdicts.by_case) {
        const bool fails = std::find(failing.begin(), failing.end(), id) != failing.end();
        const bool skipped = std::find(na.begin(), na.end(), id) != na.end();
        EXPECT_EQ(verdict, fails     ? "FAIL"
                           : skipped ? "N/A"
                                     : "PASS")
            << id << "\n"
            << verdicts.console;
    }
    EXPECT_EQ(verdicts.status, failing.empty() ? 0 : 1);
}

}  // namespace mblab::test
