#include <gtest/gtest.h>
#include <openssl/pem.h>
#include <openssl/x509.h>
#include <openssl/x509_vfy.h>
#include <openssl/x509v3.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "security/certificate_role.hpp"
#include "security/openssl_handles.hpp"
#include "security/pki.hpp"
#include "support/temp_dir.hpp"

namespace mblab::security {
namespace {

namespace fs = std::filesystem;

X509Ptr load_certificate(const fs::path& path) {
    BioPtr bio(BIO_new_file(path.c_str(), "r"));
    if (!bio) return nullptr;
    return X509Ptr(PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr));
}

EvpPkeyPtr load_key(const fs::path& path) {
    BioPtr bio(BIO_new_file(path.c_str(), "r"));
    if (!bio) return nullptr;
    return EvpPkeyPtr(PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr));
}

unsigned mode_of(const fs::path& path) {
    struct stat status {};
    if (::lstat(path.c_str(), &status) != 0) return 07777;
    return status.st_mode & 07777U;
}

// X509_V_OK or why `name`.pem does not verify against ca.pem as a TLS client (or `purpose`)
// certificate.
int verify_client(const fs::path& dir, const std::string& name,
                  int purpose = X509_PURPOSE_SSL_CLIENT) {
    X509StorePtr store(X509_STORE_new());
    const auto ca = load_certificate(dir / "ca.pem");
    const auto leaf = load_certificate(dir / (name + ".pem"));
    EXPECT_TRUE(store && ca && leaf) << name;
    if (!store || !ca || !leaf) return -1;
    X509_STORE_add_cert(store.get(), ca.get());
    X509StoreCtxPtr context(X509_STORE_CTX_new());
    X509_STORE_CTX_init(context.get(), store.get(), leaf.get(), nullptr);
    X509_STORE_CTX_set_purpose(context.get(), purpose);
    if (X509_verify_cert(context.get()) == 1) return X509_V_OK;
    return X509_STORE_CTX_get_error(context.get());
}

class LabPki : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = new test::TempDir();
        auto made = make_lab_pki(dir() / "pki", PkiRequest{});
        ASSERT_TRUE(made.ok()) << made.error();
        written_ = new std::vector<fs::path>(made.value());
    }
    static void TearDownTestSuite() {
        delete written_;
        delete dir_;
        written_ = nullptr;
        dir_ = nullptr;
    }
    static fs::path dir() { return dir_->path(); }
    static fs::path pki() { return dir_->path() / "pki"; }

    static test::TempDir* dir_;
    static std::vector<fs::path>* written_;
};

test::TempDir* LabPki::dir_ = nullptr;
std::vector<fs::path>* LabPki::written_ = nullptr;

const std::vector<std::string> kNames = {
    "ca",
    "foreign-ca",
    "server",
    "server-expired",
    "server-foreign-ca",
    "server-wrong-name",
    "client-ReadOnly",
    "client-Operator",
    "client-Administrator",
    "client-norole",
    "client-expired",
    "client-foreign-ca",
    "client-self-signed",
    "client-two-roles",
    "client-ia5-role",
};

TEST_F(LabPki, WritesEveryCertificateAndKeyMode0600InADirectoryMode0700) {
    ASSERT_NE(written_, nullptr);
    EXPECT_EQ(mode_of(pki()), 0700U);
    std::vector<fs::path> expected;
    for (const auto& name : kNames) {
        expected.push_back(pki() / (name + ".pem"));
        expected.push_back(pki() / (name + ".key"));
    }
    std::vector<fs::path> got = *written_;
    std::sort(expected.begin(), expected.end());
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected);
    std::size_t entries = 0;
    for (const auto& entry : fs::directory_iterator(pki())) {
        ++entries;
        EXPECT_EQ(mode_of(entry.path()), 0600U) << entry.path();
    }
    EXPECT_EQ(entries, expected.size());
}

