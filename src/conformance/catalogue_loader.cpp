#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <set>

#include "conformance/catalogue.hpp"
#include "conformance/procedures.hpp"
#include "conformance/toml_reader.hpp"

namespace mblab::conformance {

namespace {

const std::vector<std::string_view> kSuiteKeys = {"name", "title", "source"};
const std::vector<std::string_view> kStepKeys = {"request",    "expect",       "accept",
                                                 "silence_ms", "accept_close", "accept_silence",
                                                 "timeout_ms", "split",        "split_delay_ms"};
const std::vector<std::string_view> kCaseOnlyKeys = {
    "id",       "source",     "title",    "procedure", "params",           "step",
    "requires", "depends_on", "pipeline", "isolated",  "unsupported_is_na"};
const std::vector<std::string_view> kAcceptKeys = {"expect", "remark"};

class SuiteLoader {
  public:
    explicit SuiteLoader(const std::string& file) : reader_(file) {}

    protocol::Result<Suite, std::string> load(std::optional<toml::table> root) {
        Suite suite;
        suite.file = reader_.file();
        if (root && read_suite(*root, suite)) return suite;
        return reader_.error();
    }

    TomlReader& reader() { return reader_; }

  private:
    bool read_suite(const toml::table& root, Suite& suite) {
        if (!reader_.only_keys(root, {"suite", "case"})) return false;
        const toml::table* header = root["suite"].as_table();
        if (header == nullptr) {
            return reader_.fail_line(1, "a suite starts with a [suite] table giving its name");
        }
        if (!reader_.only_keys(*header, kSuiteKeys) || !reader_.get(*header, "name", suite.name) ||
            !reader_.get(*header, "title", suite.title) ||
            !reader_.get(*header, "source", suite.source)) {
            return false;
        }
        if (suite.name.empty()) return reader_.fail(header, "[suite] needs a name");
        const toml::array* cases = root["case"].as_array();
        if (cases == nullptr || cases->empty()) {
            return reader_.fail(header, "the suite has no [[case]] tables");
        }
        std::set<std::string> ids;
        for (const toml::node& node : *cases) {
            const toml::table* table = node.as_table();
            if (table == nullptr) return reader_.fail(&node, "'case' must be [[case]] tables");
            Case c;
            if (!read_case(*table, c)) return false;
            if (!ids.insert(c.id).second) {
                return reader_.fail(table, fmt::format("case id '{}' is used twice", c.id));
            }
            for (const auto& dependency : c.depends_on) {
                if (!ids.count(dependency) || dependency == c.id) {
                    return reader_.fail(table, fmt::format("depends_on names '{}', which is not "
                                                           "an earlier case of this suite",
                                                           dependency));
                }
            }
            suite.cases.push_back(std::move(c));
        }
        return true;
    }

    bool read_case(const toml::table& table, Case& c) {
        c.line = table.source().begin.line;
        std::vector<std::string_view> keys = kCaseOnlyKeys;
        keys.insert(keys.end(), kStepKeys.begin(), kStepKeys.end());
        if (!reader_.only_keys(table, keys) || !reader_.get(table, "id", c.id) ||
            !reader_.get(table, "source", c.source) || !reader_.get(table, "title", c.title) ||
            !reader_.get(table, "procedure", c.procedure) ||
            !reader_.get(table, "pipeline", c.pipeline) ||
            !reader_.get(table, "isolated", c.isolated) ||
            !reader_.get(table, "unsupported_is_na", c.unsupported_is_na)) {
            return false;
        }
        for (auto [key, value] :
             {std::pair{"id", &c.id}, {"source", &c.source}, {"title", &c.title}}) {
            if (value->empty()) {
                return reader_.fail(&table, fmt::format("a case needs '{}'", key));
            }
        }
        auto where = [&](const std::string& reason) {
            return reader_.fail(&table, fmt::format("case {}: {}", c.id, reason));
        };
        if (!read_requirements(table, c) || !read_dependencies(table, c)) return false;

        const bool has_step_keys = std::any_of(kStepKeys.begin(), kStepKeys.end(),
                                               [&](auto key) { return table.contains(key); });
        const bool has_steps = table.contains("step");
        if (!c.procedure.empty()) {
            if (has_step_keys || has_steps) {
                return where("a procedure case has no request, expect or steps");
            }
            return read_procedure(table, c);
        }
        if (table.contains("params")) return where("'params' belongs to procedure cases");
        if (has_step_keys == has_steps) {
            return where("give either request/expect, [[case.step]] tables, or a procedure");
        }
        if (has_step_keys) {
            Step step;
            if (!read_step(table, c, step)) return false;
            c.steps.push_back(std::move(step));
            return true;
        }
        const toml::array* steps = table["step"].as_array();
        if (steps == nullptr || steps->empty()) return where("'step' must be [[case.step]] tables");
        for (const toml::node& node : *steps) {
            const toml::table* step_table = node.as_table();
            if (step_table == nullptr) return where("'step' must be [[case.step]] tables");
            if (!reader_.only_keys(*step_table, kStepKeys)) return false;
            Step step;
            if (!read_step(*step_table, c, step)) return false;
            c.steps.push_back(std::move(step));
        }
        return true;
    }

