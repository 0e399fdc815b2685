#include "transport/socket_channel.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>

namespace mblab::transport {

Io SocketChannel::read(std::span<std::uint8_t> out) {
    for (;;) {
        const auto n = ::recv(fd_, out.data(), out.size(), MSG_DONTWAIT);
        read_filled_ = n > 0 && static_cast<std::size_t>(n) == out.size();
        if (n > 0) return Io::done(static_cast<std::size_t>(n));
        if (n == 0) return Io::end_of_input();
        if (errno == EINTR) continue;
        if (errno == EAGAIN || errno == EWOULDBLOCK) return Io::would_block();
        return Io::failed(errno);
    }
}

Io SocketChannel::writev(std::span<const iovec> buffers) {
    std::size_t wanted = 0;
    for (const auto& buffer : buffers)
        wanted += buffer.iov_len;
    // Only empty buffers (a deferred "no answer" has nothing to send): no system call.
    if (wanted == 0) return Io::done(0);
    for (;;) {
        ssize_t n = 0;
        if (buffers.size() == 1) {
            // The usual case, one answer: send() is a little cheaper than sendmsg().
            n = ::send(fd_, buffers[0].iov_base, buffers[0].iov_len, MSG_NOSIGNAL | MSG_DONTWAIT);
        } else {
            msghdr message{};
            message.msg_iov = const_cast<iovec*>(buffers.data());
            message.msg_iovlen = buffers.size();
            n = ::sendmsg(fd_, &message, MSG_NOSIGNAL | MSG_DONTWAIT);
        }
        if (n >= 0) return Io::done(static_cast<std::size_t>(n));
        if (errno == EINTR) continue;
        if (errno == EAGAIN || errno == EWOULDBLOCK) return Io::would_block();
        return Io::failed(errno);
    }
}

void SocketChannel::shutdown_write() {
    if (fd_ >= 0) ::shutdown(fd_, SHUT_WR);
}

void SocketChannel::close() {
    if (fd_ < 0) return;
    ::close(fd_);
    fd_ = -1;
}

PeerIdentity SocketChannel::peer() const {
    PeerIdentity identity;
    socklen_t size = sizeof identity.address;
    if (fd_ >= 0 &&
        ::getpeername(fd_, reinterpret_cast<sockaddr*>(&identity.address), &size) == 0) {
        identity.address_size = size;
    }
    return identity;
}

}  // namespace mblab::transport