TEST_F(LabPki, EachKeyMatchesItsCertificate) {
    for (const auto& name : kNames) {
        const auto certificate = load_certificate(pki() / (name + ".pem"));
        const auto key = load_key(pki() / (name + ".key"));
        ASSERT_TRUE(certificate && key) << name;
        EXPECT_EQ(X509_check_private_key(certificate.get(), key.get()), 1) << name;
        EXPECT_EQ(EVP_PKEY_get_base_id(key.get()), EVP_PKEY_EC) << name;
        EXPECT_EQ(X509_get_signature_nid(certificate.get()), NID_ecdsa_with_SHA256) << name;
    }
}

TEST_F(LabPki, SubjectCommonNameIsTheFileName) {
    for (const auto& name : kNames) {
        const auto certificate = load_certificate(pki() / (name + ".pem"));
        ASSERT_TRUE(certificate) << name;
        std::array<char, 128> common_name{};
        X509_NAME_get_text_by_NID(X509_get_subject_name(certificate.get()), NID_commonName,
                                  common_name.data(), static_cast<int>(common_name.size()));
        EXPECT_EQ(std::string(common_name.data()), "mblab lab " + name);
        const ASN1_INTEGER* serial = X509_get0_serialNumber(certificate.get());
        EXPECT_NE(serial->type & V_ASN1_NEG, V_ASN1_NEG) << name;
    }
}

TEST_F(LabPki, SerialsDiffer) {
    const auto first = load_certificate(pki() / "client-Operator.pem");
    const auto second = load_certificate(pki() / "client-ReadOnly.pem");
    ASSERT_TRUE(first && second);
    EXPECT_NE(
        ASN1_INTEGER_cmp(X509_get0_serialNumber(first.get()), X509_get0_serialNumber(second.get())),
        0);
}

TEST_F(LabPki, ClientCertificatesVerifyAgainstTheCaOrFailForTheirReason) {
    const std::map<std::string, int> expected = {
        {"client-ReadOnly", X509_V_OK},
        {"client-Operator", X509_V_OK},
        {"client-Administrator", X509_V_OK},
        {"client-norole", X509_V_OK},
        {"client-two-roles", X509_V_OK},
        {"client-ia5-role", X509_V_OK},
        {"client-expired", X509_V_ERR_CERT_HAS_EXPIRED},
        {"client-foreign-ca", X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT_LOCALLY},
        {"client-self-signed", X509_V_ERR_DEPTH_ZERO_SELF_SIGNED_CERT},
    };
    for (const auto& [name, error] : expected) {
        const int got = verify_client(pki(), name);
        EXPECT_EQ(got, error) << name << ": " << X509_verify_cert_error_string(got);
    }
}

TEST_F(LabPki, CertificatesCarryTheRightPurpose) {
    const auto ca = load_certificate(pki() / "ca.pem");
    const auto server = load_certificate(pki() / "server.pem");
    const auto client = load_certificate(pki() / "client-Operator.pem");
    ASSERT_TRUE(ca && server && client);
    EXPECT_EQ(X509_check_ca(ca.get()), 1);
    EXPECT_NE(X509_get_key_usage(ca.get()) & KU_KEY_CERT_SIGN, 0U);
    EXPECT_EQ(X509_check_ca(client.get()), 0);
    EXPECT_EQ(X509_check_purpose(server.get(), X509_PURPOSE_SSL_SERVER, 0), 1);
    EXPECT_EQ(X509_check_purpose(client.get(), X509_PURPOSE_SSL_CLIENT, 0), 1);
    EXPECT_NE(X509_check_purpose(client.get(), X509_PURPOSE_SSL_SERVER, 0), 1);
}

TEST_F(LabPki, EachClientCertificateReadsAsItsRole) {
    struct Expected {
        const char* name;
        RoleReading::Kind kind;
        const char* role;
    };
    const std::vector<Expected> expected = {
        {"client-ReadOnly", RoleReading::Kind::Role, "ReadOnly"},
        {"client-Operator", RoleReading::Kind::Role, "Operator"},
        {"client-Administrator", RoleReading::Kind::Role, "Administrator"},
        {"client-expired", RoleReading::Kind::Role, "Administrator"},
        {"client-foreign-ca", RoleReading::Kind::Role, "Administrator"},
        {"client-self-signed", RoleReading::Kind::Role, "Administrator"},
        {"client-norole", RoleReading::Kind::None, ""},
        {"server", RoleReading::Kind::None, ""},
        {"client-two-roles", RoleReading::Kind::Refused, ""},
        {"client-ia5-role", RoleReading::Kind::Refused, ""},
    };
    for (const auto& item : expected) {
        const auto certificate = load_certificate(pki() / (std::string(item.name) + ".pem"));
        ASSERT_TRUE(certificate) << item.name;
        const RoleReading reading = read_role(certificate.get());
        EXPECT_EQ(reading.kind, item.kind) << item.name << ": " << reading.reason;
        EXPECT_EQ(reading.role, item.role) << item.name;
    }
}

