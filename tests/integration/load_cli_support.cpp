#include "load_cli_support.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "support/temp_path.hpp"

namespace mblab::test {

using std::chrono::seconds;

std::string slurp(const std::string& path) {
    std::ifstream file(path);
    std::stringstream text;
    text << file.rdbuf();
    return text.str();
}

Device::Device(const std::string& extra) {
    const std::string text =
        slurp(std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml") + "\n" + extra;
    auto loaded = device::load_profile_text(text, "test");
    EXPECT_TRUE(loaded.ok()) << (loaded.ok() ? "" : loaded.error());
    device = std::move(loaded.value());
    server = std::make_unique<server::BackgroundServer>(*device);
    auto bound = server->start();
    EXPECT_TRUE(bound.ok());
    port = bound.ok() ? *bound : 0;
}

std::string temp(const std::string& name) {
    return test::temp_path(name);
}

std::vector<std::string> load_argv(const std::string& name, const std::vector<std::string>& args) {
    std::vector<std::string> argv = {MBLAB_BINARY,         "load",    "--json",
                                     temp(name + ".json"), "--junit", temp(name + ".xml")};
    argv.insert(argv.end(), args.begin(), args.end());
    std::remove(temp(name + ".json").c_str());
    return argv;
}

LoadRun finish(ChildProcess& child, const std::string& name, std::string out) {
    LoadRun run;
    run.status = child.wait_exit(seconds(60));
    while (auto line = child.read_stdout_line(seconds(5)))
        out += *line + "\n";
    run.out = std::move(out);
    run.err = child.drain_stderr();
    const std::string report = slurp(temp(name + ".json"));
    if (!report.empty()) run.report = nlohmann::json::parse(report);
    run.junit = slurp(temp(name + ".xml"));
    return run;
}

LoadRun mblab_load(const std::string& name, const std::vector<std::string>& args) {
    ChildProcess child(load_argv(name, args));
    return finish(child, name);
}

std::uint64_t sent_with_function(const nlohmann::json& node, int function) {
    std::uint64_t total = 0;
    for (const auto& exchange : node["exchanges"]) {
        if (exchange["function"] == function) total += exchange["sent"].get<std::uint64_t>();
    }
    return total;
}

std::uint64_t failures(const nlohmann::json& node, const char* kind) {
    return node["failures"][kind].get<std::uint64_t>();
}

void expect_clean(const nlohmann::json& node) {
    EXPECT_EQ(node["verdict"], "PASS") << node.dump(2);
    EXPECT_EQ(node["failures"]["total"], 0);
    EXPECT_GT(node["requests"].get<std::uint64_t>(), 0U);
    EXPECT_EQ(node["requests"], node["answers"]);
    EXPECT_TRUE(node["first_failure"].is_null());
}

}  // namespace mblab::test