    bool read_requirements(const toml::table& table, Case& c) {
        std::vector<std::pair<std::string, const toml::node*>> texts;
        if (!reader_.get_strings(table, "requires", texts)) return false;
        for (const auto& [text, node] : texts) {
            auto requirement = parse_requirement(text);
            if (!requirement) return reader_.fail(node, requirement.error());
            c.requirements.push_back(std::move(requirement.value()));
        }
        return true;
    }

    bool read_dependencies(const toml::table& table, Case& c) {
        std::vector<std::pair<std::string, const toml::node*>> texts;
        if (!reader_.get_strings(table, "depends_on", texts)) return false;
        for (auto& entry : texts)
            c.depends_on.push_back(std::move(entry.first));
        return true;
    }

    bool read_procedure(const toml::table& table, Case& c) {
        const ProcedureInfo* info = find_procedure(c.procedure);
        const toml::node* node = table.get("procedure");
        if (info == nullptr) {
            std::string known;
            for (const auto& p : procedures())
                known += (known.empty() ? "" : ", ") + std::string(p.name);
            return reader_.fail(
                node, fmt::format("unknown procedure '{}' (known: {})", c.procedure, known));
        }
        const toml::node* params_node = table.get("params");
        if (params_node == nullptr) return true;
        const toml::table* params = params_node->as_table();
        if (params == nullptr) return reader_.fail(params_node, "'params' must be a table");
        std::vector<std::string_view> names;
        for (const auto& [name, value] : info->params)
            names.push_back(name);
        if (!reader_.only_keys(*params, names)) return false;
        for (auto name : names) {
            std::int64_t value = 0;
            if (!params->contains(name)) continue;
            if (!reader_.get(*params, name, value, 0, 1'000'000)) return false;
            c.params[std::string(name)] = value;
        }
        return true;
    }

    // Parses one pattern string; requests must be whole bytes once facts are put in.
    bool read_pattern(const std::string& text, const toml::node* node, bool is_request,
                      Pattern& out) {
        auto parsed = Pattern::parse(text);
        std::string_view what = is_request ? "request" : "expected pattern";
        if (!parsed) {
            return reader_.fail(node, fmt::format("{}: column {}: {}", what, parsed.error().column,
                                                  parsed.error().reason));
        }
        for (const auto& name : parsed->facts()) {
            if (!is_known_fact(name)) {
                return reader_.fail(node,
                                    fmt::format("{}: unknown placeholder {{{}}}", what, name));
            }
        }
        if (is_request && !parsed->is_concrete()) {
            return reader_.fail(node,
                                "request: XX and ... are for expected patterns; a request "
                                "is exact bytes");
        }
        out = std::move(parsed.value());
        return true;
    }

