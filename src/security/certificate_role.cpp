#include "security/certificate_role.hpp"

#include <openssl/asn1.h>
#include <openssl/objects.h>
#include <openssl/x509.h>

#include <algorithm>
#include <string>
#include <vector>

#include "security/openssl_handles.hpp"
#include "security/role_text.hpp"
#include "security/tls_context.hpp"

namespace mblab::security {

namespace {

RoleReading refused(std::string reason) {
    return RoleReading{RoleReading::Kind::Refused, {}, std::move(reason)};
}

// The role's type as a reader of [SEC] would name it, for the refusal line.
std::string type_name(int type) {
    switch (type) {
        case V_ASN1_IA5STRING:
            return "an IA5String";
        case V_ASN1_PRINTABLESTRING:
            return "a PrintableString";
        case V_ASN1_VISIBLESTRING:
            return "a VisibleString";
        case V_ASN1_BMPSTRING:
            return "a BMPString";
        case V_ASN1_UNIVERSALSTRING:
            return "a UniversalString";
        case V_ASN1_T61STRING:
            return "a TeletexString";
        case V_ASN1_OCTET_STRING:
            return "an OCTET STRING";
        case V_ASN1_BIT_STRING:
            return "a BIT STRING";
        case V_ASN1_INTEGER:
            return "an INTEGER";
        case V_ASN1_NULL:
            return "a NULL";
        case V_ASN1_BOOLEAN:
            return "a BOOLEAN";
        case V_ASN1_OBJECT:
            return "an OBJECT IDENTIFIER";
        case V_ASN1_SEQUENCE:
            return "a SEQUENCE";
        case V_ASN1_SET:
            return "a SET";
        default:
            break;
    }
    // ASN1_tag2str knows the universal tags 0..30; anything else (context-specific, application,
    // private or a high tag) OpenSSL keeps as V_ASN1_OTHER, with no name to give.
    if (type < 0 || type > 30) return "not a universal ASN.1 type";
    return std::string("a ") + ASN1_tag2str(type);
}

RoleReading read_extension(X509_EXTENSION* extension) {
    const ASN1_OCTET_STRING* value = X509_EXTENSION_get_data(extension);
    if (value == nullptr) return refused("the role extension has no value");
    const unsigned char* start = ASN1_STRING_get0_data(value);
    const int length = ASN1_STRING_length(value);
    if (length <= 0) return refused("the role extension's value is empty");
    const unsigned char* cursor = start;
    Asn1TypePtr decoded(d2i_ASN1_TYPE(nullptr, &cursor, length));
    if (!decoded) return refused("the role extension's value is not DER");
    if (cursor != start + length) {
        return refused("the role extension has bytes after its value");
    }
    // OpenSSL also takes BER (long-form lengths, constructed strings); DER has one encoding per
    // value, so a value that does not encode back to the same bytes is not DER.
    if (i2d_ASN1_TYPE(decoded.get(), nullptr) != length) {
        return refused("the role extension's value is not DER");
    }
    std::vector<unsigned char> again(static_cast<std::size_t>(length));
    unsigned char* out = again.data();
    if (i2d_ASN1_TYPE(decoded.get(), &out) != length ||
        !std::equal(again.begin(), again.end(), start)) {
        return refused("the role extension's value is not DER");
    }
    const int type = ASN1_TYPE_get(decoded.get());
    if (type != V_ASN1_UTF8STRING) {
        return refused("the role is " + type_name(type) + ", not a UTF8String");
    }
    const ASN1_STRING* text = decoded->value.utf8string;
    const int text_length = ASN1_STRING_length(text);
    if (text_length <= 0) return refused("the role is an empty UTF8String");
    const unsigned char* bytes = ASN1_STRING_get0_data(text);
    std::string role(reinterpret_cast<const char*>(bytes), static_cast<std::size_t>(text_length));
    if (const char* problem = role_text_problem(role))
        return refused("the role " + std::string(problem));
    return RoleReading{RoleReading::Kind::Role, std::move(role), {}};
}

}  // namespace

RoleReading read_role(const X509* certificate) {
    static const std::string oid_text(kRoleOid);
    // no_name = 1: the text is a dotted OID, never looked up as a short or long name.
    Asn1ObjectPtr oid(OBJ_txt2obj(oid_text.c_str(), 1));
    if (!oid) return refused("cannot make the role OID: " + take_openssl_error("no reason"));
    const int first = X509_get_ext_by_OBJ(certificate, oid.get(), -1);
    if (first < 0) return RoleReading{};
    if (X509_get_ext_by_OBJ(certificate, oid.get(), first) >= 0) {
        return refused("more than one role extension");
    }
    return read_extension(X509_get_ext(certificate, first));
}

RoleReading read_role_der(std::span<const std::uint8_t> der) {
    if (der.empty()) return refused("the certificate is empty");
    // d2i takes a long; a certificate larger than that is not one anybody sends.
    if (der.size() > 1U << 20U) return refused("the certificate is larger than 1 MiB");
    const unsigned char* cursor = der.data();
    X509Ptr certificate(d2i_X509(nullptr, &cursor, static_cast<long>(der.size())));
    if (!certificate) {
        return refused("the certificate is not DER: " + take_openssl_error("no reason"));
    }
    if (cursor != der.data() + der.size()) return refused("bytes after the certificate");
    return read_role(certificate.get());
}

}  // namespace mblab::security