TEST_F(LabPki, RoleExtensionIsNotCritical) {
    const auto certificate = load_certificate(pki() / "client-Operator.pem");
    ASSERT_TRUE(certificate);
    Asn1ObjectPtr oid(OBJ_txt2obj(std::string(kRoleOid).c_str(), 1));
    const int index = X509_get_ext_by_OBJ(certificate.get(), oid.get(), -1);
    ASSERT_GE(index, 0);
    EXPECT_EQ(X509_EXTENSION_get_critical(X509_get_ext(certificate.get(), index)), 0);
}

TEST_F(LabPki, ServerCertificateNamesEveryServerName) {
    const auto server = load_certificate(pki() / "server.pem");
    ASSERT_TRUE(server);
    EXPECT_EQ(X509_check_host(server.get(), "localhost", 0, 0, nullptr), 1);
    EXPECT_EQ(X509_check_ip_asc(server.get(), "127.0.0.1", 0), 1);
    EXPECT_EQ(X509_check_ip_asc(server.get(), "::1", 0), 1);
    EXPECT_NE(X509_check_host(server.get(), "example.com", 0, 0, nullptr), 1);
    EXPECT_NE(X509_check_ip_asc(server.get(), "127.0.0.2", 0), 1);
}

// What a client must refuse in conform-client's scenario 12: each fails for one reason only.
TEST_F(LabPki, ServerCertificatesAClientMustRefuseFailForTheirReason) {
    const std::map<std::string, int> expected = {
        {"server", X509_V_OK},
        {"server-wrong-name", X509_V_OK},
        {"server-expired", X509_V_ERR_CERT_HAS_EXPIRED},
        {"server-foreign-ca", X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT_LOCALLY},
    };
    for (const auto& [name, error] : expected) {
        const int got = verify_client(pki(), name, X509_PURPOSE_SSL_SERVER);
        EXPECT_EQ(got, error) << name << ": " << X509_verify_cert_error_string(got);
    }
    for (const char* name : {"server-expired", "server-foreign-ca"}) {
        const auto certificate = load_certificate(pki() / (std::string(name) + ".pem"));
        ASSERT_TRUE(certificate) << name;
        EXPECT_EQ(X509_check_ip_asc(certificate.get(), "127.0.0.1", 0), 1) << name;
    }
    const auto wrong = load_certificate(pki() / "server-wrong-name.pem");
    ASSERT_TRUE(wrong);
    EXPECT_NE(X509_check_ip_asc(wrong.get(), "127.0.0.1", 0), 1);
    EXPECT_NE(X509_check_host(wrong.get(), "localhost", 0, 0, nullptr), 1);
}

TEST_F(LabPki, RefusesToOverwriteWithoutOverwrite) {
    const std::string before = test::file_text(pki() / "ca.pem");
    auto again = make_lab_pki(pki(), PkiRequest{});
    ASSERT_FALSE(again.ok());
    EXPECT_EQ(again.error(), (pki() / "ca.pem").string() + " exists already");
    EXPECT_EQ(test::file_text(pki() / "ca.pem"), before);
}

TEST(MakeLabPki, OverwriteReplacesFilesAndTightensTheirMode) {
    test::TempDir dir;
    PkiRequest request;
    request.roles = {"Operator"};
    ASSERT_TRUE(make_lab_pki(dir.path(), request).ok());
    const std::string before = test::file_text(dir / "ca.key");
    ASSERT_EQ(::chmod((dir / "ca.key").c_str(), 0644), 0);
    request.overwrite = true;
    auto again = make_lab_pki(dir.path(), request);
    ASSERT_TRUE(again.ok()) << again.error();
    EXPECT_NE(test::file_text(dir / "ca.key"), before);
    EXPECT_EQ(mode_of(dir / "ca.key"), 0600U);
    EXPECT_EQ(verify_client(dir.path(), "client-Operator"), X509_V_OK);
}

