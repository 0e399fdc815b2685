#include "security/pki.hpp"

#include <fcntl.h>
#include <openssl/asn1.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/objects.h>
#include <openssl/pem.h>
#include <openssl/rand.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <set>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "security/certificate_role.hpp"
#include "security/openssl_handles.hpp"
#include "security/role_text.hpp"
#include "security/tls_context.hpp"
#include "support/hex_digits.hpp"

namespace mblab::security {

namespace {

namespace fs = std::filesystem;

// Carries one line from deep in the making of a certificate up to make_lab_pki, which returns it.
class PkiFailure : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

void check(bool ok, const std::string& what) {
    if (!ok) throw PkiFailure(what + ": " + take_openssl_error("no reason given by OpenSSL"));
}

// The client certificates every PKI has besides one per role; a role of the same name would
// overwrite one of them.
constexpr std::array<const char*, 6> kFixedClients = {"norole",      "expired",   "foreign-ca",
                                                      "self-signed", "two-roles", "ia5-role"};
constexpr std::string_view kSubjectPrefix = "mblab lab ";
// ub-common-name (RFC 5280): a longer CN does not encode.
constexpr std::size_t kMaxCommonName = 64;
constexpr long kSecondsPerDay = 24L * 60 * 60;
// RFC 2606 reserves .invalid: no client is ever given this name to connect to.
constexpr const char* kWrongName = "wrong-name.invalid";

enum class Purpose { Ca, Server, Client };

// One role extension's value: the ASN.1 string type it is encoded as, and its text.
struct RoleValue {
    int type = V_ASN1_UTF8STRING;
    std::string text;
};

struct CertificateSpec {
    std::string name;  // the file stem; the subject CN is kSubjectPrefix + name
    Purpose purpose = Purpose::Client;
    std::vector<RoleValue> roles;  // one extension each
    bool expired = false;
    std::string issuer;       // the name of the signing CA's spec; empty: self-signed
    bool wrong_name = false;  // a server certificate naming a host no client connects to
};

struct Issued {
    std::string name;
    EvpPkeyPtr key;
    X509Ptr certificate;
};

EvpPkeyPtr make_key(PkiRequest::KeyType type) {
    EvpPkeyPtr key(
        type == PkiRequest::KeyType::Ec
            ? EVP_PKEY_Q_keygen(nullptr, nullptr, "EC", "P-256")
            : EVP_PKEY_Q_keygen(nullptr, nullptr, "RSA", static_cast<std::size_t>(2048)));
    check(key != nullptr, "cannot make a key");
    return key;
}

// 16 random bytes, top bit clear so the INTEGER is positive and the next bit set so it is never
// zero nor shorter than 16 bytes: RFC 5280 asks for positive serials of at most 20 bytes.
void set_random_serial(X509* certificate) {
    std::array<unsigned char, 16> bytes{};
    check(RAND_bytes(bytes.data(), static_cast<int>(bytes.size())) == 1,
          "cannot draw a random serial");
    bytes[0] = static_cast<unsigned char>((bytes[0] & 0x7FU) | 0x40U);
    BignumPtr number(BN_bin2bn(bytes.data(), static_cast<int>(bytes.size()), nullptr));
    check(number != nullptr, "cannot make a serial");
    check(BN_to_ASN1_INTEGER(number.get(), X509_get_serialNumber(certificate)) != nullptr,
          "cannot set a serial");
}

void set_validity(X509* certificate, bool expired, int days) {
    if (expired) {
        check(X509_gmtime_adj(X509_getm_notBefore(certificate), -30 * kSecondsPerDay) != nullptr,
              "cannot set notBefore");
        check(X509_gmtime_adj(X509_getm_notAfter(certificate), -kSecondsPerDay) != nullptr,
              "cannot set notAfter");
        return;
    }
    // A few minutes back: a peer whose clock is a little behind still sees the certificate valid.
    check(X509_gmtime_adj(X509_getm_notBefore(certificate), -300) != nullptr,
          "cannot set notBefore");
    check(X509_time_adj_ex(X509_getm_notAfter(certificate), days, 0, nullptr) != nullptr,
          "cannot set notAfter");
}

void add_conf_extension(X509* certificate, X509V3_CTX* context, int nid, const char* value) {
    X509ExtensionPtr extension(X509V3_EXT_conf_nid(nullptr, context, nid, value));
    check(extension != nullptr, std::string("cannot make ") + OBJ_nid2sn(nid));
    check(X509_add_ext(certificate, extension.get(), -1) == 1,
          std::string("cannot add ") + OBJ_nid2sn(nid));
}

void add_subject_alt_names(X509* certificate, const std::vector<std::string>& names) {
    if (names.empty()) return;
    GeneralNamesPtr general_names(sk_GENERAL_NAME_new_null());
    check(general_names != nullptr, "cannot make subjectAltName");
    for (const auto& name : names) {
        GeneralNamePtr general_name(GENERAL_NAME_new());
        check(general_name != nullptr, "cannot make subjectAltName");
        if (ASN1_OCTET_STRING* address = a2i_IPADDRESS(name.c_str())) {
            GENERAL_NAME_set0_value(general_name.get(), GEN_IPADD, address);
        } else {
            ERR_clear_error();  // not an address: a DNS name, and no error to report
            Asn1StringPtr dns(ASN1_IA5STRING_new());
            check(dns != nullptr &&
                      ASN1_STRING_set(dns.get(), name.data(), static_cast<int>(name.size())) == 1,
                  "cannot make subjectAltName");
            GENERAL_NAME_set0_value(general_name.get(), GEN_DNS, dns.release());
        }
        check(sk_GENERAL_NAME_push(general_names.get(), general_name.get()) > 0,
              "cannot make subjectAltName");
        general_name.release();  // the stack owns it now
    }
    check(X509_add1_ext_i2d(certificate, NID_subject_alt_name, general_names.get(), 0,
                            X509V3_ADD_APPEND) == 1,
          "cannot add subjectAltName");
}

// Non-critical: a verifier that does not know the OID (every one but a Modbus/TCP Security
// server) must still accept the certificate.
void add_role_extension(X509* certificate, const RoleValue& role) {
    static const std::string oid_text(kRoleOid);
    Asn1ObjectPtr oid(OBJ_txt2obj(oid_text.c_str(), 1));
    check(oid != nullptr, "cannot make the role OID");
    Asn1StringPtr text(ASN1_STRING_type_new(role.type));
    check(text != nullptr && ASN1_STRING_set(text.get(), role.text.data(),
                                             static_cast<int>(role.text.size())) == 1,
          "cannot make the role");
    Asn1TypePtr value(ASN1_TYPE_new());
    check(value != nullptr && ASN1_TYPE_set1(value.get(), role.type, text.get()) == 1,
          "cannot make the role");
    const int length = i2d_ASN1_TYPE(value.get(), nullptr);
    check(length > 0, "cannot encode the role");
    std::vector<unsigned char> der(static_cast<std::size_t>(length));
    unsigned char* cursor = der.data();
    check(i2d_ASN1_TYPE(value.get(), &cursor) == length, "cannot encode the role");
    Asn1StringPtr octets(ASN1_OCTET_STRING_new());
    check(octets != nullptr && ASN1_OCTET_STRING_set(octets.get(), der.data(), length) == 1,
          "cannot make the role extension");
    X509ExtensionPtr extension(X509_EXTENSION_create_by_OBJ(nullptr, oid.get(), 0, octets.get()));
    check(extension != nullptr, "cannot make the role extension");
    check(X509_add_ext(certificate, extension.get(), -1) == 1, "cannot add the role extension");
}

Issued make_certificate(const CertificateSpec& spec, const Issued* issuer,
                        const PkiRequest& request) {
    Issued made{spec.name, make_key(request.key_type), X509Ptr(X509_new())};
    X509* certificate = made.certificate.get();
    check(certificate != nullptr, "cannot make a certificate");
    check(X509_set_version(certificate, X509_VERSION_3) == 1, "cannot set the version");
    set_random_serial(certificate);
    set_validity(certificate, spec.expired, request.days);
    const std::string common_name = std::string(kSubjectPrefix) + spec.name;
    check(X509_NAME_add_entry_by_txt(X509_get_subject_name(certificate), "CN", MBSTRING_UTF8,
                                     reinterpret_cast<const unsigned char*>(common_name.c_str()),
                                     -1, -1, 0) == 1,
          "cannot set the subject of " + spec.name);
    X509* signer = issuer != nullptr ? issuer->certificate.get() : certificate;
    EVP_PKEY* signer_key = issuer != nullptr ? issuer->key.get() : made.key.get();
    check(X509_set_issuer_name(certificate, X509_get_subject_name(signer)) == 1,
          "cannot set the issuer of " + spec.name);
    check(X509_set_pubkey(certificate, made.key.get()) == 1, "cannot set the public key");

    X509V3_CTX context;
    X509V3_set_ctx(&context, signer, certificate, nullptr, nullptr, 0);
    const bool rsa = request.key_type == PkiRequest::KeyType::Rsa;
    switch (spec.purpose) {
        case Purpose::Ca:
            add_conf_extension(certificate, &context, NID_basic_constraints, "critical,CA:TRUE");
            add_conf_extension(certificate, &context, NID_key_usage,
                               "critical,keyCertSign,cRLSign");
            break;
        case Purpose::Server:
        case Purpose::Client:
            add_conf_extension(certificate, &context, NID_basic_constraints, "critical,CA:FALSE");
            // TLS 1.2 RSA key exchange encrypts with the server's key; ECDHE only signs.
            add_conf_extension(
                certificate, &context, NID_key_usage,
                rsa ? "critical,digitalSignature,keyEncipherment" : "critical,digitalSignature");
            add_conf_extension(certificate, &context, NID_ext_key_usage,
                               spec.purpose == Purpose::Server ? "serverAuth" : "clientAuth");
            break;
    }
    add_conf_extension(certificate, &context, NID_subject_key_identifier, "hash");
    if (issuer != nullptr) {
        add_conf_extension(certificate, &context, NID_authority_key_identifier, "keyid:always");
    }
    if (spec.purpose == Purpose::Server) {
        add_subject_alt_names(certificate, spec.wrong_name ? std::vector<std::string>{kWrongName}
                                                           : request.server_names);
    }
    for (const auto& role : spec.roles)
        add_role_extension(certificate, role);
    check(X509_sign(certificate, signer_key, EVP_sha256()) > 0, "cannot sign " + spec.name);
    return made;
}

std::vector<CertificateSpec> specs_for(const PkiRequest& request) {
    std::vector<CertificateSpec> specs;
    specs.push_back({"ca", Purpose::Ca, {}, false, ""});
    specs.push_back({"foreign-ca", Purpose::Ca, {}, false, ""});
    specs.push_back({"server", Purpose::Server, {}, false, "ca"});
    // The server certificates a client must refuse (mblab conform-client's scenario 12).
    specs.push_back({"server-expired", Purpose::Server, {}, true, "ca"});
    specs.push_back({"server-foreign-ca", Purpose::Server, {}, false, "foreign-ca"});
    specs.push_back({"server-wrong-name", Purpose::Server, {}, false, "ca", true});
    for (const auto& role : request.roles) {
        specs.push_back(
            {"client-" + role, Purpose::Client, {{V_ASN1_UTF8STRING, role}}, false, "ca"});
    }
    const RoleValue administrator{V_ASN1_UTF8STRING, "Administrator"};
    specs.push_back({"client-norole", Purpose::Client, {}, false, "ca"});
    specs.push_back({"client-expired", Purpose::Client, {administrator}, true, "ca"});
    specs.push_back({"client-foreign-ca", Purpose::Client, {administrator}, false, "foreign-ca"});
    specs.push_back({"client-self-signed", Purpose::Client, {administrator}, false, ""});
    specs.push_back({"client-two-roles",
                     Purpose::Client,
                     {{V_ASN1_UTF8STRING, "ReadOnly"}, administrator},
                     false,
                     "ca"});
    specs.push_back(
        {"client-ia5-role", Purpose::Client, {{V_ASN1_IA5STRING, "Administrator"}}, false, "ca"});
    return specs;
}

std::string pem_text(const BioPtr& bio) {
    char* data = nullptr;
    const long length = BIO_get_mem_data(bio.get(), &data);
    return std::string(data, static_cast<std::size_t>(length));
}

std::string certificate_pem(X509* certificate) {
    BioPtr bio(BIO_new(BIO_s_mem()));
    check(bio != nullptr && PEM_write_bio_X509(bio.get(), certificate) == 1,
          "cannot write a certificate");
    return pem_text(bio);
}

// PKCS#8 without a passphrase: the lab's servers and clients start unattended.
std::string key_pem(EVP_PKEY* key) {
    BioPtr bio(BIO_new(BIO_s_mem()));
    check(bio != nullptr &&
              PEM_write_bio_PrivateKey(bio.get(), key, nullptr, nullptr, 0, nullptr, nullptr) == 1,
          "cannot write a key");
    return pem_text(bio);
}

std::string errno_text(const std::string& what, const fs::path& path) {
    return what + " " + path.string() + ": " + std::generic_category().message(errno);
}

// Made 0600 by open itself, so no other user can read a key between creating and chmod.
void write_private_file(const fs::path& path, const std::string& text, bool overwrite) {
    const int flags = O_WRONLY | O_CREAT | O_CLOEXEC | O_NOFOLLOW | (overwrite ? O_TRUNC : O_EXCL);
    const int fd = ::open(path.c_str(), flags, 0600);
    if (fd < 0) {
        if (errno == EEXIST) throw PkiFailure(path.string() + " exists already");
        throw PkiFailure(errno_text("cannot write", path));
    }
    // A file replaced under `overwrite` keeps the mode it had; it may have been wider.
    if (::fchmod(fd, 0600) != 0) {
        const std::string error = errno_text("cannot chmod", path);
        ::close(fd);
        throw PkiFailure(error);
    }
    std::size_t written = 0;
    while (written < text.size()) {
        const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const std::string error = errno_text("cannot write", path);
            ::close(fd);
            throw PkiFailure(error);
        }
        written += static_cast<std::size_t>(n);
    }
    if (::close(fd) != 0) throw PkiFailure(errno_text("cannot write", path));
}

void make_private_directory(const fs::path& given) {
    // "lab/" names the directory lab: its parent is ".", not lab itself.
    const fs::path dir = given.has_filename() ? given : given.parent_path();
    std::error_code error;
    if (fs::is_directory(dir, error)) return;
    if (fs::exists(fs::symlink_status(dir, error))) {
        throw PkiFailure(dir.string() + " exists and is not a directory");
    }
    const fs::path parent = dir.parent_path();
    if (!parent.empty() && !fs::exists(parent, error)) {
        fs::create_directories(parent, error);
        if (error) {
            throw PkiFailure("cannot create " + parent.string() + ": " + error.message());
        }
    }
    if (::mkdir(dir.c_str(), 0700) != 0) throw PkiFailure(errno_text("cannot create", dir));
    // The umask may have taken bits from 0700; the owner needs them all, nobody else any.
    if (::chmod(dir.c_str(), 0700) != 0) throw PkiFailure(errno_text("cannot chmod", dir));
}

std::optional<std::string> request_problem(const PkiRequest& request) {
    if (request.days < 1 || request.days > kMaxPkiDays) {
        return "days must be 1.." + std::to_string(kMaxPkiDays) + ", not " +
               std::to_string(request.days);
    }
    std::set<std::string> seen;
    for (const auto& role : request.roles) {
        if (auto problem = role_name_problem(role)) return problem;
        if (!seen.insert(role).second) return "role '" + role + "' is given twice";
    }
    for (const auto& name : request.server_names) {
        const bool usable =
            !name.empty() && name.find_first_not_of(
                                 "abcdefghijklmnopqrstuvwxyz"
                                 "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789.-_:*") == std::string::npos;
        if (!usable) {
            return "server name '" + name + "' is not a DNS name or an IP address";
        }
    }
    return std::nullopt;
}

// `text` for an error line: bytes below 0x20 and DEL as \xNN, so that a refused role cannot
// move the cursor or recolour the terminal that shows the refusal.
std::string shown(const std::string& text) {
    std::string out;
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (byte < 0x20 || byte == 0x7F) {
            out += "\\x";
            out += kHexDigits[byte >> 4U];
            out += kHexDigits[byte & 0x0FU];
        } else {
            out += c;
        }
    }
    return out;
}

}  // namespace

