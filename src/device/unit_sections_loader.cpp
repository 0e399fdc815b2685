#include <algorithm>

#include "device/fault_rule_schema.hpp"
#include "device/profile_sections.hpp"
#include "protocol/function_code.hpp"
#include "protocol/limits.hpp"

namespace mblab::device {

namespace {

// Object values must leave room for the 2B/0E header and the object's id and length.
constexpr std::size_t kMaxIdentityObject = 244;
// 5B answer: function, byte count, fragment protocol, class, instance, service, error code.
constexpr std::size_t kMaxAttributeValue = protocol::limits::kMaxPdu - 11;
// FC 11 answer: function, byte count, then id + run indicator + extra.
constexpr std::size_t kMaxServerIdBytes = protocol::limits::kMaxPdu - 3;

bool unique_ids(Fields& fields, std::string_view key, std::vector<std::int64_t> ids) {
    std::sort(ids.begin(), ids.end());
    auto twin = std::adjacent_find(ids.begin(), ids.end());
    if (twin == ids.end()) return true;
    fields.fail(key, "the value " + std::to_string(*twin) + " appears twice");
    return false;
}

// A TOML value as the fault rule schema reads it.
RuleValue rule_value(const toml::node& node) {
    RuleValue value;
    value.described = describe_node(node);
    if (auto i = node.as_integer()) {
        value.type = RuleValue::Type::Integer;
        value.integer = **i;
        value.number = static_cast<double>(**i);
    } else if (auto f = node.as_floating_point()) {
        value.type = RuleValue::Type::Number;
        value.number = **f;
    } else if (auto text = node.as_string()) {
        value.type = RuleValue::Type::String;
        value.text = **text;
    } else if (auto list = node.as_array()) {
        value.type = RuleValue::Type::List;
        for (const auto& element : *list)
            value.items.push_back(rule_value(element));
    }
    return value;
}

}  // namespace

bool integer_list(Fields& fields, std::string_view key, std::int64_t min, std::int64_t max,
                  std::vector<std::int64_t>& out) {
    const toml::array* list = nullptr;
    if (!fields.array(key, list)) return false;
    out.clear();
    for (std::size_t i = 0; i < list->size(); ++i) {
        std::int64_t value = 0;
        const std::string path = fields.path(key) + "[" + std::to_string(i) + "]";
        if (!array_integer(*list->get(i), path, min, max, fields.errors(), value)) return false;
        out.push_back(value);
    }
    return unique_ids(fields, key, out);
}

bool byte_string(Fields& fields, std::string_view key, std::size_t max_size,
                 std::vector<std::uint8_t>& out) {
    const toml::node* node = fields.get(key);
    if (!node) return false;
    out.clear();
    if (auto text = node->as_string()) {
        out.assign((*text)->begin(), (*text)->end());
    } else if (auto list = node->as_array()) {
        for (std::size_t i = 0; i < list->size(); ++i) {
            std::int64_t value = 0;
            const std::string path = fields.path(key) + "[" + std::to_string(i) + "]";
            if (!array_integer(*list->get(i), path, 0, 255, fields.errors(), value)) return false;
            out.push_back(static_cast<std::uint8_t>(value));
        }
    } else {
        fields.fail(key, "expected a string or an array of bytes, got " + describe_node(*node));
        return false;
    }
    if (out.size() > max_size) {
        fields.fail(key, "is " + std::to_string(out.size()) + " bytes long; at most " +
                             std::to_string(max_size) + " fit in one answer");
        return false;
    }
    return true;
}

bool load_identification(Fields& unit, IdentitySpec& out) {
    const toml::table* table = nullptr;
    if (!unit.table("identification", table)) return !unit.failed();
    Fields fields(*table, unit.path("identification"), unit.errors());

    static constexpr std::pair<std::string_view, std::uint8_t> kNamed[] = {
        {"vendor", 0x00},          {"product_code", 0x01}, {"revision", 0x02},
        {"vendor_url", 0x03},      {"product_name", 0x04}, {"model", 0x05},
        {"user_application", 0x06}};
    out.objects.clear();
    for (const auto& [key, id] : kNamed) {
        std::vector<std::uint8_t> value;
        if (byte_string(fields, key, kMaxIdentityObject, value)) {
            out.objects.push_back({id, std::string(value.begin(), value.end())});
        }
        if (fields.failed()) return false;
    }
    for (std::uint8_t mandatory = 0; mandatory <= 2; ++mandatory) {
        if (std::none_of(out.objects.begin(), out.objects.end(),
                         [&](const IdentityObject& o) { return o.id == mandatory; })) {
            fields.require(kNamed[mandatory].first,
                           "vendor, product_code and revision are mandatory objects");
            return false;
        }
    }
    std::vector<std::int64_t> private_ids;
    const bool listed =
        each_table(fields, "private", [&](const toml::table& t, const std::string& path) {
            Fields object(t, path, unit.errors());
            std::int64_t id = 0;
            std::vector<std::uint8_t> value;
            if (!object.require("id", "private objects have ids 0x80..0xFF")) return false;
            if (!object.integer("id", id, 0x80, 0xFF)) return false;
            if (!object.require("value", "give the object's text, e.g. value = \"serial 42\"")) {
                return false;
            }
            if (!byte_string(object, "value", kMaxIdentityObject, value)) return false;
            if (std::find(private_ids.begin(), private_ids.end(), id) != private_ids.end()) {
                object.fail("id", "object " + std::to_string(id) + " appears twice");
                return false;
            }
            private_ids.push_back(id);
            out.objects.push_back(
                {static_cast<std::uint8_t>(id), std::string(value.begin(), value.end())});
            object.finish();
            return !object.failed();
        });
    if (!listed) return false;
    std::sort(out.objects.begin(), out.objects.end(),
              [](const IdentityObject& a, const IdentityObject& b) { return a.id < b.id; });

    std::vector<std::int64_t> codes;
    if (integer_list(fields, "read_codes", 1, 4, codes)) {
        out.read_codes.fill(false);
        for (auto code : codes)
            out.read_codes[static_cast<std::size_t>(code)] = true;
    }
    fields.choice<bool>("unknown_object", out.unknown_object_restarts,
                        {{"restart", true}, {"exception-02", false}});
    fields.finish();
    return !fields.failed();
}

bool load_diagnostics(Fields& unit, DiagnosticsSpec& out) {
    out.sub_functions.clear();
    for (std::uint16_t sub = 0; sub <= 0x14; ++sub) {
        if (protocol::is_known_diagnostic_sub(sub)) out.sub_functions.push_back(sub);
    }
    const toml::table* table = nullptr;
    if (!unit.table("diagnostics", table)) return !unit.failed();
    Fields fields(*table, unit.path("diagnostics"), unit.errors());
    std::vector<std::int64_t> subs;
    if (integer_list(fields, "sub_functions", 0, 0xFFFF, subs)) {
        for (std::size_t i = 0; i < subs.size(); ++i) {
            if (!protocol::is_known_diagnostic_sub(static_cast<std::uint16_t>(subs[i]))) {
                fields.fail("sub_functions",
                            "sub-function " + std::to_string(subs[i]) +
                                " is not one the device implements (0-4, 10-18, 20)");
                return false;
            }
        }
        out.sub_functions.assign(subs.begin(), subs.end());
        std::sort(out.sub_functions.begin(), out.sub_functions.end());
    }
    std::int64_t first = 0;
    std::int64_t last = 0;
    if (integer_pair(fields, "echo_words", 0, 125, first, last)) {
        out.echo_min_words = static_cast<std::uint16_t>(first);
        out.echo_max_words = static_cast<std::uint16_t>(last);
    }
    fields.integer_as("register", out.diagnostic_register, 0, 0xFFFF);
    fields.finish();
    return !fields.failed();
}

bool load_server_id(Fields& unit, ServerIdSpec& out) {
    const toml::table* table = nullptr;
    if (!unit.table("server_id", table)) return !unit.failed();
    Fields fields(*table, unit.path("server_id"), unit.errors());
    std::vector<std::uint8_t> id;
    if (byte_string(fields, "id", kMaxServerIdBytes - 1, id)) out.id.assign(id.begin(), id.end());
    fields.boolean("running", out.running);
    fields.string("extra", out.extra);
    if (!fields.failed() && out.id.size() + 1 + out.extra.size() > kMaxServerIdBytes) {
        fields.fail("extra", "id, run indicator and extra together exceed " +
                                 std::to_string(kMaxServerIdBytes) + " bytes");
    }
    fields.finish();
    return !fields.failed();
}

bool load_files(Fields& unit, std::vector<FileSpec>& out) {
    return each_table(unit, "files", [&](const toml::table& t, const std::string& path) {
        Fields fields(t, path, unit.errors());
        FileSpec file;
        std::int64_t records = 0;
        if (!fields.require("number", "files are numbered 1..65535, e.g. number = 1")) return false;
        if (!fields.integer_as("number", file.number, 1, 0xFFFF)) return false;
        if (!fields.require("records", "give the record count, e.g. records = 100")) return false;
        if (!fields.integer("records", records, 1, protocol::limits::kMaxFileRecordNumber + 1)) {
            return false;
        }
        file.records.assign(static_cast<std::size_t>(records), 0);
        std::int64_t fill = 0;
        if (fields.integer("value", fill, 0, 0xFFFF)) {
            std::fill(file.records.begin(), file.records.end(), static_cast<std::uint16_t>(fill));
        }
        for (const auto& other : out) {
            if (other.number == file.number) {
                fields.fail("number", "file " + std::to_string(file.number) + " appears twice");
                return false;
            }
        }
        fields.finish();
        out.push_back(std::move(file));
        return !fields.failed();
    });
}

bool load_objects(Fields& unit, std::vector<SemiObject>& out) {
    return each_table(unit, "objects", [&](const toml::table& t, const std::string& path) {
        Fields fields(t, path, unit.errors());
        SemiObject object;
        if (!fields.require("class", "e.g. class = 1")) return false;
        if (!fields.integer_as("class", object.class_id, 0, 0xFFFF)) return false;
        if (!fields.require("instance", "e.g. instance = 1")) return false;
        if (!fields.integer_as("instance", object.instance_id, 0, 0xFFFF)) return false;
        for (const auto& other : out) {
            if (other.class_id == object.class_id && other.instance_id == object.instance_id) {
                fields.fail("instance", "class " + std::to_string(object.class_id) + " instance " +
                                            std::to_string(object.instance_id) + " appears twice");
                return false;
            }
        }
        const bool loaded =
            each_table(fields, "attributes", [&](const toml::table& a, const std::string& apath) {
                Fields attribute(a, apath, unit.errors());
                ObjectAttribute value;
                if (!attribute.require("id", "e.g. id = 1")) return false;
                if (!attribute.integer_as("id", value.id, 0, 0xFFFF)) return false;
                if (!attribute.require("value", "a string or an array of bytes")) return false;
                if (!byte_string(attribute, "value", kMaxAttributeValue, value.value)) return false;
                for (const auto& other : object.attributes) {
                    if (other.id == value.id) {
                        attribute.fail("id",
                                       "attribute " + std::to_string(value.id) + " appears twice");
                        return false;
                    }
                }
                object.attributes.push_back(std::move(value));
                attribute.finish();
                return !attribute.failed();
            });
        if (!loaded) return false;
        fields.finish();
        out.push_back(std::move(object));
        return !fields.failed();
    });
}

bool load_faults(Fields& unit, std::vector<FaultSpec>& out) {
    return each_table(unit, "faults", [&](const toml::table& t, const std::string& path) {
        std::vector<RuleField> fields;
        for (const auto& [key, node] : t)
            fields.push_back({std::string(key.str()), rule_value(node)});
        FaultSpec fault;
        RuleError error;
        if (read_fault_rule(fields, fault, error)) {
            out.push_back(std::move(fault));
            return true;
        }
        // At the line of the value (or its element) at fault, or of the table when it is missing.
        const toml::node* node = t.get(error.key);
        if (node && error.element && node->as_array()) node = node->as_array()->get(*error.element);
        unit.errors().fail(node ? node->source() : t.source(), path + "." + error.field(),
                           error.message);
        return false;
    });
}

}  // namespace mblab::device
