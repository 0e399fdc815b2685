/* libmodbus's client against `mblab serve`: every function libmodbus has, each write read back.
 * Usage: libmodbus_client PORT. Exits non-zero on the first mismatch. */
#include <errno.h>
#include <modbus.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int checks = 0;

static void fail(const char* what) {
    fprintf(stderr, "FAIL %s: %s\n", what, modbus_strerror(errno));
    exit(1);
}

static void expect(const char* what, int ok) {
    ++checks;
    if (!ok) {
        fprintf(stderr, "FAIL %s\n", what);
        exit(1);
    }
}

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    modbus_t* ctx = modbus_new_tcp("127.0.0.1", atoi(argv[1]));
    if (!ctx) fail("modbus_new_tcp");
    modbus_set_response_timeout(ctx, 5, 0);
    modbus_set_slave(ctx, 1);
    if (modbus_connect(ctx) != 0) fail("connect");

    /* 05, 0F, 01 */
    if (modbus_write_bit(ctx, 300, 1) != 1) fail("write bit");
    const uint8_t bits_out[] = {0, 1, 1, 0, 1, 0, 0, 1, 1};
    if (modbus_write_bits(ctx, 301, 9, bits_out) != 9) fail("write bits");
    uint8_t bits_in[10];
    if (modbus_read_bits(ctx, 300, 10, bits_in) != 10) fail("read bits");
    expect("coil 300", bits_in[0] == 1);
    expect("coils 301..309", memcmp(bits_in + 1, bits_out, 9) == 0);
    /* 02: all off in the reference profile */
    if (modbus_read_input_bits(ctx, 0, 10, bits_in) != 10) fail("read input bits");
    for (int i = 0; i < 10; ++i)
        expect("discrete input", bits_in[i] == 0);

    /* 06, 10, 03 */
    if (modbus_write_register(ctx, 400, 0xCAFE) != 1) fail("write register");
    const uint16_t regs_out[] = {0x0001, 0x0203, 0xFFFF, 0x8000};
    if (modbus_write_registers(ctx, 401, 4, regs_out) != 4) fail("write registers");
    uint16_t regs_in[125];
    if (modbus_read_registers(ctx, 400, 5, regs_in) != 5) fail("read registers");
    expect("holding 400", regs_in[0] == 0xCAFE);
    expect("holding 401..404", memcmp(regs_in + 1, regs_out, sizeof regs_out) == 0);
    /* The most a read may ask for. */
    if (modbus_read_registers(ctx, 0x1000, 125, regs_in) != 125) fail("read 125 registers");
    /* 04 */
    if (modbus_read_input_registers(ctx, 0, 4, regs_in) != 4) fail("read input registers");
    for (int i = 0; i < 4; ++i)
        expect("input register", regs_in[i] == 0);

    /* 16: (0x0012 AND 0x00F2) OR (0x0025 AND NOT 0x00F2) = 0x0017 */
    if (modbus_write_register(ctx, 410, 0x0012) != 1) fail("write register");
    if (modbus_mask_write_register(ctx, 410, 0x00F2, 0x0025) != 1) fail("mask write");
    if (modbus_read_registers(ctx, 410, 1, regs_in) != 1) fail("read register");
    expect("mask write result", regs_in[0] == 0x0017);

    /* 17: the write happens before the read */
    const uint16_t rw_out[] = {0x1111, 0x2222, 0x3333};
    if (modbus_write_and_read_registers(ctx, 420, 3, rw_out, 419, 5, regs_in) != 5) {
        fail("write and read registers");
    }
    expect("read/write 420..422", memcmp(regs_in + 1, rw_out, sizeof rw_out) == 0);

    /* 11 */
    uint8_t id[MODBUS_MAX_PDU_LENGTH];
    int id_length = modbus_report_slave_id(ctx, sizeof id, id);
    if (id_length < 0) fail("report slave id");
    expect("server id and run indicator", id_length >= 6 && memcmp(id, "mblab\xff", 6) == 0);

    /* An exception: a range past 0xFFFF is "illegal data address". */
    errno = 0;
    expect("exception 02",
           modbus_read_registers(ctx, 0xFFFF, 2, regs_in) == -1 && errno == EMBXILADD);
    /* Unit ids 0 and 0xFF reach the same unit. */
    modbus_set_slave(ctx, 0xFF);
    if (modbus_read_registers(ctx, 400, 1, regs_in) != 1) fail("read unit 255");
    expect("unit 255", regs_in[0] == 0xCAFE);

    modbus_close(ctx);
    modbus_free(ctx);
    printf("libmodbus: %d checks passed\n", checks);
    return 0;
}
