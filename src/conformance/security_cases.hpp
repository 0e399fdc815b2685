#pragma once

#include "conformance/verdict.hpp"

// The security suite's procedures (catalogue/security.toml, docs/security.md): Modbus/TCP
// Security ([SEC], MB-TCP-Security v36 requirement numbers) judged from the client's side. Each
// opens TLS sessions of its own to the device's mbaps:// port, with the certificate the case is
// about, and judges what the device did with it: a handshake refused or completed, a request
// answered, refused with exception 01, or left unanswered. A device that cannot be reached, or a
// certificate this side cannot present, gives NOT RUN; a declaration missing gives N/A.
namespace mblab::conformance {

class Session;
struct Case;

Outcome run_tls_handshake(Session& session, const Case& c);
Outcome run_tls10_refused(Session& session, const Case& c);
Outcome run_tls11_refused(Session& session, const Case& c);
Outcome run_no_certificate_refused(Session& session, const Case& c);
Outcome run_expired_certificate_refused(Session& session, const Case& c);
Outcome run_foreign_ca_certificate_refused(Session& session, const Case& c);
Outcome run_self_signed_certificate_refused(Session& session, const Case& c);
Outcome run_null_role_denied(Session& session, const Case& c);
Outcome run_read_only_role(Session& session, const Case& c);
Outcome run_write_role(Session& session, const Case& c);
Outcome run_tls_renegotiation(Session& session, const Case& c);
Outcome run_tls_close_notify(Session& session, const Case& c);

}  // namespace mblab::conformance
