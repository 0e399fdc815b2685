#include "conformance/client_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <memory>

extern char** environ;

namespace mblab::conformance {

ClientProcess::~ClientProcess() {
    kill();
    if (output_ >= 0) ::close(output_);
}

protocol::Result<std::unique_ptr<ClientProcess>, std::string> ClientProcess::start(
    const std::vector<std::string>& argv) {
    if (argv.empty()) return std::string("no client command");
    int pipe_fds[2];
    if (::pipe2(pipe_fds, O_CLOEXEC) != 0) return std::string("pipe: ") + std::strerror(errno);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDERR_FILENO);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    // Its own group, so a client that starts helpers (a Python interpreter, a shell) is stopped
    // whole.
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attributes, 0);
    std::vector<char*> args;
    for (const auto& arg : argv)
        args.push_back(const_cast<char*>(arg.c_str()));
    args.push_back(nullptr);
    pid_t pid = -1;
    const int failed = ::posix_spawnp(&pid, args[0], &actions, &attributes, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    ::close(pipe_fds[1]);
    if (failed != 0) {
        ::close(pipe_fds[0]);
        return "cannot run '" + argv[0] + "': " + std::strerror(failed);
    }
    auto process = std::make_unique<ClientProcess>();
    process->pid_ = pid;
    process->output_ = pipe_fds[0];
    ::fcntl(process->output_, F_SETFL, O_NONBLOCK);
    return process;
}

void ClientProcess::read_output() {
    if (output_ < 0) return;
    char buffer[4096];
    while (true) {
        const auto got = ::read(output_, buffer, sizeof buffer);
        if (got > 0) {
            text_.append(buffer, static_cast<std::size_t>(got));
            continue;
        }
        if (got < 0 && (errno == EAGAIN || errno == EINTR)) return;
        ::close(output_);
        output_ = -1;
        return;
    }
}

bool ClientProcess::exited() {
    if (reaped_) return true;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) != pid_) return false;
    reaped_ = true;
    status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return true;
}

void ClientProcess::kill() {
    if (pid_ < 0 || reaped_) return;
    ::kill(-pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    reaped_ = true;
    status_ = 128 + SIGKILL;
}

std::string fill_placeholders(std::string text, const ClientPlaceholders& values) {
    const std::pair<std::string_view, const std::string*> names[] = {
        {"{host}", &values.host},     {"{port}", &values.port},       {"{url}", &values.url},
        {"{unit}", &values.unit},     {"{address}", &values.address}, {"{count}", &values.count},
        {"{device}", &values.device}, {"{baud}", &values.baud},       {"{ca}", &values.ca},
        {"{cert}", &values.cert},     {"{key}", &values.key},
    };
    // One pass from the left, so a value is never read for names again.
    std::string filled;
    for (std::size_t at = 0; at < text.size();) {
        const auto* match = std::find_if(std::begin(names), std::end(names), [&](const auto& n) {
            return std::string_view(text).substr(at).starts_with(n.first);
        });
        if (match == std::end(names)) {
            filled += text[at++];
            continue;
        }
        filled += *match->second;
        at += match->first.size();
    }
    return filled;
}

}  // namespace mblab::conformance
