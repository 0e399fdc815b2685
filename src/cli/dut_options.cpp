#include "cli/dut_options.hpp"

#include <fmt/core.h>

#include <utility>

#include "conformance/provenance.hpp"

namespace mblab::cli {

bool GivenFlags::operator()(const char* name, std::string_view key) {
    const bool present = command_.count(name) > 0;
    any_ = any_ || present;
    if (present) sources_.set(key, fmt::format("flag {}", name));
    return present;
}

void GivenFlags::file(const std::string& path) {
    sources_.reset("defaults");
    for (const auto& key : conformance::dut_file_keys(path))
        sources_.set(key, path);
}

void GivenFlags::mark(conformance::Dut& dut) const {
    if (!any_) return;
    dut.declared_by = dut.declared_by == "defaults" ? "flags" : dut.declared_by + " and flags";
}

void DutOptions::add_to(CLI::App& command, const DutOptionWords& words) {
    command.add_option("--dut", file_, words.dut)->check(CLI::ExistingFile);
    command.add_option("--unit", unit_, words.unit)->check(CLI::Range(0, 255));
    command.add_option("--registers", registers_, words.registers)->check(CLI::Range(1, 65536));
    has_max_read_ = *words.max_read != '\0';
    if (has_max_read_)
        command.add_option("--max-read", max_read_, words.max_read)->check(CLI::Range(1, 125));
    command.add_flag("--object-messaging", object_messaging_, words.object_messaging);
    has_alternate_encoding_ = *words.alternate_encoding != '\0';
    if (has_alternate_encoding_)
        command.add_flag("--alternate-encoding", alternate_encoding_, words.alternate_encoding);
}

std::string DutOptions::declare(conformance::Dut& dut, GivenFlags& given) const {
    if (!file_.empty()) {
        auto loaded = conformance::load_dut_file(file_);
        if (!loaded) return loaded.error();
        dut = std::move(loaded.value());
        given.file(file_);
    }
    if (given("--unit", "unit")) dut.unit = static_cast<std::uint8_t>(unit_);
    if (given("--registers", "registers")) dut.registers = registers_;
    if (has_max_read_ && given("--max-read", "max_read"))
        dut.max_read = static_cast<std::uint16_t>(max_read_);
    // A flag given as --object-messaging=false declares false.
    if (given("--object-messaging", "object_messaging")) dut.object_messaging = object_messaging_;
    if (has_alternate_encoding_ && given("--alternate-encoding", "alternate_encoding"))
        dut.alternate_encoding = alternate_encoding_;
    return {};
}

bool DutOptions::unit_declared(const CLI::App& command) const {
    return !file_.empty() || command.count("--unit") > 0;
}

}  // namespace mblab::cli
