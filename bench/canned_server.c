/* The fastest a Modbus/TCP server can be on this machine: a bare epoll loop that frames requests
 * by their MBAP length and answers each with the same canned FC 03 response for 125 registers
 * (only the transaction id is copied). A ceiling for server benchmarks, not a server.
 *
 *   canned_server PORT      (PORT 0: any; the port is printed as "port=N")
 */
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

enum { kQuantity = 125, kAnswerSize = 9 + 2 * kQuantity, kMaxAdu = 260 };

struct connection {
    int fd;
    uint32_t held;
    uint8_t input[4096];
};

int main(int argc, char** argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: canned_server PORT\n");
        return 2;
    }
    int listener = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    int one = 1;
    setsockopt(listener, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    struct sockaddr_in address = {.sin_family = AF_INET,
                                  .sin_port = htons((uint16_t)atoi(argv[1])),
                                  .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    socklen_t length = sizeof address;
    if (bind(listener, (struct sockaddr*)&address, sizeof address) != 0 ||
        listen(listener, 4096) != 0 ||
        getsockname(listener, (struct sockaddr*)&address, &length) != 0) {
        perror("canned_server");
        return 1;
    }
    printf("port=%d\n", ntohs(address.sin_port));
    fflush(stdout);

    uint8_t answer[kAnswerSize] = {0, 0, 0, 0, 0, 3 + 2 * kQuantity, 1, 3, 2 * kQuantity};
    uint8_t output[4096 / 12 * kAnswerSize + kAnswerSize];
    int epoll = epoll_create1(EPOLL_CLOEXEC);
    struct epoll_event event = {.events = EPOLLIN, .data.ptr = NULL};
    epoll_ctl(epoll, EPOLL_CTL_ADD, listener, &event);
    struct epoll_event events[256];
    for (;;) {
        int n = epoll_wait(epoll, events, 256, -1);
        for (int e = 0; e < n; ++e) {
            struct connection* c = events[e].data.ptr;
            if (!c) {
                int fd;
                while ((fd = accept4(listener, NULL, NULL, SOCK_NONBLOCK | SOCK_CLOEXEC)) >= 0) {
                    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
                    c = calloc(1, sizeof *c);
                    c->fd = fd;
                    struct epoll_event add = {.events = EPOLLIN, .data.ptr = c};
                    epoll_ctl(epoll, EPOLL_CTL_ADD, fd, &add);
                }
                continue;
            }
            ssize_t got = recv(c->fd, c->input + c->held, sizeof c->input - c->held, 0);
            if (got <= 0) {
                close(c->fd);
                free(c);
                continue;
            }
            c->held += (uint32_t)got;
            uint32_t at = 0;
            size_t out = 0;
            while (c->held - at >= 7) {
                uint32_t frame = 6u + (uint32_t)(c->input[at + 4] << 8 | c->input[at + 5]);
                if (frame > kMaxAdu) {
                    c->held = at = 0; /* not Modbus: drop everything */
                    break;
                }
                if (c->held - at < frame) break;
                answer[0] = c->input[at];
                answer[1] = c->input[at + 1];
                memcpy(output + out, answer, kAnswerSize);
                out += kAnswerSize;
                at += frame;
            }
            memmove(c->input, c->input + at, c->held - at);
            c->held -= at;
            if (out) send(c->fd, output, out, MSG_NOSIGNAL);
        }
    }
}
