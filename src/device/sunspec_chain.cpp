#include "device/sunspec_chain.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <set>

namespace mblab::device {

namespace {

constexpr std::uint32_t kAddressSpace = 65536;
constexpr std::uint16_t kEndModel = 0xFFFF;

bool is_signed(SunSpecType type) {
    return type == SunSpecType::Int16 || type == SunSpecType::Int32 || type == SunSpecType::Int64 ||
           type == SunSpecType::Sunssf;
}

// How the dashboard and the REST API show the point's registers (typed_points.cpp).
ValueType shown_as(const SunSpecPoint& point) {
    switch (point.type) {
        case SunSpecType::String:
            return ValueType::String;
        case SunSpecType::Int16:
        case SunSpecType::Sunssf:
            return ValueType::I16;
        case SunSpecType::Float32:
            return ValueType::F32;
        default:
            return point.size == 2 && point.type != SunSpecType::Int32 ? ValueType::U32
                                                                       : ValueType::U16;
    }
}

// The raw values an integer type of `size` registers holds: from the first, below the second.
std::pair<double, double> raw_bounds(const SunSpecPoint& point) {
    const double bits = 16.0 * std::min<std::uint16_t>(point.size, 4);
    if (is_signed(point.type)) return {-std::exp2(bits - 1), std::exp2(bits - 1)};
    return {0, std::exp2(bits)};
}

class Builder {
  public:
    Builder(const SunSpecChainSpec& spec, const std::map<std::uint16_t, SunSpecModel>& defs)
        : spec_(spec), defs_(defs), at_(spec.base) {}

    Loaded<SunSpecChain> build() {
        if (!place("SunS", {0x5375, 0x6E53}, Access::ReadOnly, ValueType::String)) return error_;
        for (const SunSpecModelValues& model : spec_.models) {
            if (!lay_model(model)) return error_;
        }
        if (spec_.end_model && !place("end", {kEndModel, 0}, Access::ReadOnly)) return error_;
        return std::move(chain_);
    }

  private:
    struct ScaleFactor {
        std::optional<int> value;  // none when the profile gives it none
        std::uint32_t address = 0;
    };
    using Scales = std::map<std::string, ScaleFactor>;

    bool fail(std::string message) {
        error_ = "model " + std::to_string(model_) + ": " + std::move(message);
        return false;
    }

    bool place(std::string name, std::vector<std::uint16_t> words, Access access,
               ValueType type = ValueType::U16) {
        const auto count = static_cast<std::uint32_t>(words.size());
        if (at_ + count > kAddressSpace) {
            return fail(name + " would lie past register 65535; start the chain lower");
        }
        RangeSpec range;
        range.start = at_;
        range.count = count;
        range.access = access;
        range.values = std::move(words);
        range.type = type;
        range.name = std::move(name);
        chain_.ranges.push_back(std::move(range));
        at_ += count;
        return true;
    }

    bool lay_model(const SunSpecModelValues& model) {
        model_ = model.id;
        const auto def = defs_.find(model.id);
        if (def == defs_.end())
            return fail("no definition (model_" + std::to_string(model.id) +
                        ".json in the SunSpec models folder)");
        values_ = &model;
        chain_.points.emplace_back();
        used_.clear();
        limited_.clear();
        const std::uint32_t start = at_;
        const std::size_t first = chain_.ranges.size();
        if (!lay_group(def->second.group, "", {})) return false;
        if (model.extra_registers > 0 &&
            !place(std::to_string(model.id) + ".extra",
                   std::vector<std::uint16_t>(model.extra_registers, 0), Access::ReadOnly)) {
            return false;
        }
        // L counts what follows ID and L (Information Model Specification, "Model length").
        chain_.ranges[first + 1].values[0] = static_cast<std::uint16_t>(at_ - start - 2);
        for (const auto& [name, value] : model.values) {
            if (used_.count(name) == 0) return fail("no point \"" + name + "\" to give a value");
        }
        for (const auto& [name, limit] : model.limits) {
            if (limited_.count(name) == 0) return fail("no RW point \"" + name + "\" to limit");
        }
        return true;
    }

    bool lay_group(const SunSpecGroup& group, const std::string& prefix, Scales scales) {
        // A point's offset counts from its group instance's start, in the top group the ID.
        const std::uint32_t start = at_;
        for (const SunSpecPoint& point : group.points) {
            if (point.type != SunSpecType::Sunssf) continue;
            const auto found = values_->values.find(prefix + point.name);
            const double* raw =
                found == values_->values.end() ? nullptr : std::get_if<double>(&found->second);
            scales[point.name] = {raw ? std::optional<int>(static_cast<int>(*raw)) : std::nullopt,
                                  start + point.offset};
        }
        for (const SunSpecPoint& point : group.points) {
            if (!lay_point(point, prefix, scales)) return false;
        }
        for (const SunSpecGroup& child : group.groups) {
            std::uint32_t times = child.fixed_count;
            if (!child.count_point.empty()) {
                const auto found = values_->values.find(prefix + child.count_point);
                const double* count =
                    found == values_->values.end() ? nullptr : std::get_if<double>(&found->second);
                times = count ? static_cast<std::uint32_t>(*count) : 0;
            }
            for (std::uint32_t i = 1; i <= times; ++i) {
                const std::string inner = prefix + child.name + "[" + std::to_string(i) + "].";
                if (!lay_group(child, inner, scales)) return false;
            }
        }
        return true;
    }

    std::optional<int> scale_of(const SunSpecPoint& point, const Scales& scales) const {
        if (point.fixed_sf) return point.fixed_sf;
        if (point.sf.empty()) return 0;
        const auto found = scales.find(point.sf);
        return found == scales.end() ? std::nullopt : found->second.value;
    }

