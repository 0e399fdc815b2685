/* A small libmodbus 3.1.6 client as an application would write one, examined by
 * `mblab conform-client`: reads COUNT holding registers at ADDRESS of UNIT, prints their values
 * and ends with status 1 on any error libmodbus reports (an exception, no answer, a bad frame).
 * One try, a 300 ms response timeout (libmodbus itself never retries a read).
 * Usage: libmodbus_read_client tcp HOST PORT UNIT ADDRESS COUNT
 *        libmodbus_read_client rtu DEVICE BAUD UNIT ADDRESS COUNT   (even parity, 8 data, 1 stop)
 */
#include <errno.h>
#include <modbus.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char** argv) {
    if (argc != 7) {
        fprintf(stderr, "usage: %s tcp|rtu HOST|DEVICE PORT|BAUD UNIT ADDRESS COUNT\n", argv[0]);
        return 2;
    }
    modbus_t* ctx = strcmp(argv[1], "rtu") == 0 ? modbus_new_rtu(argv[2], atoi(argv[3]), 'E', 8, 1)
                                                : modbus_new_tcp(argv[2], atoi(argv[3]));
    if (!ctx) {
        fprintf(stderr, "error: %s\n", modbus_strerror(errno));
        return 1;
    }
    modbus_set_response_timeout(ctx, 0, 300000);
    modbus_set_slave(ctx, atoi(argv[4]));
    if (modbus_connect(ctx) != 0) {
        printf("error: connect: %s\n", modbus_strerror(errno));
        modbus_free(ctx);
        return 1;
    }
    const int count = atoi(argv[6]);
    uint16_t values[125];
    const int read =
        count >= 1 && count <= 125 ? modbus_read_registers(ctx, atoi(argv[5]), count, values) : -1;
    int status = 0;
    if (read != count) {
        printf("error: %s\n", modbus_strerror(errno));
        status = 1;
    } else {
        for (int i = 0; i < count; ++i)
            printf(i ? " %u" : "%u", values[i]);
        printf("\n");
    }
    modbus_close(ctx);
    modbus_free(ctx);
    return status;
}
