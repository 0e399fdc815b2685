#include "conformance/client_exam_run.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "conformance/client_attach.hpp"
#include "conformance/client_exam_tcp_wire.hpp"
#include "conformance/client_exam_wire.hpp"
#include "conformance/client_judge.hpp"
#include "transport/serial_url.hpp"
#include "transport/tcp_url.hpp"

namespace mblab::conformance {

namespace {

using namespace std::chrono_literals;
using Clock = ClientExaminer::Clock;

std::chrono::milliseconds since(Clock::time_point start) {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start);
}

ClientRun run_one(ExamWire& wire, const std::vector<std::string>& argv,
                  const ClientDeclarations& declared) {
    ClientRun run;
    run.limit = client_run_limit(declared);
    auto process = ClientProcess::start(argv);
    if (!process) {
        run.exit_status = 127;
        run.output = process.error();
        return run;
    }
    auto& client = **process;
    const auto started = Clock::now();
    while (true) {
        std::vector<pollfd> polls;
        wire.add_polls(polls);
        if (client.output_fd() >= 0) polls.push_back({client.output_fd(), POLLIN, 0});
        ::poll(polls.data(), polls.size(), static_cast<int>(wire.wait().count()));
        wire.on_polled(polls);
        client.read_output();
        wire.perform();
        if (client.exited() && client.output_fd() < 0) break;
        if (since(started) > run.limit) {
            run.stopped = true;
            client.kill();
            client.read_output();
            break;
        }
    }
    run.elapsed = since(started);
    run.ended = Clock::now();
    run.exit_status = client.exit_status();
    run.output = client.output();
    return run;
}

bool chosen(const ClientCase& c, const std::vector<std::string>& only) {
    if (only.empty()) return true;
    return std::any_of(only.begin(), only.end(), [&](const std::string& id) {
        return c.id == id || (c.id.starts_with(id) && c.id[id.size()] == '.');
    });
}

}  // namespace

