#include "conformance/references.hpp"

#include <fmt/format.h>

#include <array>

namespace mblab::conformance {
namespace {

constexpr std::array kReferences{
    Reference{"APP", "Modbus Application Protocol Specification V1.1b3",
              "https://modbus.org/docs/Modbus_Application_Protocol_V1_1b3.pdf"},
    Reference{"TCPG", "Modbus Messaging on TCP/IP Implementation Guide V1.0b",
              "https://modbus.org/docs/Modbus_Messaging_Implementation_Guide_V1_0b.pdf"},
    Reference{"SER", "Modbus over Serial Line Specification and Implementation Guide V1.02",
              "https://modbus.org/docs/Modbus_over_serial_line_V1_02.pdf"},
    Reference{"CTP",
              "Conformance Test Policy for the Modbus/TCP Conformance Test Laboratory, version "
              "2.1 (University of Michigan)",
              "https://modbus.org"},
    Reference{"SEC", "Modbus/TCP Security Protocol Specification MB-TCP-Security v36",
              "https://modbus.org/docs/MB-TCP-Security-v36_2021-07-30.pdf"},
    Reference{"INSTR", "RS-485 instrument communication manual, 5.7 Self-diagnostic Function",
              "https://www.clrwtr.com"},
    Reference{"EPS", "Schneider Electric EcoStruxure Panel Server User Guide DOCA0172EN-14",
              "https://www.se.com/ww/en/download/document/DOCA0172EN/"},
    Reference{"MVI56E", "ProSoft Technology MVI56E-MCM/MCMXT User Manual (June 18, 2014)",
              "https://www.prosoft-technology.com"},
    Reference{"SSIM", "SunSpec Device Information Model Specification, version 1.1",
              "https://sunspec.org/specifications/"},
    Reference{"SSMB", "SunSpec Modbus Specification, version 1.0",
              "https://sunspec.org/specifications/"},
    Reference{"RFC", "IETF Request for Comments", "https://www.rfc-editor.org"},
    Reference{"CVE", "Common Vulnerabilities and Exposures record", "https://www.cve.org"},
};

std::string_view trim(std::string_view text) {
    while (!text.empty() && text.front() == ' ')
        text.remove_prefix(1);
    while (!text.empty() && text.back() == ' ')
        text.remove_suffix(1);
    return text;
}

// The first word of an RFC citation ("RFC 5246 7.2.1") is the number, the second the section.
std::string rfc_url(std::string_view base, std::string_view rest) {
    const auto number = rest.substr(0, rest.find(' '));
    std::string url = fmt::format("{}/rfc/rfc{}", base, number);
    if (number.size() < rest.size()) {
        auto section = rest.substr(number.size() + 1);
        section = section.substr(0, section.find_first_of(" ,"));
        if (!section.empty() && section.front() >= '0' && section.front() <= '9')
            url += fmt::format("#section-{}", section);
    }
    return url;
}

}  // namespace

std::span<const Reference> references() {
    return kReferences;
}

const Reference* cited_reference(std::string_view citation) {
    citation = trim(citation);
    for (const auto& reference : kReferences) {
        if (!citation.starts_with(reference.tag)) continue;
        const auto after = citation.substr(reference.tag.size());
        // "CVE-2019-14462" joins its tag with a hyphen; every other tag stands alone.
        if (after.empty() || after.front() == ' ' || (reference.tag == "CVE" && after[0] == '-'))
            return &reference;
    }
    return nullptr;
}

std::vector<Citation> citations(std::string_view source) {
    std::vector<Citation> out;
    while (!source.empty()) {
        const auto end = source.find("; ");
        const auto part = trim(source.substr(0, end));
        source = end == std::string_view::npos ? std::string_view() : source.substr(end + 2);
        if (part.empty()) continue;
        Citation citation{std::string(part), std::string(part), {}};
        if (const Reference* reference = cited_reference(part)) {
            const auto rest = trim(part.substr(reference->tag.size()));
            if (reference->tag == "RFC") {
                citation.title = fmt::format("RFC {}", rest);
                citation.url = rfc_url(reference->url, rest);
            } else if (reference->tag == "CVE") {
                citation.url = fmt::format("{}/CVERecord?id={}", reference->url, part);
            } else {
                citation.title = rest.empty() ? std::string(reference->title)
                                              : fmt::format("{}, {}", reference->title, rest);
                citation.url = std::string(reference->url);
            }
        }
        out.push_back(std::move(citation));
    }
    return out;
}

std::string cited_in_full(std::string_view source) {
    std::string out;
    for (const auto& citation : citations(source))
        out += (out.empty() ? "" : "; ") + citation.title;
    return out;
}

}  // namespace mblab::conformance
