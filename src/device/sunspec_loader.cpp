#include "device/sunspec_loader.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace mblab::device {
namespace {

using Json = nlohmann::json;

// The first problem found, as the one line the caller prints.
struct Problems {
    std::string source;
    std::string first = {};

    bool fail(const std::string& where, const std::string& what) {
        if (first.empty()) first = source + ": " + where + ": " + what;
        return false;
    }
};

std::string text_of(const Json& object, const char* key) {
    const auto found = object.find(key);
    return found != object.end() && found->is_string() ? found->get<std::string>() : std::string();
}

bool flag(const Json& object, const char* key, const char* yes) {
    return text_of(object, key) == yes;
}

bool load_point(const Json& json, const std::string& where, Problems& problems,
                SunSpecPoint& point) {
    if (!json.is_object()) return problems.fail(where, "a point must be an object");
    point.name = text_of(json, "name");
    const std::string at = where + "." + (point.name.empty() ? "?" : point.name);
    if (point.name.empty()) return problems.fail(at, "a point needs a \"name\"");
    point.label = text_of(json, "label");
    const std::string type_name = text_of(json, "type");
    const auto type = sunspec_type_named(type_name);
    if (!type) return problems.fail(at, "unknown type \"" + type_name + "\"");
    point.type = *type;
    const auto size = json.find("size");
    if (size == json.end() || !size->is_number_unsigned() || size->get<std::uint32_t>() == 0 ||
        size->get<std::uint32_t>() > 0xFFFF) {
        return problems.fail(at, "\"size\" must be a number of registers, 1 or more");
    }
    point.size = size->get<std::uint16_t>();
    const std::uint16_t expected = sunspec_type_size(point.type);
    if (expected != 0 && point.size != expected) {
        return problems.fail(at, "size " + std::to_string(point.size) + " for type " + type_name +
                                     ", which takes " + std::to_string(expected));
    }
    if (const auto sf = json.find("sf"); sf != json.end()) {
        if (sf->is_string()) {
            point.sf = sf->get<std::string>();
        } else if (sf->is_number_integer()) {
            point.fixed_sf = sf->get<int>();
        } else {
            return problems.fail(at, "\"sf\" must name a sunssf point or be a number");
        }
    }
    point.units = text_of(json, "units");
    point.writable = flag(json, "access", "RW");
    point.mandatory = flag(json, "mandatory", "M");
    point.is_static = flag(json, "static", "S");
    if (const auto value = json.find("value"); value != json.end() && value->is_number_integer()) {
        point.value = value->get<std::int64_t>();
    }
    if (const auto symbols = json.find("symbols"); symbols != json.end()) {
        if (!symbols->is_array()) return problems.fail(at, "\"symbols\" must be a list");
        for (const Json& symbol : *symbols) {
            const auto value = symbol.find("value");
            if (!symbol.is_object() || text_of(symbol, "name").empty() || value == symbol.end() ||
                !value->is_number_integer()) {
                return problems.fail(at, "each symbol needs a \"name\" and an integer \"value\"");
            }
            point.symbols.push_back({text_of(symbol, "name"), value->get<std::int64_t>()});
        }
    }
    return true;
}

// `names` holds the points of the groups above, for counts and scale factors named there.
bool load_group(const Json& json, const std::string& where, std::vector<std::string> names,
                Problems& problems, SunSpecGroup& group) {
    if (!json.is_object()) return problems.fail(where, "a group must be an object");
    group.name = text_of(json, "name");
    const std::string at = where.empty() ? group.name : where + "." + group.name;
    if (group.name.empty()) return problems.fail(at.empty() ? "group" : at, "a group needs a name");
    group.label = text_of(json, "label");
    if (const auto count = json.find("count"); count != json.end()) {
        if (count->is_string()) {
            group.count_point = count->get<std::string>();
        } else if (count->is_number_unsigned()) {
            group.fixed_count = count->get<std::uint32_t>();
        } else {
            return problems.fail(at, "\"count\" must name a point or be a number");
        }
    }
    const auto points = json.find("points");
    if (points != json.end() && !points->is_array()) {
        return problems.fail(at, "\"points\" must be a list");
    }
    std::uint32_t offset = 0;
    for (const Json& entry : points == json.end() ? Json::array() : *points) {
        SunSpecPoint point;
        if (!load_point(entry, at, problems, point)) return false;
        point.offset = offset;
        offset += point.size;
        names.push_back(point.name);
        group.points.push_back(std::move(point));
    }
    auto named = [&names](const std::string& name) {
        return std::find(names.begin(), names.end(), name) != names.end();
    };
    for (const SunSpecPoint& point : group.points) {
        if (!point.sf.empty() && !named(point.sf)) {
            return problems.fail(at + "." + point.name,
                                 "scale factor \"" + point.sf + "\" names no point");
        }
    }
    if (const auto groups = json.find("groups"); groups != json.end()) {
        if (!groups->is_array()) return problems.fail(at, "\"groups\" must be a list");
        for (const Json& entry : *groups) {
            SunSpecGroup child;
            if (!load_group(entry, at, names, problems, child)) return false;
            if (!child.count_point.empty() && !named(child.count_point)) {
                return problems.fail(at + "." + child.name,
                                     "count \"" + child.count_point + "\" names no point");
            }
            const std::uint32_t times = child.count_point.empty() ? child.fixed_count : 1;
            offset += times * child.size;
            group.groups.push_back(std::move(child));
        }
    }
    group.size = offset;
    return true;
}

}  // namespace

