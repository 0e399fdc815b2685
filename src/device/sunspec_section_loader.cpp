#include <algorithm>

#include "device/profile_paths.hpp"
#include "device/profile_sections.hpp"
#include "device/sunspec_behaviours.hpp"
#include "device/sunspec_chain.hpp"
#include "device/sunspec_loader.hpp"

// [unit.sunspec]: a SunSpec chain laid from the model definitions (sunspec_chain.hpp) into the
// unit's holding registers, beside any ranges the unit maps itself.
namespace mblab::device {

namespace {

std::optional<double> number_of(const toml::node& node) {
    if (auto i = node.as_integer()) return static_cast<double>(**i);
    if (auto f = node.as_floating_point()) return **f;
    return std::nullopt;
}

bool load_values(Fields& model, ProfileErrors& errors, SunSpecModelValues& out) {
    const toml::table* points = nullptr;
    if (model.has("points") && model.table("points", points)) {
        for (const auto& [key, node] : *points) {
            const std::string path = model.path("points") + "." + std::string(key.str());
            if (auto number = number_of(node)) {
                out.values[std::string(key.str())] = *number;
            } else if (auto text = node.as_string()) {
                out.values[std::string(key.str())] = **text;
            } else {
                errors.fail(node.source(), path,
                            "expected a number or a string, got " + describe_node(node));
                return false;
            }
        }
    }
    const toml::table* limits = nullptr;
    if (model.has("limits") && model.table("limits", limits)) {
        for (const auto& [key, node] : *limits) {
            const toml::array* pair = node.as_array();
            std::optional<double> low;
            std::optional<double> high;
            if (pair && pair->size() == 2) {
                low = number_of(*pair->get(0));
                high = number_of(*pair->get(1));
            }
            if (!low || !high || *low > *high) {
                errors.fail(node.source(), model.path("limits") + "." + std::string(key.str()),
                            "expected [lowest, highest] in engineering units");
                return false;
            }
            out.limits[std::string(key.str())] = {*low, *high};
        }
    }
    return !model.failed();
}

// A model's table, kept until the chain is laid: its behaviours name points only the laid chain
// places.
struct ModelTable {
    const toml::table* table = nullptr;
    std::string path = {};
};

bool load_chain_spec(Fields& section, SunSpecChainSpec& spec, std::vector<ModelTable>& tables) {
    section.integer_as("base", spec.base, 0, 65535);
    section.choice<bool>("split_reads", spec.split_refused,
                         {{"accept", false}, {"exception-02", true}});
    section.boolean("end_model", spec.end_model);
    section.boolean("writes_applied", spec.writes_applied);
    section.boolean("read_only_writable", spec.read_only_writable);
    if (section.failed()) return false;
    if (!section.require("model", "list the models, [[unit.sunspec.model]] id = 1 first")) {
        return false;
    }
    return each_table(section, "model", [&](const toml::table& t, const std::string& path) {
        Fields model(t, path, section.errors());
        SunSpecModelValues values;
        if (!model.require("id", "give the SunSpec model id, e.g. id = 103")) return false;
        model.integer_as("id", values.id, 1, 65534);
        model.integer_as("extra_registers", values.extra_registers, 0, 1000);
        if (const toml::array* moving = nullptr; model.has("behaviours")) {
            model.array("behaviours", moving);
        }
        if (model.failed() || !load_values(model, section.errors(), values)) return false;
        tables.push_back({&t, path});
        model.finish();
        spec.models.push_back(std::move(values));
        return !model.failed();
    });
}

}  // namespace

bool load_sunspec(Fields& unit, UnitSpec& spec) {
    const toml::table* table = nullptr;
    if (!unit.has("sunspec") || !unit.table("sunspec", table)) return !unit.failed();
    Fields section(*table, unit.path("sunspec"), unit.errors());
    SunSpecChainSpec chain_spec;
    std::vector<ModelTable> tables;
    if (!load_chain_spec(section, chain_spec, tables)) return false;
    std::map<std::uint16_t, SunSpecModel> definitions;
    for (const SunSpecModelValues& model : chain_spec.models) {
        const auto file = sunspec_models_dir() / ("model_" + std::to_string(model.id) + ".json");
        auto definition = read_sunspec_model(file);
        if (!definition) {
            section.fail("model", definition.error());
            return false;
        }
        definitions.emplace(model.id, std::move(definition).value());
    }
    auto chain = build_sunspec_chain(chain_spec, definitions);
    if (!chain) {
        section.fail("model", chain.error());
        return false;
    }
    auto& holding = spec.banks[static_cast<std::size_t>(BankKind::HoldingRegisters)];
    const std::uint32_t first = chain->ranges.front().start;
    const std::uint32_t end = chain->ranges.back().start + chain->ranges.back().count;
    for (const RangeSpec& range : holding) {
        if (range.start < end && range.start + range.count > first) {
            section.fail("base", "the SunSpec chain (" + std::to_string(first) + ".." +
                                     std::to_string(end - 1) + ") overlaps holding register " +
                                     std::to_string(range.start) + " of the unit's own ranges");
            return false;
        }
    }
    for (std::size_t i = 0; i < tables.size(); ++i) {
        Fields model(*tables[i].table, tables[i].path, section.errors());
        if (!load_sunspec_behaviours(model, chain_spec.models[i].id, chain->points[i],
                                     chain->ranges, spec.behaviours)) {
            return false;
        }
    }
    holding.insert(holding.end(), std::make_move_iterator(chain->ranges.begin()),
                   std::make_move_iterator(chain->ranges.end()));
    std::sort(holding.begin(), holding.end(),
              [](const RangeSpec& a, const RangeSpec& b) { return a.start < b.start; });
    spec.point_rules = std::move(chain->rules);
    section.finish();
    return !section.failed();
}

}  // namespace mblab::device
