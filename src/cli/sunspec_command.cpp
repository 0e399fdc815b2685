#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "conformance/sunspec_scan.hpp"
#include "device/profile_paths.hpp"
#include "device/sunspec_loader.hpp"

// `mblab sunspec TARGET`: the device's SunSpec models, each point with its scaled value and units.
namespace mblab::cli {

namespace {

using conformance::SunSpecModelReading;
using conformance::SunSpecPointReading;
using device::SunSpecType;

struct SunspecOptions {
    ClientOptions client;
    std::string models_dir;
};

std::string hex_words(const std::vector<std::uint16_t>& words) {
    std::string text = "0x";
    for (std::uint16_t word : words)
        text += fmt::format("{:04X}", word);
    return text;
}

// The value as printed: text for strings, hex for bitfields and addresses, the symbol beside an
// enum's number, the scaled number otherwise.
std::string value_text(const SunSpecPointReading& reading) {
    const device::SunSpecPoint& point = *reading.point;
    if (!reading.implemented) return "(not implemented)";
    switch (point.type) {
        case SunSpecType::String:
            return "\"" + device::sunspec_string(reading.words) + "\"";
        case SunSpecType::Bitfield16:
        case SunSpecType::Bitfield32:
        case SunSpecType::Bitfield64:
        case SunSpecType::Ipaddr:
        case SunSpecType::Ipv6addr:
        case SunSpecType::Eui48:
            return hex_words(reading.words);
        default:
            break;
    }
    if (!reading.value) return hex_words(reading.words) + " (scale factor not implemented)";
    const std::string number = fmt::format("{}", *reading.value);
    if (const auto symbol = conformance::symbol_name(point, *reading.value)) {
        return number + " (" + *symbol + ")";
    }
    return number;
}

std::string model_title(const SunSpecModelReading& model) {
    if (model.definition == nullptr) return fmt::format("model {}", model.id);
    const auto& group = model.definition->group;
    return fmt::format("model {} {}{}", model.id, group.name,
                       group.label.empty() ? "" : " (" + group.label + ")");
}

void print_scan(const conformance::SunSpecScan& scan) {
    fmt::print("SunSpec marker at {}, {} models, end model at {}\n", scan.base, scan.models.size(),
               scan.end_address);
    for (const SunSpecModelReading& model : scan.models) {
        fmt::print("\n{} at {}, length {}\n", model_title(model), model.address, model.length);
        if (!model.problem.empty()) fmt::print("  ! {}\n", model.problem);
        for (const SunSpecPointReading& reading : model.points) {
            if (reading.point->type == SunSpecType::Pad) continue;
            const std::string name = reading.group.empty()
                                         ? reading.point->name
                                         : reading.group + "." + reading.point->name;
            const bool shown = reading.implemented && !reading.point->units.empty();
            fmt::print("  {:<6} {:<24} {}{}\n", reading.address, name, value_text(reading),
                       shown ? " " + reading.point->units : "");
        }
    }
}

nlohmann::json scan_json(const conformance::SunSpecScan& scan) {
    nlohmann::json models = nlohmann::json::array();
    for (const SunSpecModelReading& model : scan.models) {
        nlohmann::json points = nlohmann::json::array();
        for (const SunSpecPointReading& reading : model.points) {
            const device::SunSpecPoint& point = *reading.point;
            nlohmann::json entry = {{"name", point.name},
                                    {"type", device::sunspec_type_name(point.type)},
                                    {"address", reading.address},
                                    {"raw", hex_words(reading.words)},
                                    {"implemented", reading.implemented}};
            if (!reading.group.empty()) entry["group"] = reading.group;
            if (reading.implemented) {
                if (point.type == SunSpecType::String) {
                    entry["value"] = device::sunspec_string(reading.words);
                } else if (reading.value) {
                    entry["value"] = *reading.value;
                    if (auto symbol = conformance::symbol_name(point, *reading.value)) {
                        entry["symbol"] = *symbol;
                    }
                }
            }
            if (reading.scale) entry["scale"] = *reading.scale;
            if (!point.units.empty()) entry["units"] = point.units;
            points.push_back(std::move(entry));
        }
        nlohmann::json entry = {{"id", model.id},
                                {"address", model.address},
                                {"length", model.length},
                                {"points", std::move(points)}};
        if (model.definition != nullptr) entry["name"] = model.definition->group.name;
        if (!model.problem.empty()) entry["problem"] = model.problem;
        models.push_back(std::move(entry));
    }
    return {{"base", scan.base}, {"end", scan.end_address}, {"models", std::move(models)}};
}

int run_sunspec(const SunspecOptions& options) {
    CommandOutput output("sunspec", options.client);
    const std::filesystem::path dir = options.models_dir.empty()
                                          ? device::sunspec_models_dir()
                                          : std::filesystem::path(options.models_dir);
    const auto models = device::read_sunspec_models(dir);
    if (!models) return output.usage(models.error());
    return with_client(options.client, output, [&](client::Client& client, CommandOutput& out) {
        const conformance::RegisterReader read = [&client](std::uint16_t address,
                                                           std::uint16_t count) {
            return client.read_holding_registers(address, count);
        };
        const auto scan = conformance::scan_sunspec(read, *models);
        if (!scan) return out.fail({client::ErrorKind::BadAnswer, scan.error(), std::nullopt});
        if (!scan->chain_problem.empty()) {
            return out.fail({client::ErrorKind::BadAnswer, scan->chain_problem, std::nullopt});
        }
        out.document()["sunspec"] = scan_json(*scan);
        return out.done([&] { print_scan(*scan); });
    });
}

constexpr std::string_view kSummary =
    "Read a SunSpec device: find the SunS marker, walk its models and print each point scaled, "
    "with its units";
constexpr std::string_view kHelp = R"(
The marker is looked for at 40000, then 0, then 50000 (holding registers, FC 03); each
model is read in reads of at most 125 registers and decoded by its definition. The
definitions are mblab's own (models 1, 103, 120-123, 203) unless --sunspec-models or
MBLAB_SUNSPEC_MODELS names a folder of the official JSON models (docs/sunspec.md).
Exit status: 0 read, 1 no marker or a chain that does not end, 2 usage error or
unreachable target.
Example: mblab sunspec tcp://127.0.0.1:502 --sunspec-models ~/sunspec-models/json)";

}  // namespace

void add_sunspec_command(CLI::App& app, CommandRunner& runner) {
    auto [cmd, options] = add_client_command<SunspecOptions>(
        app, runner, "sunspec", std::string(kSummary), help_text(kHelp), run_sunspec);
    cmd->add_option("--sunspec-models", options->models_dir,
                    "Folder of SunSpec model definitions (model_*.json), e.g. the json/ folder "
                    "of the official set")
        ->check(CLI::ExistingDirectory);
}

}  // namespace mblab::cli