protocol::Result<std::unique_ptr<ExamListener>, std::string> ExamListener::open(
    const std::string& url) {
    std::unique_ptr<ExamListener> listener(new ExamListener());
    protocol::Result<asio::ip::tcp::endpoint, std::string> endpoint = std::string();
    if (url.starts_with("rtu+tcp:")) {
        // RTU frames over TCP, as a serial gateway carries them.
        listener->scheme_ = "rtu+tcp://";
        auto parsed = transport::parse_serial_url(url);
        if (parsed)
            endpoint = parsed->endpoint;
        else
            endpoint = parsed.error();
    } else if (transport::is_mbaps_url(url)) {
        listener->scheme_ = "mbaps://";
        endpoint = transport::parse_mbaps_url(url);
    } else {
        endpoint = transport::parse_tcp_url(url);
    }
    if (!endpoint) return endpoint.error();
    const int family = endpoint->address().is_v6() ? AF_INET6 : AF_INET;
    listener->fd_ = ::socket(family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    const int on = 1;
    ::setsockopt(listener->fd_, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    if (listener->fd_ < 0 ||
        ::bind(listener->fd_, endpoint->data(), static_cast<socklen_t>(endpoint->size())) != 0 ||
        ::listen(listener->fd_, 16) != 0) {
        return "cannot listen on " + url + ": " + std::strerror(errno);
    }
    sockaddr_storage bound{};
    socklen_t size = sizeof bound;
    ::getsockname(listener->fd_, reinterpret_cast<sockaddr*>(&bound), &size);
    listener->port_ = ntohs(family == AF_INET6 ? reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port
                                               : reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
    const auto address = endpoint->address();
    // A client cannot connect to "any address": it is sent to loopback.
    listener->host_ =
        address.is_unspecified() ? (address.is_v6() ? "::1" : "127.0.0.1") : address.to_string();
    return listener;
}

ExamListener::~ExamListener() {
    if (fd_ >= 0) ::close(fd_);
}

std::string ExamListener::url() const {
    const bool v6 = host_.find(':') != std::string::npos;
    return scheme_ + (v6 ? "[" + host_ + "]" : host_) + ":" + std::to_string(port_);
}

Suite client_suite(std::string name, std::string title, std::string source,
                   const std::vector<ClientCase>& cases) {
    Suite suite{std::move(name), std::move(title), std::move(source), "", {}};
    for (const auto& c : cases) {
        Case entry;
        entry.id = c.id;
        entry.source = c.source;
        entry.title = c.title;
        suite.cases.push_back(entry);
    }
    return suite;
}

Suite client_tcp_suite() {
    return client_suite("client-tcp", "a Modbus/TCP client against the examiner", "TCPG 4.4.1.1",
                        client_tcp_cases());
}

Suite client_mbaps_suite() {
    return client_suite("client-mbaps",
                        "a Modbus/TCP Security client against the examiner, behind TLS", "SEC R-06",
                        client_mbaps_cases());
}

Suite client_rtu_tcp_suite() {
    return client_suite("client-rtu-tcp",
                        "a Modbus RTU client (master) over TCP, as through a serial gateway",
                        "SER 2.4.1", client_line_cases());
}

RunResult run_client_exam(ExamListener& listen, const ClientExamOptions& options,
                          RunListener* listener) {
    const auto* tls = options.tls;
    const bool rtu = listen.framing() == protocol::Framing::Rtu;
    ClientPlaceholders where;
    where.host = listen.host();
    where.port = std::to_string(listen.port());
    where.url = listen.url();
    if (tls) {
        where.ca = tls->ca();
        where.cert = tls->cert();
        where.key = tls->key();
    }
    ExamCarrier carrier{rtu   ? client_rtu_tcp_suite()
                        : tls ? client_mbaps_suite()
                              : client_tcp_suite(),
                        rtu   ? &client_line_cases()
                        : tls ? &client_mbaps_cases()
                              : &client_tcp_cases(),
                        where, listen.framing(),
                        [&](ClientExaminer& exam) -> std::unique_ptr<ExamWire> {
                            drain_backlog(listen.fd());
                            return make_tcp_wire(exam, listen.fd(), options.capture,
                                                 tls ? tls->context(exam.scenario()) : nullptr);
                        }};
    return run_client_cases(carrier, options, listener);
}

RunResult run_client_cases(const ExamCarrier& carrier, const ClientExamOptions& options,
                           RunListener* listener) {
    RunResult result;
    result.target = options.command.empty() ? "" : options.command.front();
    const auto& suite = carrier.suite;
    SuiteResult suite_result{suite.name, suite.title, "", {}};
    if (listener) listener->suite_started(suite);
    const auto started = Clock::now();
    for (const auto& c : *carrier.cases) {
        if (!chosen(c, options.only)) continue;
        CaseResult case_result{c.id, c.source, c.title, {}, {}, 0, false};
        const auto case_start = Clock::now();
        auto declared = options.declared;
        auto values = carrier.values;
        // SER 2.2: a broadcast goes to address 0.
        if (c.scenario == ClientScenario::Broadcast) declared.unit = 0;
        values.unit = std::to_string(declared.unit);
        values.address = std::to_string(declared.address);
        values.count = std::to_string(declared.count);
        auto na = undeclared(c, declared);
        if (!na && options.attach) na = needs_output(c);
        if (na) {
            case_result.outcome = *na;
        } else {
            std::vector<std::string> argv;
            for (const auto& arg : options.command)
                argv.push_back(fill_placeholders(arg, values));
            ClientExaminer exam(c, declared, Clock::now(), carrier.framing);
            const auto wire = carrier.wire(exam);
            const auto run = options.attach
                                 ? watch_attached(*wire, exam, declared, options.attach_wait)
                                 : run_one(*wire, argv, declared);
            case_result.outcome = judge_client(exam, declared, run);
            if (options.transcripts) (*options.transcripts)[c.id] = transcript_of(exam, case_start);
            case_result.requests = exam.requests().size();
        }
        case_result.elapsed =
            std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - case_start);
        result.requests += case_result.requests;
        if (listener) listener->case_finished(suite, case_result);
        suite_result.cases.push_back(std::move(case_result));
    }
    result.elapsed = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - started);
    result.suites.push_back(std::move(suite_result));
    return result;
}

}  // namespace mblab::conformance