    void note_placed(const SunSpecPoint& point, const std::string& path, std::uint32_t start,
                     bool given, const Scales& scales) {
        SunSpecPlacedPoint placed{start,    point.type,   point.size, scale_of(point, scales),
                                  point.sf, std::nullopt, given};
        if (const auto found = scales.find(point.sf);
            !point.fixed_sf && !point.sf.empty() && found != scales.end()) {
            placed.sf_address = found->second.address;
        }
        chain_.points.back().emplace(path, std::move(placed));
    }

    bool lay_point(const SunSpecPoint& point, const std::string& prefix, const Scales& scales) {
        const std::string path = prefix + point.name;
        const auto given = values_->values.find(path);
        if (given != values_->values.end()) used_.insert(path);
        std::vector<std::uint16_t> words = not_implemented_words(point);
        if (point.name == "ID" && prefix.empty()) {
            if (given != values_->values.end()) return fail("ID is the model's id; give no value");
            words = {model_};
        } else if (point.name == "L" && prefix.empty()) {
            if (given != values_->values.end()) return fail("L is counted; give no value");
            words = {0};
        } else if (given != values_->values.end() && point.type != SunSpecType::Pad) {
            if (!encode(point, path, given->second, scales, words)) return false;
        }
        const bool writable = point.writable || spec_.read_only_writable;
        const std::uint32_t start = at_;
        note_placed(point, path, start, given != values_->values.end(), scales);
        if (!place(std::to_string(model_) + "." + path, std::move(words),
                   writable ? Access::ReadWrite : Access::ReadOnly, shown_as(point))) {
            return false;
        }
        return add_rule(point, path, start, scales);
    }

    bool encode(const SunSpecPoint& point, const std::string& path, const SunSpecValue& value,
                const Scales& scales, std::vector<std::uint16_t>& words) {
        if (point.type == SunSpecType::String) {
            const std::string* text = std::get_if<std::string>(&value);
            if (!text || text->size() > 2u * point.size) {
                return fail(path + " takes text of up to " + std::to_string(2 * point.size) +
                            " characters");
            }
            for (std::size_t i = 0; i < text->size(); ++i) {
                const auto byte = static_cast<std::uint8_t>((*text)[i]);
                words[i / 2] = static_cast<std::uint16_t>(words[i / 2] | byte << (i % 2 ? 0 : 8));
            }
            return true;
        }
        double number = 0;
        if (const std::string* text = std::get_if<std::string>(&value)) {
            const auto symbol =
                std::find_if(point.symbols.begin(), point.symbols.end(),
                             [&](const SunSpecSymbol& s) { return s.name == *text; });
            if (symbol == point.symbols.end()) {
                return fail(path + " has no symbol \"" + *text + "\"");
            }
            number = static_cast<double>(symbol->value);
        } else {
            number = std::get<double>(value);
            const auto scale = scale_of(point, scales);
            if (!scale) return fail(path + " needs a value for its scale factor " + point.sf);
            number = std::round(number / std::pow(10.0, *scale));
        }
        if (point.type == SunSpecType::Float32) {
            words = sunspec_words(std::bit_cast<std::uint32_t>(static_cast<float>(number)), 2);
            return true;
        }
        if (point.type == SunSpecType::Float64) {
            words = sunspec_words(std::bit_cast<std::uint64_t>(number), 4);
            return true;
        }
        const auto [low, high] = raw_bounds(point);
        if (number < low || number >= high) {
            return fail(path + " = " + std::to_string(number) + " (raw) does not fit its type " +
                        std::string(sunspec_type_name(point.type)));
        }
        words =
            sunspec_words(number < 0 ? static_cast<std::uint64_t>(static_cast<std::int64_t>(number))
                                     : static_cast<std::uint64_t>(number),
                          point.size);
        return true;
    }

    bool add_rule(const SunSpecPoint& point, const std::string& path, std::uint32_t start,
                  const Scales& scales) {
        PointRule rule;
        rule.start = start;
        rule.count = point.size;
        rule.is_signed = is_signed(point.type);
        rule.whole = spec_.split_refused && point.size > 1;
        rule.applied = spec_.writes_applied;
        if (point.writable && is_sunspec_enum(point.type)) {
            for (const SunSpecSymbol& symbol : point.symbols)
                rule.allowed.push_back(symbol.value);
        }
        if (const auto limit = values_->limits.find(path); limit != values_->limits.end()) {
            if (!point.writable) return fail(path + " is not RW; only RW points take limits");
            limited_.insert(path);
            const auto scale = scale_of(point, scales);
            if (!scale) return fail(path + " needs a value for its scale factor " + point.sf);
            rule.min = std::llround(limit->second.first / std::pow(10.0, *scale));
            rule.max = std::llround(limit->second.second / std::pow(10.0, *scale));
        }
        const bool checked = !rule.allowed.empty() || rule.min || rule.max;
        if (rule.whole || (point.writable && (checked || !rule.applied))) {
            chain_.rules.push_back(std::move(rule));
        }
        return true;
    }

    const SunSpecChainSpec& spec_;
    const std::map<std::uint16_t, SunSpecModel>& defs_;
    std::uint32_t at_;
    std::uint16_t model_ = 0;
    const SunSpecModelValues* values_ = nullptr;
    std::set<std::string> used_;
    std::set<std::string> limited_;
    SunSpecChain chain_;
    std::string error_;
};

}  // namespace

Loaded<SunSpecChain> build_sunspec_chain(const SunSpecChainSpec& spec,
                                         const std::map<std::uint16_t, SunSpecModel>& definitions) {
    if (spec.models.empty() || spec.models.front().id != 1) {
        return std::string("the chain starts with the common model 1");
    }
    return Builder(spec, definitions).build();
}

}  // namespace mblab::device
