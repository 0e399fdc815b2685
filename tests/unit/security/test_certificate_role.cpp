#include <gtest/gtest.h>
#include <openssl/asn1.h>
#include <openssl/evp.h>
#include <openssl/objects.h>
#include <openssl/x509.h>

#include <cstdint>
#include <string>
#include <vector>

#include "security/certificate_role.hpp"
#include "security/openssl_handles.hpp"

namespace mblab::security {
namespace {

using Bytes = std::vector<std::uint8_t>;

// The DER of an ASN.1 string of `tag` (a universal tag below 31) holding `text`, short form.
Bytes der_string(std::uint8_t tag, const std::string& text) {
    Bytes der;
    der.push_back(tag);
    der.push_back(static_cast<std::uint8_t>(text.size()));
    for (const char c : text)
        der.push_back(static_cast<std::uint8_t>(c));
    return der;
}

// A self-signed certificate with one role extension per entry of `values`, each holding those
// bytes as its OCTET STRING content, whatever they are.
X509Ptr certificate_with(const std::vector<Bytes>& values) {
    EvpPkeyPtr key(EVP_PKEY_Q_keygen(nullptr, nullptr, "EC", "P-256"));
    X509Ptr certificate(X509_new());
    EXPECT_TRUE(key && certificate);
    X509_set_version(certificate.get(), X509_VERSION_3);
    ASN1_INTEGER_set(X509_get_serialNumber(certificate.get()), 1);
    X509_gmtime_adj(X509_getm_notBefore(certificate.get()), 0);
    X509_gmtime_adj(X509_getm_notAfter(certificate.get()), 3600);
    X509_NAME_add_entry_by_txt(X509_get_subject_name(certificate.get()), "CN", MBSTRING_UTF8,
                               reinterpret_cast<const unsigned char*>("role test"), -1, -1, 0);
    X509_set_issuer_name(certificate.get(), X509_get_subject_name(certificate.get()));
    X509_set_pubkey(certificate.get(), key.get());
    Asn1ObjectPtr oid(OBJ_txt2obj(std::string(kRoleOid).c_str(), 1));
    for (const auto& value : values) {
        Asn1StringPtr octets(ASN1_OCTET_STRING_new());
        ASN1_OCTET_STRING_set(octets.get(), value.data(), static_cast<int>(value.size()));
        X509ExtensionPtr extension(
            X509_EXTENSION_create_by_OBJ(nullptr, oid.get(), 0, octets.get()));
        X509_add_ext(certificate.get(), extension.get(), -1);
    }
    EXPECT_GT(X509_sign(certificate.get(), key.get(), EVP_sha256()), 0);
    return certificate;
}

Bytes der_of(X509* certificate) {
    const int length = i2d_X509(certificate, nullptr);
    Bytes der(static_cast<std::size_t>(length));
    unsigned char* cursor = der.data();
    i2d_X509(certificate, &cursor);
    return der;
}

RoleReading read(const std::vector<Bytes>& values) {
    const auto certificate = certificate_with(values);
    const RoleReading direct = read_role(certificate.get());
    // Both entry points read the same certificate the same way.
    const RoleReading from_der = read_role_der(der_of(certificate.get()));
    EXPECT_EQ(direct.kind, from_der.kind);
    EXPECT_EQ(direct.role, from_der.role);
    EXPECT_EQ(direct.reason, from_der.reason);
    return direct;
}

constexpr std::uint8_t kUtf8 = V_ASN1_UTF8STRING;
constexpr std::uint8_t kIa5 = V_ASN1_IA5STRING;

TEST(CertificateRole, NoExtensionIsTheNullRole) {
    const RoleReading reading = read({});
    EXPECT_EQ(reading.kind, RoleReading::Kind::None);
    EXPECT_EQ(reading.role, "");
}

TEST(CertificateRole, OneUtf8StringIsTheRole) {
    const RoleReading reading = read({der_string(kUtf8, "Operator")});
    ASSERT_EQ(reading.kind, RoleReading::Kind::Role) << reading.reason;
    EXPECT_EQ(reading.role, "Operator");
}

TEST(CertificateRole, NonAsciiUtf8RoleIsKept) {
    const RoleReading reading = read({der_string(kUtf8, "Op\xC3\xA9rateur")});
    ASSERT_EQ(reading.kind, RoleReading::Kind::Role) << reading.reason;
    EXPECT_EQ(reading.role, "Op\xC3\xA9rateur");
}

TEST(CertificateRole, Ia5StringIsRefusedNamingTheType) {
    const RoleReading reading = read({der_string(kIa5, "Administrator")});
    EXPECT_EQ(reading.kind, RoleReading::Kind::Refused);
    EXPECT_EQ(reading.reason, "the role is an IA5String, not a UTF8String");
    EXPECT_EQ(reading.role, "");
}

TEST(CertificateRole, OtherTypesAreRefusedNamingTheType) {
    EXPECT_EQ(read({der_string(V_ASN1_PRINTABLESTRING, "Operator")}).reason,
              "the role is a PrintableString, not a UTF8String");
    EXPECT_EQ(read({der_string(V_ASN1_OCTET_STRING, "Operator")}).reason,
              "the role is an OCTET STRING, not a UTF8String");
    // A SEQUENCE holding the UTF8String: one level too deep is not the spec's encoding either.
    Bytes sequence{0x30, 0x0A};
    const Bytes inner = der_string(kUtf8, "Operator");
    sequence.insert(sequence.end(), inner.begin(), inner.end());
    EXPECT_EQ(read({sequence}).reason, "the role is a SEQUENCE, not a UTF8String");
    // Context-specific [0]: OpenSSL has no universal type to name.
    EXPECT_EQ(read({Bytes{0x80, 0x01, 'A'}}).kind, RoleReading::Kind::Refused);
}

TEST(CertificateRole, TwoRoleExtensionsAreRefused) {
    const RoleReading reading =
        read({der_string(kUtf8, "ReadOnly"), der_string(kUtf8, "Administrator")});
    EXPECT_EQ(reading.kind, RoleReading::Kind::Refused);
    EXPECT_EQ(reading.reason, "more than one role extension");
    EXPECT_EQ(reading.role, "");
}

TEST(CertificateRole, TwoIdenticalRoleExtensionsAreRefusedToo) {
    EXPECT_EQ(read({der_string(kUtf8, "Operator"), der_string(kUtf8, "Operator")}).kind,
              RoleReading::Kind::Refused);
}

TEST(CertificateRole, GarbageInTheExtensionIsRefused) {
    // A length running past the value, a lone tag, and an empty value.
    for (const Bytes& value : {Bytes{0x0C, 0x20, 'O', 'p'}, Bytes{0x0C}, Bytes{}}) {
        const RoleReading reading = read({value});
        EXPECT_EQ(reading.kind, RoleReading::Kind::Refused);
        EXPECT_FALSE(reading.reason.empty());
        EXPECT_EQ(reading.reason.find('\n'), std::string::npos);
    }
}

TEST(CertificateRole, TrailingBytesAfterTheUtf8StringAreRefused) {
    Bytes value = der_string(kUtf8, "Operator");
    value.push_back(0x00);
    const RoleReading reading = read({value});
    EXPECT_EQ(reading.kind, RoleReading::Kind::Refused);
    EXPECT_EQ(reading.reason, "the role extension has bytes after its value");
}

TEST(CertificateRole, BerThatIsNotDerIsRefused) {
    // A long-form length where the short form fits, and a constructed UTF8String of two parts.
    const Bytes long_length{0x0C, 0x81, 0x02, 'O', 'p'};
    const Bytes constructed{0x2C, 0x08, 0x0C, 0x02, 'O', 'p', 0x0C, 0x02, 'e', 'r'};
    for (const Bytes& value : {long_length, constructed}) {
        const RoleReading reading = read({value});
        EXPECT_EQ(reading.kind, RoleReading::Kind::Refused);
        EXPECT_EQ(reading.role, "");
        EXPECT_FALSE(reading.reason.empty());
    }
    EXPECT_EQ(read({long_length}).reason, "the role extension's value is not DER");
}

TEST(CertificateRole, EmptyUtf8StringIsRefused) {
    const RoleReading reading = read({der_string(kUtf8, "")});
    EXPECT_EQ(reading.kind, RoleReading::Kind::Refused);
    EXPECT_EQ(reading.reason, "the role is an empty UTF8String");
}

TEST(CertificateRole, MalformedUtf8AndControlCharactersAreRefused) {
    EXPECT_EQ(read({der_string(kUtf8, "Op\xC3")}).reason, "the role is not valid UTF-8");
    EXPECT_EQ(read({der_string(kUtf8, "\xC0\xAF")}).reason, "the role is not valid UTF-8");
    EXPECT_EQ(read({der_string(kUtf8, std::string("Op\0x", 4))}).reason,
              "the role contains a control character");
    EXPECT_EQ(read({der_string(kUtf8, "Op\nx")}).reason, "the role contains a control character");
}

TEST(CertificateRole, DerThatIsNotACertificateIsRefused) {
    for (const Bytes& der : {Bytes{}, Bytes{0x30}, Bytes{0x30, 0x03, 0x02, 0x01, 0x01},
                             Bytes{0xFF, 0xFF, 0xFF, 0xFF}}) {
        const RoleReading reading = read_role_der(der);
        EXPECT_EQ(reading.kind, RoleReading::Kind::Refused);
        EXPECT_FALSE(reading.reason.empty());
        EXPECT_EQ(reading.reason.find('\n'), std::string::npos);
    }
}

TEST(CertificateRole, BytesAfterTheCertificateAreRefused) {
    const auto certificate = certificate_with({der_string(kUtf8, "Operator")});
    Bytes der = der_of(certificate.get());
    ASSERT_EQ(read_role_der(der).kind, RoleReading::Kind::Role);
    der.push_back(0x00);
    EXPECT_EQ(read_role_der(der).kind, RoleReading::Kind::Refused);
}

TEST(CertificateRole, EveryTruncationOfACertificateIsRefusedWithoutCrashing) {
    const auto certificate = certificate_with({der_string(kUtf8, "Operator")});
    const Bytes der = der_of(certificate.get());
    for (std::size_t length = 0; length < der.size(); ++length) {
        const RoleReading reading = read_role_der({der.data(), length});
        EXPECT_EQ(reading.kind, RoleReading::Kind::Refused) << "length " << length;
    }
}

}  // namespace
}  // namespace mblab::security
