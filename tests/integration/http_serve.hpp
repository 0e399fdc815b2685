#pragma once

// `mblab serve --http` as a process on ephemeral ports, driven with curl.
#include <signal.h>
#include <unistd.h>

#include <regex>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "test_client_support.hpp"

namespace mblab::test {

using namespace std::chrono_literals;

// `mblab serve` with --http on ephemeral ports: both addresses, and the token serve made, from
// its first two lines.
class HttpServe {
  public:
    explicit HttpServe(std::vector<std::string> extra) : child_(args(std::move(extra))) {
        std::smatch match;
        if (auto line = child_.read_stdout_line(10s);
            line && std::regex_search(*line, match, std::regex("tcp://127\\.0\\.0\\.1:[0-9]+"))) {
            modbus_ = match[0];
        }
        if (auto line = child_.read_stdout_line(10s)) {
            if (std::regex_search(*line, match, std::regex("http://127\\.0\\.0\\.1:[0-9]+")))
                http_ = match[0];
            if (std::regex_search(*line, match, std::regex("#token=([0-9a-f]+)")))
                token_ = match[1];
        }
    }
    ~HttpServe() {
        child_.signal(SIGTERM);
        child_.wait_exit(10s);
    }
    const std::string& modbus() const { return modbus_; }
    const std::string& http() const { return http_; }
    const std::string& token() const { return token_; }
    ChildProcess& child() { return child_; }

  private:
    static std::vector<std::string> args(std::vector<std::string> extra) {
        std::vector<std::string> out{MBLAB_BINARY,        "serve",  "--listen",
                                     "tcp://127.0.0.1:0", "--http", "127.0.0.1:0"};
        out.insert(out.end(), extra.begin(), extra.end());
        return out;
    }
    ChildProcess child_;
    std::string modbus_;
    std::string http_;
    std::string token_;
};

// curl ARGS... with the status code on a last line of its own.
inline Ran curl(std::vector<std::string> args) {
    std::vector<std::string> argv{"/usr/bin/curl", "-s", "-w", "\n%{http_code}\n"};
    argv.insert(argv.end(), args.begin(), args.end());
    return run_program(argv);
}

// A change as the dashboard makes it: the token serve made, a JSON body.
inline Ran change(const HttpServe& serve, const std::string& method, const std::string& path,
                  const std::string& body) {
    return curl({"-X", method, "-H", "Authorization: Bearer " + serve.token(), "-H",
                 "Content-Type: application/json", "--data-binary", body, serve.http() + path});
}

// The Modbus address serve prints on its first line.
inline std::string modbus_target(ChildProcess& serve) {
    std::smatch match;
    const auto line = serve.read_stdout_line(10s);
    if (!line || !std::regex_search(*line, match, std::regex("tcp://127\\.0\\.0\\.1:[0-9]+")))
        return {};
    return match[0];
}

// `mblab serve ARGS...` on an ephemeral port (no HTTP).
inline std::vector<std::string> serve_argv(std::vector<std::string> args) {
    std::vector<std::string> argv{MBLAB_BINARY, "serve", "--listen", "tcp://127.0.0.1:0"};
    argv.insert(argv.end(), args.begin(), args.end());
    return argv;
}

inline bool have(const char* program) {
    return ::access(program, X_OK) == 0;
}

}  // namespace mblab::test
