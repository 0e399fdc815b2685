/* Closed-loop Modbus/TCP load generator: N connections on one epoll thread, each with one FC 03
 * request for 125 registers in flight at a time. Prints requests per second and latency
 * percentiles as one line of key=value pairs.
 *
 *   server_load HOST PORT CONNECTIONS SECONDS        load test
 *   server_load HOST PORT CONNECTIONS --idle FILE    open CONNECTIONS idle connections, write
 *                                                    "ready" to FILE, hold them until SIGTERM
 */
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

enum { kQuantity = 125, kAnswerSize = 9 + 2 * kQuantity, kHistogramUs = 1000000 };

struct connection {
    int fd;
    uint16_t tid;
    uint32_t received;
    uint64_t sent_ns;
    uint8_t buffer[kAnswerSize];
};

static uint64_t now_ns(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (uint64_t)t.tv_sec * 1000000000u + (uint64_t)t.tv_nsec;
}

static int open_connection(const struct sockaddr_in* address) {
    int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return -1;
    if (connect(fd, (const struct sockaddr*)address, sizeof *address) != 0) {
        close(fd);
        return -1;
    }
    int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    fcntl(fd, F_SETFL, O_NONBLOCK);
    return fd;
}

static int send_request(struct connection* c) {
    uint8_t request[12] = {0, 0, 0, 0, 0, 6, 1, 3, 0, 0, 0, kQuantity};
    c->tid++;
    request[0] = (uint8_t)(c->tid >> 8);
    request[1] = (uint8_t)c->tid;
    c->received = 0;
    c->sent_ns = now_ns();
    return send(c->fd, request, sizeof request, MSG_NOSIGNAL) == (ssize_t)sizeof request ? 0 : -1;
}

static volatile sig_atomic_t stop_idle = 0;
static void on_term(int signal_number) {
    (void)signal_number;
    stop_idle = 1;
}

static int hold_idle(const struct sockaddr_in* address, int count, const char* ready_file) {
    int* fds = calloc((size_t)count, sizeof *fds);
    for (int i = 0; i < count; ++i) {
        fds[i] = open_connection(address);
        if (fds[i] < 0) {
            fprintf(stderr, "server_load: connection %d failed: %s\n", i, strerror(errno));
            return 1;
        }
    }
    signal(SIGTERM, on_term);
    FILE* ready = fopen(ready_file, "w");
    if (ready) {
        fputs("ready\n", ready);
        fclose(ready);
    }
    while (!stop_idle)
        pause();
    for (int i = 0; i < count; ++i)
        close(fds[i]);
    free(fds);
    return 0;
}

int main(int argc, char** argv) {
    if (argc != 5 && argc != 6) {
        fprintf(stderr, "usage: server_load HOST PORT CONNECTIONS SECONDS|--idle FILE\n");
        return 2;
    }
    struct sockaddr_in address = {.sin_family = AF_INET,
                                  .sin_port = htons((uint16_t)atoi(argv[2]))};
    inet_pton(AF_INET, argv[1], &address.sin_addr);
    int count = atoi(argv[3]);
    if (argc == 6 && strcmp(argv[4], "--idle") == 0) return hold_idle(&address, count, argv[5]);
    double seconds = atof(argv[4]);

    struct connection* connections = calloc((size_t)count, sizeof *connections);
    uint32_t* histogram = calloc(kHistogramUs + 1, sizeof *histogram);
    int epoll = epoll_create1(EPOLL_CLOEXEC);
    for (int i = 0; i < count; ++i) {
        connections[i].fd = open_connection(&address);
        if (connections[i].fd < 0) {
            fprintf(stderr, "server_load: connection %d failed: %s\n", i, strerror(errno));
            return 1;
        }
        struct epoll_event event = {.events = EPOLLIN, .data.ptr = &connections[i]};
        epoll_ctl(epoll, EPOLL_CTL_ADD, connections[i].fd, &event);
    }
    for (int i = 0; i < count; ++i)
        send_request(&connections[i]);

    /* A warm-up of a tenth of the run is not counted. */
    uint64_t start = now_ns();
    uint64_t measure_from = start + (uint64_t)(seconds * 0.1e9);
    uint64_t end = start + (uint64_t)(seconds * 1.1e9);
    uint64_t requests = 0, errors = 0;
    struct epoll_event events[256];
    for (;;) {
        uint64_t now = now_ns();
        if (now >= end) break;
        int n = epoll_wait(epoll, events, 256, 100);
        for (int e = 0; e < n; ++e) {
            struct connection* c = events[e].data.ptr;
            ssize_t got = recv(c->fd, c->buffer + c->received, kAnswerSize - c->received, 0);
            if (got <= 0) {
                if (got < 0 && errno == EAGAIN) continue;
                fprintf(stderr, "server_load: the server closed a connection\n");
                return 1;
            }
            c->received += (uint32_t)got;
            if (c->received < kAnswerSize) continue;
            uint64_t done = now_ns();
            if (c->buffer[0] != (uint8_t)(c->tid >> 8) || c->buffer[1] != (uint8_t)c->tid ||
                c->buffer[7] != 3 || c->buffer[8] != 2 * kQuantity) {
                errors++;
            }
            if (c->sent_ns >= measure_from) {
                uint64_t us = (done - c->sent_ns) / 1000;
                histogram[us > kHistogramUs ? kHistogramUs : us]++;
                requests++;
            }
            if (send_request(c) != 0) errors++;
        }
    }
    double measured = (double)(now_ns() - measure_from) / 1e9;
    uint64_t p50 = 0, p99 = 0, seen = 0;
    for (uint64_t us = 0; us <= kHistogramUs; ++us) {
        seen += histogram[us];
        if (!p50 && seen * 2 >= requests) p50 = us ? us : 1;
        if (!p99 && seen * 100 >= requests * 99) {
            p99 = us ? us : 1;
            break;
        }
    }
    printf("connections=%d requests=%llu rps=%.0f p50_us=%llu p99_us=%llu errors=%llu\n", count,
           (unsigned long long)requests, (double)requests / measured, (unsigned long long)p50,
           (unsigned long long)p99, (unsigned long long)errors);
    return errors ? 1 : 0;
}
