#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <string_view>

#include "conformance/declaration_sources.hpp"
#include "conformance/dut.hpp"

// The device-under-test declaration `mblab conform` and `mblab load` take (CTP 6): a DUT file
// (--dut), then the flags given over it, each replacing the file's key of the same name.
namespace mblab::cli {

// What a command's help says of each option; an empty text leaves that option out.
struct DutOptionWords {
    const char* dut;
    const char* unit;
    const char* registers;
    const char* max_read;
    const char* object_messaging;
    const char* alternate_encoding;
};

// Which flags a command line gave, each told to `sources` as the origin of its DUT file key.
class GivenFlags {
  public:
    GivenFlags(const CLI::App& command, conformance::DeclarationSources& sources)
        : command_(command), sources_(sources) {}
    bool operator()(const char* name, std::string_view key);
    // A DUT file replaced the declaration: its keys come from it, the others from the defaults.
    void file(const std::string& path);
    // "flags" joins `dut.declared_by` when any flag was given.
    void mark(conformance::Dut& dut) const;

  private:
    const CLI::App& command_;
    conformance::DeclarationSources& sources_;
    bool any_ = false;
};

class DutOptions {
  public:
    void add_to(CLI::App& command, const DutOptionWords& words);
    // The DUT file, if given, replaces `dut` whole (what it leaves out is a default again), then
    // each flag given replaces its key; "" when declared, else why not.
    std::string declare(conformance::Dut& dut, GivenFlags& given) const;
    // Whether the unit was declared rather than left at its default.
    bool unit_declared(const CLI::App& command) const;
    const std::string& file() const { return file_; }

  private:
    std::string file_;
    int unit_ = 1;
    std::uint32_t registers_ = 0;
    int max_read_ = 125;
    bool object_messaging_ = false;
    bool alternate_encoding_ = false;
    bool has_max_read_ = false;
    bool has_alternate_encoding_ = false;
};

}  // namespace mblab::cli
