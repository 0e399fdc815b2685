#include "device/profile_loader.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "device/profile_sections.hpp"
#include "protocol/function_code.hpp"

namespace mblab::device {

namespace {

constexpr std::array<std::string_view, kBankKinds> kBankKeys = {
    "coils", "discrete_inputs", "holding_registers", "input_registers"};

// The SEMI alternate encoding (CTP 7.13.2): "SE", "MI", zero-sum.
constexpr std::array<std::uint16_t, 3> kSemiSignature = {0x5345, 0x4D49, 0x5F72};

struct PlacedRange {
    RangeSpec range;
    std::size_t index = 0;  // position in the profile, for messages
    toml::source_region where;
};

bool load_bank(Fields& unit, BankKind kind, std::vector<RangeSpec>& out) {
    const std::string_view key = bank_key(kind);
    std::vector<PlacedRange> placed;
    const bool loaded = each_table(unit, key, [&](const toml::table& t, const std::string& path) {
        PlacedRange entry;
        entry.index = placed.size();
        entry.where = t.source();
        if (!load_range(t, path, kind, unit.errors(), entry.range)) return false;
        placed.push_back(std::move(entry));
        return true;
    });
    if (!loaded) return false;
    std::stable_sort(placed.begin(), placed.end(), [](const PlacedRange& a, const PlacedRange& b) {
        return a.range.start < b.range.start;
    });
    for (std::size_t i = 1; i < placed.size(); ++i) {
        const auto& before = placed[i - 1];
        const auto& after = placed[i];
        if (after.range.start >= before.range.start + before.range.count) continue;
        const auto& later = before.index > after.index ? before : after;
        const auto& earlier = before.index > after.index ? after : before;
        const auto last = [](const RangeSpec& r) { return r.start + r.count - 1; };
        unit.errors().fail(
            later.where, unit.path(key) + "[" + std::to_string(later.index) + "]",
            "addresses " + std::to_string(later.range.start) + ".." +
                std::to_string(last(later.range)) + " overlap " + std::string(key) + "[" +
                std::to_string(earlier.index) + "] (" + std::to_string(earlier.range.start) + ".." +
                std::to_string(last(earlier.range)) + "); ranges of a bank must not overlap");
        return false;
    }
    out.clear();
    for (auto& entry : placed)
        out.push_back(std::move(entry.range));
    return true;
}

const RangeSpec* range_at(const std::vector<RangeSpec>& ranges, std::uint32_t address) {
    for (const auto& range : ranges) {
        if (address >= range.start && address < range.start + range.count) return &range;
    }
    return nullptr;
}

// Makes `address` a read-only range of its own holding `value`, splitting the range it was in.
void pin_register(std::vector<RangeSpec>& ranges, std::uint32_t address, std::uint16_t value) {
    auto it = std::find_if(ranges.begin(), ranges.end(), [&](const RangeSpec& r) {
        return address >= r.start && address < r.start + r.count;
    });
    RangeSpec whole = std::move(*it);
    it = ranges.erase(it);
    const std::uint32_t offset = address - whole.start;
    RangeSpec before = whole;
    before.count = offset;
    before.values.assign(whole.values.begin(), whole.values.begin() + offset);
    RangeSpec pinned = whole;
    pinned.start = address;
    pinned.count = 1;
    pinned.access = Access::ReadOnly;
    pinned.values.assign(1, value);
    pinned.name = "semi_signature";
    pinned.type = ValueType::U16;
    RangeSpec after = whole;
    after.start = address + 1;
    after.count = whole.count - offset - 1;
    after.values.assign(whole.values.begin() + offset + 1, whole.values.end());
    if (after.count) it = ranges.insert(it, std::move(after));
    it = ranges.insert(it, std::move(pinned));
    if (before.count) ranges.insert(it, std::move(before));
}

bool load_semi_signature(Fields& unit, UnitSpec& spec) {
    const toml::node* node = unit.get("semi_signature");
    if (!node) return true;
    std::int64_t address = 0;
    if (auto flag = node->as_boolean()) {
        if (!**flag) return true;
    } else if (!array_integer(*node, unit.path("semi_signature"), 0, 0xFFFD, unit.errors(),
                              address)) {
        return false;
    }
    auto& holding = spec.banks[static_cast<std::size_t>(BankKind::HoldingRegisters)];
    for (std::uint32_t i = 0; i < kSemiSignature.size(); ++i) {
        if (!range_at(holding, static_cast<std::uint32_t>(address) + i)) {
            unit.fail("semi_signature", "holding register " + std::to_string(address + i) +
                                            " is not in any holding_registers range; the "
                                            "signature takes 3 registers");
            return false;
        }
    }
    for (std::uint32_t i = 0; i < kSemiSignature.size(); ++i) {
        pin_register(holding, static_cast<std::uint32_t>(address) + i, kSemiSignature[i]);
    }
    spec.semi_signature = static_cast<std::uint16_t>(address);
    return true;
}

bool load_functions(Fields& unit, UnitSpec& spec) {
    for (unsigned code = 1; code < 0x80; ++code) {
        spec.functions[code] = protocol::is_public_function(static_cast<std::uint8_t>(code));
    }
    const toml::node* node = unit.get("functions");
    if (!node) return true;
    if (auto all = node->as_string(); all && **all == "all") return true;
    if (!node->as_array()) {
        unit.fail("functions",
                  "expected \"all\" or a list of function codes, got " + describe_node(*node));
        return false;
    }
    std::vector<std::int64_t> codes;
    if (!integer_list(unit, "functions", 1, 0x7F, codes)) return false;
    spec.functions.fill(false);
    for (auto code : codes) {
        if (!protocol::is_public_function(static_cast<std::uint8_t>(code))) {
            unit.fail("functions", "function " + std::to_string(code) +
                                       " is not a public function code the device implements");
            return false;
        }
        spec.functions[static_cast<std::size_t>(code)] = true;
    }
    return true;
}

// The exception that refuses an access to addresses of the other access, or `pass`: the access
// goes through and passes over them.
void load_refusal(Fields& unit, std::string_view key, std::optional<protocol::ExceptionCode>& out,
                  std::string_view pass) {
    using protocol::ExceptionCode;
    unit.choice<std::optional<ExceptionCode>>(key, out,
                                              {{"exception-01", ExceptionCode::IllegalFunction},
                                               {"exception-02", ExceptionCode::IllegalDataAddress},
                                               {"exception-03", ExceptionCode::IllegalDataValue},
                                               {"exception-04", ExceptionCode::ServerDeviceFailure},
                                               {pass, std::nullopt}});
}

bool load_access_policy(Fields& unit, AccessPolicy& policy) {
    load_refusal(unit, "write_read_only", policy.write_read_only, "ignore");
    load_refusal(unit, "read_write_only", policy.read_write_only, "zeros");
    return !unit.failed();
}

bool load_fifos(Fields& unit, UnitSpec& spec) {
    std::vector<std::int64_t> fifos;
    if (!integer_list(unit, "fifos", 0, 0xFFFF, fifos)) return !unit.failed();
    const auto& holding = spec.banks[static_cast<std::size_t>(BankKind::HoldingRegisters)];
    for (auto address : fifos) {
        if (!range_at(holding, static_cast<std::uint32_t>(address))) {
            unit.fail("fifos", "holding register " + std::to_string(address) +
                                   " (the FIFO count) is not in any holding_registers range");
            return false;
        }
        spec.fifos.push_back(static_cast<std::uint16_t>(address));
    }
    std::sort(spec.fifos.begin(), spec.fifos.end());
    return true;
}

bool load_unit(const toml::table& table, const std::string& path, const Profile& profile,
               ProfileErrors& errors, UnitSpec& spec) {
    Fields unit(table, path, errors);
    if (!unit.require("id", "give the unit id (serial address), e.g. id = 1")) return false;
    if (!unit.integer_as("id", spec.id, profile.min_address, profile.max_address)) return false;
    for (const auto& other : profile.units) {
        if (other.id == spec.id) {
            unit.fail("id", "unit " + std::to_string(spec.id) + " appears twice");
            return false;
        }
    }
    unit.string("name", spec.name);
    for (std::size_t kind = 0; kind < kBankKinds; ++kind) {
        if (!load_bank(unit, static_cast<BankKind>(kind), spec.banks[kind])) return false;
    }
    if (!load_sunspec(unit, spec)) return false;
    if (!load_functions(unit, spec) || !load_access_policy(unit, spec.access_policy)) return false;
    unit.integer_as("max_read_registers", spec.max_read_registers, 1, 125);
    unit.integer_as("max_read_bits", spec.max_read_bits, 1, 2000);
    unit.integer_as("exception_status", spec.exception_status, 0, 0xFF);
    if (unit.failed() || !load_semi_signature(unit, spec) || !load_fifos(unit, spec)) return false;
    if (!load_server_id(unit, spec.server_id) || !load_diagnostics(unit, spec.diagnostics) ||
        !load_identification(unit, spec.identification) || !load_files(unit, spec.files) ||
        !load_objects(unit, spec.objects) || !load_faults(unit, spec.faults) ||
        !load_behaviours(unit, spec, spec.behaviours)) {
        return false;
    }
    if (spec.identification.objects.empty()) {
        spec.identification.objects = {{0x00, "mblab"}, {0x01, "mblab-device"}, {0x02, "1.0"}};
    }
    unit.finish();
    return !unit.failed();
}

bool load_root(const toml::table& root, ProfileErrors& errors, Profile& profile) {
    Fields fields(root, "", errors);
    fields.string("name", profile.name);
    fields.string("description", profile.description);
    fields.integer_as("fault_seed", profile.fault_seed, 0, INT64_MAX);
    fields.integer_as("behaviour_seed", profile.behaviour_seed, 0, INT64_MAX);
    fields.choice<UnmatchedUnit>("unmatched_unit", profile.unmatched_unit,
                                 {{"first-unit", UnmatchedUnit::FirstUnit},
                                  {"ignore", UnmatchedUnit::Ignore},
                                  {"exception-0a", UnmatchedUnit::PathUnavailable},
                                  {"exception-0b", UnmatchedUnit::TargetFailed}});
    std::int64_t first = 0;
    std::int64_t last = 0;
    if (integer_pair(fields, "addresses", 1, 247, first, last)) {
        profile.min_address = static_cast<std::uint8_t>(first);
        profile.max_address = static_cast<std::uint8_t>(last);
    }
    if (fields.failed() || !load_roles(fields, profile.roles)) return false;
    const toml::table* tls = nullptr;
    if (fields.has("tls") && fields.table("tls", tls)) {
        Fields files(*tls, "tls", errors);
        files.string("cert", profile.tls.cert);
        files.string("key", profile.tls.key);
        files.string("ca", profile.tls.ca);
        files.finish();
    }
    if (fields.failed()) return false;
    if (!fields.require("unit", "add at least one [[unit]] table with an id")) return false;
    const bool loaded =
        each_table(fields, "unit", [&](const toml::table& t, const std::string& path) {
            UnitSpec spec;
            if (!load_unit(t, path, profile, errors, spec)) return false;
            profile.units.push_back(std::move(spec));
            return true;
        });
    if (!loaded) return false;
    if (profile.units.empty()) {
        fields.fail("unit", "add at least one [[unit]] table with an id");
        return false;
    }
    fields.finish();
    return !fields.failed();
}

}  // namespace

std::string_view bank_key(BankKind kind) {
    return kBankKeys[static_cast<std::size_t>(kind)];
}

bool is_bit_bank(BankKind kind) {
    return kind == BankKind::Coils || kind == BankKind::DiscreteInputs;
}

Loaded<Profile> parse_profile(std::string_view text, std::string_view source) {
    ProfileErrors errors{std::string(source)};
    toml::table root;
    try {
        root = toml::parse(text, source);
    } catch (const toml::parse_error& e) {
        errors.fail(e.source(), "", "TOML syntax: " + std::string(e.description()));
        return errors.message();
    }
    Profile profile;
    profile.source = std::string(source);
    if (!load_root(root, errors, profile)) return errors.message();
    return profile;
}

Loaded<Profile> read_profile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        return path.string() +
               ": cannot open the profile; check the path (the shipped profiles "
               "are in the profiles/ folder)";
    }
    std::ostringstream text;
    text << in.rdbuf();
    return parse_profile(text.str(), path.string());
}

}  // namespace mblab::device