Loaded<SunSpecModel> parse_sunspec_model(std::string_view text, std::string_view source) {
    Problems problems{std::string(source)};
    const Json root = Json::parse(text, nullptr, false);
    if (root.is_discarded() || !root.is_object()) {
        return problems.source +
               ": not a JSON object (a SunSpec model file has \"id\" and "
               "\"group\")";
    }
    const auto id = root.find("id");
    if (id == root.end() || !id->is_number_unsigned() || id->get<std::uint32_t>() > 0xFFFE) {
        return problems.source + ": \"id\" must be a model id, 1 to 65534";
    }
    const auto top = root.find("group");
    if (top == root.end()) return problems.source + ": no \"group\"";
    SunSpecModel model;
    model.id = id->get<std::uint16_t>();
    if (!load_group(*top, "", {}, problems, model.group)) return problems.first;
    const auto& points = model.group.points;
    if (points.size() < 2 || points[0].name != "ID" || points[1].name != "L") {
        return problems.source + ": " + model.group.name +
               ": the first points must be ID and L (the model's id and length)";
    }
    if (points[0].value && *points[0].value != model.id) {
        return problems.source + ": " + model.group.name + ".ID: value " +
               std::to_string(*points[0].value) + " is not the model's id " +
               std::to_string(model.id);
    }
    // Counted groups count no instance in the fixed part; fixed counts count theirs.
    model.fixed_length = model.length_with({});
    return model;
}

Loaded<SunSpecModel> read_sunspec_model(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return path.string() + ": cannot open the SunSpec model file";
    std::ostringstream text;
    text << in.rdbuf();
    return parse_sunspec_model(text.str(), path.string());
}

Loaded<std::map<std::uint16_t, SunSpecModel>> read_sunspec_models(
    const std::filesystem::path& dir) {
    std::error_code error;
    std::filesystem::directory_iterator entries(dir, error);
    if (error) return dir.string() + ": cannot read the SunSpec models folder: " + error.message();
    std::map<std::uint16_t, SunSpecModel> models;
    for (const auto& entry : entries) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("model_", 0) != 0 || entry.path().extension() != ".json") continue;
        auto model = read_sunspec_model(entry.path());
        if (!model) return model.error();
        const std::uint16_t id = model->id;
        if (!models.emplace(id, std::move(model).value()).second) {
            return entry.path().string() + ": a second definition of model " + std::to_string(id);
        }
    }
    if (models.empty()) return dir.string() + ": no model_*.json files";
    return models;
}

}  // namespace mblab::device
