#pragma once

#include <string>
#include <vector>

#include "conformance/client_exam_scenarios.hpp"
#include "conformance/client_transcript.hpp"
#include "conformance/provenance.hpp"
#include "conformance/verdict.hpp"

namespace mblab::web {

// The client `mblab conform-client` examined, as its report names it.
struct ClientUnderTest {
    std::string examiner;              // where the examiner listened (its URL)
    std::vector<std::string> command;  // as given, placeholders unfilled; empty under --attach
    conformance::ClientDeclarations declared;
    std::string pki;  // mbaps: the PKI the examiner presented
};

// `mblab conform-client --html`: the run as one self-contained page, as conform's is, but of a
// client: its command and declarations, each scenario's verdict and citation, and what the wire
// carried in it (the client's requests and the examiner's answers, decoys marked).
std::string conform_client_html_report(const conformance::RunResult& result,
                                       const conformance::Provenance& provenance,
                                       const ClientUnderTest& client,
                                       const conformance::ClientTranscripts& transcripts);

}  // namespace mblab::web
