/* A Modbus/TCP server built on Debian's libmodbus that serves many clients at once, the way
 * libmodbus's documentation and its many-clients example do it: one select() loop over the
 * listener and every connection, modbus_set_socket() to the ready one, then modbus_receive() and
 * modbus_reply(). modbus_reply() writes the answer with a blocking send(): a client that sends
 * requests and never reads the answers fills its socket's send buffer, and the one loop then waits
 * in send() for it, serving nobody else.
 *
 * Listens on 127.0.0.1 on an ephemeral port, prints the port on the first line of stdout, and
 * exits by itself after the number of seconds given as its first argument (default 120). */
#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

int main(int argc, char** argv) {
    unsigned lifetime = argc > 1 ? (unsigned)atoi(argv[1]) : 120;
    alarm(lifetime);
    modbus_t* ctx = modbus_new_tcp("127.0.0.1", 0);
    modbus_mapping_t* map = modbus_mapping_new(65536, 65536, 65536, 65536);
    if (ctx == NULL || map == NULL) return 1;
    int listener = modbus_tcp_listen(ctx, 64);
    if (listener < 0) return 1;
    struct sockaddr_in address;
    socklen_t length = sizeof address;
    if (getsockname(listener, (struct sockaddr*)&address, &length) != 0) return 1;
    printf("%u\n", ntohs(address.sin_port));
    fflush(stdout);
    fd_set open_set;
    FD_ZERO(&open_set);
    FD_SET(listener, &open_set);
    int highest = listener;
    uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
    for (;;) {
        fd_set ready = open_set;
        if (select(highest + 1, &ready, NULL, NULL, NULL) < 0) return 1;
        for (int fd = 0; fd <= highest; ++fd) {
            if (!FD_ISSET(fd, &ready)) continue;
            if (fd == listener) {
                int client = accept(listener, NULL, NULL);
                if (client < 0) continue;
                /* select() cannot watch descriptors past FD_SETSIZE. */
                if (client >= FD_SETSIZE) {
                    close(client);
                    continue;
                }
                FD_SET(client, &open_set);
                if (client > highest) highest = client;
                continue;
            }
            modbus_set_socket(ctx, fd);
            int size = modbus_receive(ctx, query);
            if (size > 0) {
                modbus_reply(ctx, query, size, map);
            } else if (size < 0) {
                close(fd);
                FD_CLR(fd, &open_set);
            }
        }
    }
}
