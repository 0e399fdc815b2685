/* The yardstick for `mblab load`'s own ceiling: the least a Modbus/TCP load client can do.
 * Each connection keeps PIPELINE copies of one FC 03 request in flight and sends the next as
 * each whole answer arrives (closed loop), on one thread with level-triggered epoll. It checks
 * nothing but the answer's length, and prints answers/s.
 *
 *   load_epoll_client HOST PORT CONNECTIONS SECONDS [QUANTITY] [PIPELINE]
 *
 * Built by bench/run_load_bench.sh with cc; not part of the CMake build. */
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

struct conn {
    int fd;
    unsigned char in[8192];
    size_t held;
};

static unsigned char request[12];
static size_t answer_size;

static double now_s(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec / 1e9;
}

static int send_requests(int fd, int count) {
    unsigned char out[12 * 64];
    for (int i = 0; i < count; ++i)
        memcpy(out + 12 * (size_t)i, request, 12);
    size_t total = 12 * (size_t)count, done = 0;
    while (done < total) {
        ssize_t n = send(fd, out + done, total - done, MSG_NOSIGNAL);
        if (n <= 0) return -1;
        done += (size_t)n;
    }
    return 0;
}

int main(int argc, char** argv) {
    if (argc < 5) {
        fprintf(stderr, "usage: %s HOST PORT CONNECTIONS SECONDS [QUANTITY] [PIPELINE]\n", argv[0]);
        return 2;
    }
    const char* host = argv[1];
    int port = atoi(argv[2]);
    int connections = atoi(argv[3]);
    double seconds = atof(argv[4]);
    int quantity = argc > 5 ? atoi(argv[5]) : 125;
    int pipeline = argc > 6 ? atoi(argv[6]) : 1;
    if (connections < 1 || quantity < 1 || quantity > 125 || pipeline < 1 || pipeline > 64) {
        fprintf(stderr, "bad arguments\n");
        return 2;
    }
    struct rlimit limit;
    if (getrlimit(RLIMIT_NOFILE, &limit) == 0) {
        limit.rlim_cur = limit.rlim_max;
        setrlimit(RLIMIT_NOFILE, &limit);
    }
    /* Transaction id 0, protocol 0, length 6, unit 0, FC 03, address 0, quantity. */
    unsigned char r[12] = {
        0, 0, 0, 0, 0, 6, 0, 3, 0, 0, (unsigned char)(quantity >> 8), (unsigned char)quantity};
    memcpy(request, r, sizeof r);
    answer_size = 9 + 2 * (size_t)quantity;

    struct sockaddr_in address;
    memset(&address, 0, sizeof address);
    address.sin_family = AF_INET;
    address.sin_port = htons((unsigned short)port);
    if (inet_pton(AF_INET, host, &address.sin_addr) != 1) {
        fprintf(stderr, "bad host %s\n", host);
        return 2;
    }
    int ep = epoll_create1(0);
    struct conn* conns = calloc((size_t)connections, sizeof *conns);
    for (int i = 0; i < connections; ++i) {
        int fd = socket(AF_INET, SOCK_STREAM, 0);
        int one = 1;
        setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        if (connect(fd, (struct sockaddr*)&address, sizeof address) != 0) {
            perror("connect");
            return 2;
        }
        conns[i].fd = fd;
        struct epoll_event ev = {.events = EPOLLIN, .data.ptr = &conns[i]};
        epoll_ctl(ep, EPOLL_CTL_ADD, fd, &ev);
    }
    for (int i = 0; i < connections; ++i) {
        if (send_requests(conns[i].fd, pipeline) != 0) return 1;
    }

    unsigned long long answers = 0;
    const double start = now_s(), end = start + seconds;
    struct epoll_event events[256];
    while (now_s() < end) {
        int n = epoll_wait(ep, events, 256, 10);
        for (int i = 0; i < n; ++i) {
            struct conn* c = events[i].data.ptr;
            ssize_t got = recv(c->fd, c->in + c->held, sizeof c->in - c->held, 0);
            if (got <= 0) {
                fprintf(stderr, "connection lost\n");
                return 1;
            }
            c->held += (size_t)got;
            int whole = 0;
            while (c->held >= answer_size) {
                memmove(c->in, c->in + answer_size, c->held - answer_size);
                c->held -= answer_size;
                ++whole;
            }
            answers += (unsigned long long)whole;
            if (whole > 0 && send_requests(c->fd, whole) != 0) return 1;
        }
    }
    const double elapsed = now_s() - start;
    printf("%.0f\n", (double)answers / elapsed);
    return 0;
}
