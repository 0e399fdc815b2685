#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/number_text.hpp"

// `mblab devid TARGET [basic|regular|extended|OBJECT]`: read device identification (FC 2B / 0E),
// following "more follows" across transactions until the device has sent every object.
namespace mblab::cli {

namespace {

struct DevidOptions {
    ClientOptions client;
    std::string what = "basic";
};

struct ObjectName {
    std::uint8_t id;
    const char* name;   // on the command line
    const char* title;  // in the output, as [APP] table 6.21 names it
};

constexpr std::array<ObjectName, 7> kObjects = {{
    {0x00, "vendor-name", "vendor name"},
    {0x01, "product-code", "product code"},
    {0x02, "revision", "major minor revision"},
    {0x03, "vendor-url", "vendor url"},
    {0x04, "product-name", "product name"},
    {0x05, "model-name", "model name"},
    {0x06, "user-application-name", "user application name"},
}};

struct Request {
    std::uint8_t read_code = 1;
    std::uint8_t object_id = 0;
};

std::optional<Request> parse_what(const std::string& what) {
    if (what == "basic") return Request{1, 0};
    if (what == "regular") return Request{2, 0};
    if (what == "extended") return Request{3, 0};
    for (const auto& object : kObjects) {
        if (what == object.name) return Request{4, object.id};
    }
    if (auto id = parse_unsigned(what, 0xFF)) return Request{4, static_cast<std::uint8_t>(*id)};
    return std::nullopt;
}

std::string object_title(std::uint8_t id) {
    for (const auto& object : kObjects) {
        if (object.id == id) return object.title;
    }
    return id >= 0x80 ? "private object" : "reserved object";
}

std::string conformity_text(std::uint8_t level) {
    static constexpr std::array<const char*, 4> kLevels = {"?", "basic", "regular", "extended"};
    const unsigned stream = level & 0x7FU;
    return fmt::format("0x{:02X} ({}{})", level, stream < kLevels.size() ? kLevels[stream] : "?",
                       (level & 0x80U) ? ", individual access" : "");
}

int run_devid(const DevidOptions& options) {
    CommandOutput output("devid", options.client);
    auto request = parse_what(options.what);
    if (!request) {
        return output.usage(fmt::format(
            "'{}' is not basic, regular, extended, an object id (0..255) or an object name",
            options.what));
    }
    return with_client(options.client, output, [&](client::Client& client, CommandOutput& out) {
        auto identity = client.read_device_identification(request->read_code, request->object_id);
        if (!identity) return out.fail(identity.error());
        auto& document = out.document();
        document["read_code"] = identity->read_code;
        document["conformity_level"] = identity->conformity_level;
        document["transactions"] = identity->transactions;
        auto& objects = document["objects"] = nlohmann::json::array();
        std::size_t width = 0;
        for (const auto& object : identity->objects) {
            width = std::max(width, object_title(object.id).size());
        }
        if (!out.json()) {
            fmt::print("conformity level {}\n", conformity_text(identity->conformity_level));
        }
        for (const auto& object : identity->objects) {
            objects.push_back(
                {{"id", object.id}, {"name", object_title(object.id)}, {"value", object.value}});
            if (!out.json()) {
                fmt::print("0x{:02X}  {:<{}}  {}\n", object.id, object_title(object.id), width,
                           object.value);
            }
        }
        return out.done();
    });
}

// What `mblab --help` says of the command.
constexpr std::string_view kSummary =
    "Read device identification (FC 2B / 0E), every object the device has";
constexpr std::string_view kHelp = R"(
WHAT is basic (default, objects 00..02), regular (..7F), extended (..FF), or one object
by id (0x80) or name: vendor-name, product-code, revision, vendor-url, product-name,
model-name, user-application-name. Stream reads follow "more follows" across as many
transactions as the device needs.
Exit status: 0 read, 1 the device answered an exception or no proper answer, 2 usage
error or unreachable target.
Example: mblab devid tcp://127.0.0.1:502 extended)";

}  // namespace

void add_devid_command(CLI::App& app, CommandRunner& runner) {
    auto [cmd, options] = add_client_command<DevidOptions>(
        app, runner, "devid", std::string(kSummary), help_text(kHelp), run_devid);
    cmd->add_option("what", options->what, "basic, regular, extended, or an object id or name");
}

}  // namespace mblab::cli
