#include "security/queue_bio.hpp"

#include <algorithm>
#include <cstring>
#include <new>

namespace mblab::security {

void ByteQueue::append(std::span<const std::uint8_t> more) {
    if (more.empty()) return;
    // Taken bytes are forgotten before the queue grows, not on every take: a record read in
    // several parts moves nothing until the next one comes.
    if (head_ > 0) {
        bytes_.erase(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(head_));
        head_ = 0;
    }
    bytes_.insert(bytes_.end(), more.begin(), more.end());
}

std::size_t ByteQueue::take(std::span<std::uint8_t> out) {
    const std::size_t count = std::min(out.size(), size());
    if (count > 0) std::memcpy(out.data(), bytes_.data() + head_, count);
    drop(count);
    return count;
}

void ByteQueue::drop(std::size_t count) {
    head_ += std::min(count, size());
    if (head_ == bytes_.size()) {
        bytes_.clear();
        head_ = 0;
    }
}

void ByteQueue::release() {
    if (empty()) std::vector<std::uint8_t>().swap(bytes_);
}

namespace {

ByteQueue& queue_of(BIO* bio) {
    return *static_cast<ByteQueue*>(BIO_get_data(bio));
}

int write_ex(BIO* bio, const char* data, std::size_t size, std::size_t* written) {
    BIO_clear_retry_flags(bio);
    *written = 0;
    // No exception may cross OpenSSL's C frames: out of memory is a failed write, as a memory
    // BIO reports it.
    try {
        queue_of(bio).append({reinterpret_cast<const std::uint8_t*>(data), size});
    } catch (const std::bad_alloc&) {
        return 0;
    }
    *written = size;
    return 1;
}

// -1 and "retry" when empty, as a memory BIO made to return -1 at its end says it: TLS then waits
// for more (SSL_ERROR_WANT_READ) instead of taking the connection for ended.
int read(BIO* bio, char* data, int size) {
    BIO_clear_retry_flags(bio);
    if (size <= 0) return 0;
    const std::size_t got =
        queue_of(bio).take({reinterpret_cast<std::uint8_t*>(data), static_cast<std::size_t>(size)});
    if (got > 0) return static_cast<int>(got);
    BIO_set_retry_read(bio);
    return -1;
}

long control(BIO* bio, int command, long number, void*) {
    switch (command) {
        case BIO_CTRL_PENDING:
        case BIO_CTRL_WPENDING:
            return static_cast<long>(queue_of(bio).size());
        case BIO_CTRL_FLUSH:
            return 1;
        case BIO_CTRL_GET_CLOSE:
            return BIO_get_shutdown(bio);
        case BIO_CTRL_SET_CLOSE:
            BIO_set_shutdown(bio, static_cast<int>(number));
            return 1;
        default:
            // Not a socket, a datagram, kTLS or a filter: OpenSSL falls back on its own.
            return 0;
    }
}

int create(BIO* bio) {
    BIO_set_init(bio, 1);
    return 1;
}

const BIO_METHOD* queue_method() {
    static BIO_METHOD* const method = [] {
        BIO_METHOD* made =
            BIO_meth_new(BIO_get_new_index() | BIO_TYPE_SOURCE_SINK, "mblab byte queue");
        if (!made) return made;
        BIO_meth_set_write_ex(made, write_ex);
        BIO_meth_set_read(made, read);
        BIO_meth_set_ctrl(made, control);
        BIO_meth_set_create(made, create);
        return made;
    }();
    return method;
}

}  // namespace

BIO* new_queue_bio(ByteQueue& queue) {
    const BIO_METHOD* method = queue_method();
    if (!method) return nullptr;
    BIO* bio = BIO_new(method);
    if (bio) BIO_set_data(bio, &queue);
    return bio;
}

}  // namespace mblab::security