TEST(MakeLabPki, MakesMissingParentsAndTakesATrailingSlash) {
    test::TempDir dir;
    PkiRequest request;
    request.roles = {};
    auto made = make_lab_pki((dir / "a/b/pki/").string(), request);
    ASSERT_TRUE(made.ok()) << made.error();
    EXPECT_EQ(mode_of(dir / "a/b/pki"), 0700U);
    EXPECT_TRUE(fs::exists(dir / "a/b/pki/ca.pem"));
}

TEST(MakeLabPki, RsaKeysWhenAsked) {
    test::TempDir dir;
    PkiRequest request;
    request.roles = {"Operator"};
    request.key_type = PkiRequest::KeyType::Rsa;
    ASSERT_TRUE(make_lab_pki(dir.path(), request).ok());
    const auto key = load_key(dir / "client-Operator.key");
    ASSERT_TRUE(key);
    EXPECT_EQ(EVP_PKEY_get_base_id(key.get()), EVP_PKEY_RSA);
    EXPECT_EQ(EVP_PKEY_get_bits(key.get()), 2048);
    const auto certificate = load_certificate(dir / "client-Operator.pem");
    ASSERT_TRUE(certificate);
    EXPECT_EQ(X509_get_signature_nid(certificate.get()), NID_sha256WithRSAEncryption);
    EXPECT_EQ(verify_client(dir.path(), "client-Operator"), X509_V_OK);
}

TEST(MakeLabPki, DaysSetNotAfter) {
    test::TempDir dir;
    PkiRequest request;
    request.roles = {};
    request.days = 2;
    ASSERT_TRUE(make_lab_pki(dir.path(), request).ok());
    const auto certificate = load_certificate(dir / "server.pem");
    ASSERT_TRUE(certificate);
    int days = 0;
    int seconds = 0;
    ASSERT_EQ(ASN1_TIME_diff(&days, &seconds, nullptr, X509_get0_notAfter(certificate.get())), 1);
    EXPECT_TRUE(days == 2 || (days == 1 && seconds > 86000)) << days << " " << seconds;
}

TEST(MakeLabPki, BadRequestsWriteNothing) {
    test::TempDir dir;
    const auto refused = [&](PkiRequest request) {
        auto made = make_lab_pki(dir / "pki", request);
        EXPECT_FALSE(made.ok());
        EXPECT_FALSE(fs::exists(dir / "pki"));
        return made.ok() ? std::string() : made.error();
    };
    PkiRequest request;
    request.roles = {"a/b"};
    EXPECT_EQ(refused(request), "role 'a/b' contains '/' (it names the file client-ROLE.pem)");
    request.roles = {""};
    EXPECT_EQ(refused(request), "role '' is empty");
    request.roles = {"Op\x01"};
    EXPECT_EQ(refused(request), "role 'Op\\x01' contains a control character");
    request.roles = {"expired"};
    EXPECT_NE(refused(request).find("client-expired.pem"), std::string::npos);
    request.roles = {"Operator", "Operator"};
    EXPECT_EQ(refused(request), "role 'Operator' is given twice");
    request.roles = {std::string(48, 'x')};
    EXPECT_NE(refused(request).find("too long"), std::string::npos);
    request.roles = {};
    request.days = 0;
    EXPECT_EQ(refused(request), "days must be 1..36500, not 0");
    request.days = 365;
    request.server_names = {"bad name"};
    EXPECT_NE(refused(request).find("'bad name'"), std::string::npos);
}

TEST(MakeLabPki, LongestRoleFitsTheCommonName) {
    EXPECT_EQ(role_name_problem(std::string(47, 'x')), std::nullopt);
    EXPECT_NE(role_name_problem(std::string(48, 'x')), std::nullopt);
    EXPECT_EQ(role_name_problem("Op\xC3\xA9rateur"), std::nullopt);
}

}  // namespace
}  // namespace mblab::security
