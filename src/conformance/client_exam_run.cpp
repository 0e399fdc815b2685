#include "conformance/client_exam_run.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <map>
#include <optional>

#include "conformance/client_exam_wire.hpp"
#include "conformance/client_judge.hpp"
#include "transport/tcp_url.hpp"

namespace mblab::conformance {

namespace {

using namespace std::chrono_literals;
using Clock = ClientExaminer::Clock;

constexpr auto kPollSlice = 20ms;  // how often a running client's exit is looked for

std::chrono::milliseconds since(Clock::time_point start) {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start);
}

// The client's end as the capture's local side, the examiner's as its peer (the device's).
client::LinkAddresses addresses_of(int fd) {
    client::LinkAddresses addresses;
    sockaddr_storage ends[2]{};
    socklen_t sizes[2] = {sizeof ends[0], sizeof ends[1]};
    ::getpeername(fd, reinterpret_cast<sockaddr*>(&ends[0]), &sizes[0]);
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&ends[1]), &sizes[1]);
    addresses.ipv6 = ends[0].ss_family == AF_INET6;
    const auto take = [&](const sockaddr_storage& end, std::array<std::uint8_t, 16>& ip,
                          std::uint16_t& port) {
        if (addresses.ipv6) {
            const auto& in6 = reinterpret_cast<const sockaddr_in6&>(end);
            std::memcpy(ip.data(), &in6.sin6_addr, 16);
            port = ntohs(in6.sin6_port);
        } else {
            const auto& in4 = reinterpret_cast<const sockaddr_in&>(end);
            std::memcpy(ip.data(), &in4.sin_addr, 4);
            port = ntohs(in4.sin_port);
        }
    };
    take(ends[0], addresses.local_ip, addresses.local_port);
    take(ends[1], addresses.peer_ip, addresses.peer_port);
    return addresses;
}

void reset_and_close(int fd) {
    const linger abort{1, 0};  // close() then sends an RST
    ::setsockopt(fd, SOL_SOCKET, SO_LINGER, &abort, sizeof abort);
    ::close(fd);
}

// The examiner's connections on sockets: it accepts, reads and performs the examiner's actions.
class Wire final : public ExamWire {
  public:
    Wire(ClientExaminer& exam, int listen_fd, Capture* capture)
        : exam_(exam), listen_fd_(listen_fd), capture_(capture) {
        if (capture_) capture_->on_label(exam.scenario().id);
    }
    Wire(const Wire&) = delete;
    Wire& operator=(const Wire&) = delete;
    ~Wire() override {
        if (captured_) end_capture(*captured_, true);
        for (const auto& [id, fd] : sockets_)
            ::close(fd);
    }

    void add_polls(std::vector<pollfd>& polls) const override {
        polls.push_back({listen_fd_, POLLIN, 0});
        for (const auto& [id, fd] : sockets_)
            polls.push_back({fd, POLLIN, 0});
    }

    void on_polled(const std::vector<pollfd>& polls) override {
        for (const auto& polled : polls) {
            if (polled.revents == 0) continue;
            if (polled.fd == listen_fd_) {
                accept_all();
                continue;
            }
            for (const auto& [id, fd] : sockets_)
                if (fd == polled.fd) read_from(id);
        }
        forget_closed();
    }

    void perform() override {
        for (auto& action : exam_.due(Clock::now())) {
            const auto found = sockets_.find(action.connection);
            if (found == sockets_.end()) continue;
            const int fd = found->second;
            switch (action.kind) {
                case ClientExaminer::Action::Kind::Send:
                    ::send(fd, action.bytes.data(), action.bytes.size(), MSG_NOSIGNAL);
                    if (captured(action.connection)) capture_->on_received(action.bytes);
                    break;
                case ClientExaminer::Action::Kind::Close:
                    // A FIN; what the client sends after it is read and dropped until it closes.
                    ::shutdown(fd, SHUT_WR);
                    end_capture(action.connection, true);
                    break;
                case ClientExaminer::Action::Kind::Reset:
                    end_capture(action.connection, true);
                    reset_and_close(fd);
                    sockets_.erase(found);
                    break;
            }
        }
    }

