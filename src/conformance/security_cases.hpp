#pragma once

#include <vector>

#include "conformance/procedures.hpp"

// The security suite's procedures (catalogue/security.toml, docs/security.md): Modbus/TCP
// Security ([SEC], MB-TCP-Security v36 requirement numbers) judged from the client's side. Each
// opens TLS sessions of its own to the device's mbaps:// port, with the certificate the case is
// about, and judges what the device did with it: a handshake refused or completed, a request
// answered, refused with exception 01, or left unanswered. A device that cannot be reached, or a
// certificate this side cannot present, gives NOT RUN; a declaration missing gives N/A.
namespace mblab::conformance {

std::vector<ProcedureInfo> security_procedures();

}  // namespace mblab::conformance
