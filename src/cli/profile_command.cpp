#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <array>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

#include "cli/commands.hpp"
#include "device/register_map_csv.hpp"

// `mblab profile import-csv FILE.csv`: a register map kept as a spreadsheet, printed as profile
// TOML for `mblab serve`.
namespace mblab::cli {

namespace {

struct ImportOptions {
    std::string file;
    int unit = 1;
    std::string name;
};

// The file's text, or why it cannot be used: a directory, a file past the size bound, or a
// stream (a pipe, /dev/zero) that goes on past it.
std::optional<std::string> read_csv(const std::string& file, std::string& text) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const auto status = fs::status(file, ec);
    if (!ec && fs::is_directory(status)) return file + " is a directory, not a CSV file";
    const auto too_large = fmt::format(
        "{} is larger than {} MiB, far more than a register map of every address takes; "
        "check the file",
        file, device::kMaxCsvBytes >> 20);
    if (!ec && fs::is_regular_file(status)) {
        const auto size = fs::file_size(file, ec);
        if (!ec && size > device::kMaxCsvBytes) return too_large;
    }
    std::ifstream in(file, std::ios::binary);
    if (!in) return "cannot open " + file + "; check the path";
    std::array<char, 64 * 1024> chunk{};
    while (in.read(chunk.data(), chunk.size()) || in.gcount() > 0) {
        text.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
        if (text.size() > device::kMaxCsvBytes) return too_large;
    }
    if (in.bad()) return "cannot read " + file;
    return std::nullopt;
}

int run_import(const ImportOptions& options) {
    std::string text;
    if (const auto error = read_csv(options.file, text)) {
        fmt::print(stderr, "mblab profile import-csv: {}\n", *error);
        return kExitUsage;
    }
    device::CsvImport import;
    import.source = options.file;
    import.name =
        options.name.empty() ? std::filesystem::path(options.file).stem().string() : options.name;
    import.unit = static_cast<std::uint8_t>(options.unit);
    const auto profile = device::register_map_to_profile(text, import);
    if (!profile) {
        fmt::print(stderr, "mblab profile import-csv: {}\n", profile.error());
        return kExitUsage;
    }
    fmt::print("{}", profile->toml);
    return kExitOk;
}

}  // namespace

void add_profile_command(CLI::App& app, CommandRunner& runner) {
    CLI::App* group = app.add_subcommand("profile", "work with device profiles: import-csv");
    group->require_subcommand(1);
    group->footer(
        "Exit status: 0 done, 2 usage error, or a file that cannot be read or used.\n"
        "Example: mblab profile import-csv registers.csv > registers.toml");
    auto options = std::make_shared<ImportOptions>();
    CLI::App* cmd = group->add_subcommand(
        "import-csv", "print the profile TOML of a register map kept as CSV, one point a line");
    cmd->footer(help_text(R"(
The first line names the columns: address (required), bank (holding, input, coil,
discrete), type (u16, i16, u32, i32, u64, i64, f32, f64), name, description,
behaviour and its parameters (docs/profiles.md "Register maps from CSV").
Exit status: 0 printed, 2 usage error, or a file that cannot be read or used (the
message names its line and column).
Example: mblab profile import-csv registers.csv > registers.toml)"));
    cmd->add_option("file", options->file, "the CSV file")->required();
    cmd->add_option("--unit", options->unit, "the unit id of the profile's one unit")
        ->check(CLI::Range(1, 247))
        ->capture_default_str();
    cmd->add_option("--name", options->name, "the profile's name (default: the file's stem)");
    cmd->callback([options, &runner] { runner = [options] { return run_import(*options); }; });
}

}  // namespace mblab::cli