    std::chrono::milliseconds wait() const override {
        const auto deadline = exam_.deadline();
        if (deadline == Clock::time_point::max()) return kPollSlice;
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        return std::clamp(left, 0ms, std::chrono::milliseconds(kPollSlice));
    }

  private:
    // A capture holds one connection at a time: it follows the newest, and the bytes of an older
    // one still open (a client's second connection overlapping its first) are left out.
    bool captured(std::size_t id) const { return capture_ && captured_ == id; }
    void end_capture(std::size_t id, bool by_examiner) {
        if (!captured(id)) return;
        capture_->on_close(by_examiner);
        captured_.reset();
    }

    void accept_all() {
        while (true) {
            const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
            if (fd < 0) return;
            const int on = 1;
            // Each action is one segment: split answers must not be joined again.
            ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
            const auto id = exam_.opened(Clock::now());
            sockets_[id] = fd;
            if (capture_) {
                capture_->on_open(addresses_of(fd));
                captured_ = id;
            }
        }
    }

    void read_from(std::size_t id) {
        std::uint8_t buffer[1024];
        const int fd = sockets_.at(id);
        while (true) {
            const auto got = ::recv(fd, buffer, sizeof buffer, 0);
            if (got > 0) {
                if (captured(id)) capture_->on_sent({buffer, static_cast<std::size_t>(got)});
                exam_.received(id,
                               std::span<const std::uint8_t>(buffer, static_cast<std::size_t>(got)),
                               Clock::now());
                continue;
            }
            if (got < 0 && (errno == EAGAIN || errno == EINTR)) return;
            end_capture(id, false);
            exam_.closed(id, Clock::now());
            closed_.push_back(id);
            return;
        }
    }

    void forget_closed() {
        for (const auto id : closed_) {
            if (auto found = sockets_.find(id); found != sockets_.end()) {
                ::close(found->second);
                sockets_.erase(found);
            }
        }
        closed_.clear();
    }

    ClientExaminer& exam_;
    int listen_fd_;
    Capture* capture_;
    std::optional<std::size_t> captured_;
    std::map<std::size_t, int> sockets_;
    std::vector<std::size_t> closed_;
};

// A connection left over from the scenario before (a client's late reconnect) is not this one's.
void drain_backlog(int listen_fd) {
    while (true) {
        const int fd = ::accept4(listen_fd, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) return;
        ::close(fd);
    }
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
    auto endpoint = transport::parse_tcp_url(url);
    if (!endpoint) return endpoint.error();
    std::unique_ptr<ExamListener> listener(new ExamListener());
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
    return "tcp://" + (v6 ? "[" + host_ + "]" : host_) + ":" + std::to_string(port_);
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

RunResult run_client_exam(ExamListener& listen, const ClientExamOptions& options,
                          RunListener* listener) {
    ClientPlaceholders where;
    where.host = listen.host();
    where.port = std::to_string(listen.port());
    where.url = listen.url();
    ExamCarrier carrier{client_tcp_suite(), &client_tcp_cases(), where, protocol::Framing::Mbap,
                        [&](ClientExaminer& exam) -> std::unique_ptr<ExamWire> {
                            drain_backlog(listen.fd());
                            return std::make_unique<Wire>(exam, listen.fd(), options.capture);
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
        if (auto na = undeclared(c, declared)) {
            case_result.outcome = *na;
        } else {
            std::vector<std::string> argv;
            for (const auto& arg : options.command)
                argv.push_back(fill_placeholders(arg, values));
            ClientExaminer exam(c, declared, Clock::now(), carrier.framing);
            const auto wire = carrier.wire(exam);
            const auto run = run_one(*wire, argv, declared);
            case_result.outcome = judge_client(exam, declared, run);
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