    bool read_millis(const toml::table& table, std::string_view key,
                     std::optional<std::chrono::milliseconds>& out) {
        std::int64_t value = -1;
        if (!reader_.get(table, key, value, 0, 60'000)) return false;
        if (value >= 0) out = std::chrono::milliseconds(value);
        return true;
    }

    bool read_step(const toml::table& table, const Case& c, Step& step) {
        step.line = table.source().begin.line;
        auto fail = [&](const toml::node* at, const std::string& reason) {
            return reader_.fail(at, fmt::format("case {}: {}", c.id, reason));
        };
        std::string request;
        if (!reader_.get(table, "request", request)) return false;
        if (request.empty()) return fail(&table, "a step needs a request");
        if (!read_pattern(request, table.get("request"), true, step.request)) return false;

        std::string expect;
        if (!reader_.get(table, "expect", expect)) return false;
        if (!expect.empty()) {
            Alternative preferred;
            if (!read_pattern(expect, table.get("expect"), false, preferred.pattern)) return false;
            step.expect.push_back(std::move(preferred));
        }
        if (!read_accept(table, c, step)) return false;
        if (!read_millis(table, "silence_ms", step.silence) ||
            !read_millis(table, "timeout_ms", step.timeout)) {
            return false;
        }
        if (!read_remark(table, "accept_close", step.accept_close) ||
            !read_remark(table, "accept_silence", step.accept_silence)) {
            return false;
        }
        if (step.expect.empty() == !step.silence.has_value()) {
            return fail(&table, "a step gives either 'expect' or 'silence_ms'");
        }
        for (const char* key : {"accept", "accept_silence"}) {
            if (step.silence && table.contains(key)) {
                return fail(table.get(key),
                            fmt::format("'{}' goes with 'expect', not 'silence_ms'", key));
            }
        }
        std::optional<std::chrono::milliseconds> delay;
        if (!read_millis(table, "split_delay_ms", delay)) return false;
        if (delay) step.split_delay = *delay;
        return read_split(table, c, step);
    }

    bool read_remark(const toml::table& table, std::string_view key,
                     std::optional<std::string>& out) {
        std::string remark;
        if (!reader_.get(table, key, remark)) return false;
        if (table.contains(key)) out = std::move(remark);
        return true;
    }

    bool read_accept(const toml::table& table, const Case& c, Step& step) {
        const toml::node* node = table.get("accept");
        if (node == nullptr) return true;
        const toml::array* list = node->as_array();
        if (list == nullptr) {
            return reader_.fail(node, fmt::format("case {}: 'accept' must be an array of "
                                                  "{{ expect = ..., remark = ... }}",
                                                  c.id));
        }
        for (const toml::node& item : *list) {
            const toml::table* entry = item.as_table();
            if (entry == nullptr) {
                return reader_.fail(&item,
                                    fmt::format("case {}: each 'accept' entry is a table", c.id));
            }
            Alternative alternative;
            std::string expect;
            if (!reader_.only_keys(*entry, kAcceptKeys) || !reader_.get(*entry, "expect", expect) ||
                !reader_.get(*entry, "remark", alternative.remark)) {
                return false;
            }
            if (expect.empty()) {
                return reader_.fail(entry,
                                    fmt::format("case {}: an 'accept' entry needs 'expect'", c.id));
            }
            if (!read_pattern(expect, entry->get("expect"), false, alternative.pattern)) {
                return false;
            }
            step.expect.push_back(std::move(alternative));
        }
        if (step.expect.size() == list->size()) {
            return reader_.fail(node, fmt::format("case {}: 'accept' adds to an 'expect'", c.id));
        }
        return true;
    }

    bool read_split(const toml::table& table, const Case& c, Step& step) {
        const toml::node* node = table.get("split");
        if (node == nullptr) return true;
        const toml::array* list = node->as_array();
        auto fail = [&] {
            return reader_.fail(node, fmt::format("case {}: 'split' is a rising list of byte "
                                                  "offsets inside the request",
                                                  c.id));
        };
        if (list == nullptr || list->empty()) return fail();
        const std::size_t size = render_size(step.request);
        std::size_t previous = 0;
        for (const toml::node& item : *list) {
            const auto* value = item.as_integer();
            if (value == nullptr || value->get() <= static_cast<std::int64_t>(previous) ||
                value->get() >= static_cast<std::int64_t>(size)) {
                return fail();
            }
            previous = static_cast<std::size_t>(value->get());
            step.split.push_back(previous);
        }
        return true;
    }

    // Size of a request in bytes; facts are one byte for {unit} and two for the others, except
    // the computed ones, whose size is only known when the DUT is.
    static std::size_t render_size(const Pattern& pattern) {
        std::size_t size = 0;
        for (const auto& token : pattern.tokens()) {
            if (token.kind == PatternToken::Kind::Length) {
                size += 2;
            } else if (token.kind == PatternToken::Kind::Fact) {
                size += token.name == "unit" ? 1 : 2;
            } else {
                size += 1;
            }
        }
        return size;
    }

    TomlReader reader_;
};

}  // namespace

protocol::Result<Suite, std::string> load_suite_file(const std::string& path) {
    SuiteLoader loader(path);
    return loader.load(loader.reader().parse_file());
}

protocol::Result<Suite, std::string> load_suite_text(std::string_view text,
                                                     const std::string& file_name) {
    SuiteLoader loader(file_name);
    return loader.load(loader.reader().parse_text(text));
}

std::vector<std::string> shipped_suite_files(const std::string& directory) {
    std::vector<std::string> files;
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator(directory, error)) {
        if (entry.is_regular_file() && entry.path().extension() == ".toml") {
            files.push_back(entry.path().string());
        }
    }
    auto is_policy = [](const std::string& path) {
        return std::filesystem::path(path).filename().string().rfind("policy", 0) == 0;
    };
    std::sort(files.begin(), files.end(), [&](const std::string& a, const std::string& b) {
        if (is_policy(a) != is_policy(b)) return is_policy(a);
        return a < b;
    });
    return files;
}

}  // namespace mblab::conformance
