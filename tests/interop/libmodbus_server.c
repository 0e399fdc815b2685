/* A Modbus/TCP server built on Debian's libmodbus, for mblab's conformance interop test.
 *
 * Listens on 127.0.0.1 on an ephemeral port, prints the port on the first line of stdout, and
 * serves 65536 coils, discrete inputs, holding and input registers through modbus_reply(), the
 * way libmodbus's own example servers do: one connection at a time. It exits by itself after
 * the number of seconds given as its first argument (default 120) so a failed test cannot leave
 * it running. */
#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <unistd.h>

int main(int argc, char** argv) {
    unsigned lifetime = argc > 1 ? (unsigned)atoi(argv[1]) : 120;
    alarm(lifetime);
    modbus_t* ctx = modbus_new_tcp("127.0.0.1", 0);
    modbus_mapping_t* map = modbus_mapping_new(65536, 65536, 65536, 65536);
    if (ctx == NULL || map == NULL) return 1;
    /* On a request it cannot take (an unknown function, a bad length) modbus_reply sleeps for the
     * response timeout before it answers and flushes; 100 ms instead of the default 500 ms keeps
     * that behaviour and shortens the tests that meet it many times. */
    modbus_set_response_timeout(ctx, 0, 100000);
    int listener = modbus_tcp_listen(ctx, 1);
    if (listener < 0) return 1;
    struct sockaddr_in address;
    socklen_t length = sizeof address;
    if (getsockname(listener, (struct sockaddr*)&address, &length) != 0) return 1;
    printf("%u\n", ntohs(address.sin_port));
    fflush(stdout);
    uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
    for (;;) {
        int client = modbus_tcp_accept(ctx, &listener);
        if (client < 0) return 1;
        for (;;) {
            int size = modbus_receive(ctx, query);
            if (size > 0) {
                modbus_reply(ctx, query, size, map);
            } else if (size < 0) {
                break;
            }
        }
        close(client);
    }
}