std::optional<std::string> role_name_problem(const std::string& role) {
    if (const char* problem = role_text_problem(role)) {
        return "role '" + shown(role) + "' " + problem;
    }
    if (role.find('/') != std::string::npos) {
        return "role '" + role + "' contains '/' (it names the file client-ROLE.pem)";
    }
    for (const char* fixed : kFixedClients) {
        if (role == fixed) {
            return "role '" + role + "' would replace client-" + role +
                   ".pem, which is not a role's certificate";
        }
    }
    std::size_t characters = 0;
    for (const char c : std::string(kSubjectPrefix) + "client-" + role) {
        if ((static_cast<unsigned char>(c) & 0xC0U) != 0x80U) ++characters;
    }
    if (characters > kMaxCommonName) {
        return "role '" + role + "' is too long for a certificate's common name (at most " +
               std::to_string(kMaxCommonName - kSubjectPrefix.size() - 7) + " characters)";
    }
    return std::nullopt;
}

protocol::Result<std::vector<fs::path>, std::string> make_lab_pki(const fs::path& dir,
                                                                  const PkiRequest& request) {
    if (auto problem = request_problem(request)) return *problem;
    try {
        std::vector<Issued> issued;
        for (const auto& spec : specs_for(request)) {
            const Issued* issuer = nullptr;
            for (const auto& made : issued) {
                if (made.name == spec.issuer) issuer = &made;
            }
            issued.push_back(make_certificate(spec, issuer, request));
        }
        // Every file's text before the first file is written: a failure leaves no half a PKI.
        std::vector<std::pair<fs::path, std::string>> files;
        for (const auto& made : issued) {
            files.emplace_back(dir / (made.name + ".pem"), certificate_pem(made.certificate.get()));
            files.emplace_back(dir / (made.name + ".key"), key_pem(made.key.get()));
        }
        if (!request.overwrite) {
            for (const auto& [path, text] : files) {
                std::error_code error;
                if (fs::exists(fs::symlink_status(path, error))) {
                    return path.string() + " exists already";
                }
            }
        }
        make_private_directory(dir);
        std::vector<fs::path> written;
        for (const auto& [path, text] : files) {
            write_private_file(path, text, request.overwrite);
            written.push_back(path);
        }
        return written;
    } catch (const PkiFailure& failure) {
        return std::string(failure.what());
    }
}

}  // namespace mblab::security
