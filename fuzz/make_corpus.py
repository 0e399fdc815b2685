#!/usr/bin/python3
"""Writes the seed corpora of the PDU decoder fuzz targets.

Each file is one PDU (function code first, no MBAP/RTU framing), taken from the unit-test
vectors in tests/unit/protocol/: the examples of the Modbus Application Protocol v1.1b3, the
frames of seeds 000/001/003, values at each limit, and malformed inputs that must be refused.
Run from anywhere: /usr/bin/python3 fuzz/make_corpus.py
"""
import pathlib


def ascii_hex(text):
    return " ".join(f"{ord(c):02X}" for c in text)


def repeat(byte, count):
    return " ".join([byte] * count)


REQUESTS = {
    "app01_read_coils": "01 00 13 00 13",
    "app02_read_discrete_inputs": "02 00 C4 00 16",
    "app03_read_holding": "03 00 6B 00 03",
    "app04_read_input": "04 00 08 00 01",
    "app05_write_coil": "05 00 AC FF 00",
    "app06_write_register": "06 00 01 00 03",
    "app07_exception_status": "07",
    "app08_query_data": "08 00 00 A5 37",
    "app08_restart": "08 00 01 FF 00",
    "app08_ascii_delimiter": "08 00 03 0D 00",
    "app08_bus_messages": "08 00 0B 00 00",
    "app0b_event_counter": "0B",
    "app0c_event_log": "0C",
    "app0f_write_coils": "0F 00 13 00 0A 02 CD 01",
    "app10_write_registers": "10 00 01 00 02 04 00 0A 01 02",
    "app11_server_id": "11",
    "app14_read_file": "14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02",
    "app15_write_file": "15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D",
    "app16_mask_write": "16 00 04 00 F2 00 25",
    "app17_read_write": "17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF",
    "app18_fifo": "18 04 DE",
    "app2b_device_id": "2B 0E 01 00",
    "app2b_device_id_object": "2B 0E 04 02",
    "canopen": "2B 0D 00 01 02 03",
    "seed000_object_messaging": "5B 09 00 00 01 00 01 00 07 00 01",
    "seed000_illegal_function": "25 00 01 00 01",
    "seed000_out_of_range": "03 80 01 00 01",
    "seed000_bad_quantity": "03 00 00 FF FF",
    "seed001_echo_100_words": "08 00 00 " + repeat("5A", 200),
    "seed001_mei_0f": "2B 0F 01 00",
    "limit_read_coils_2000": "01 00 00 07 D0",
    "limit_write_coils_1968": "0F 00 00 07 B0 F6 " + repeat("FF", 246),
    "limit_write_registers_123": "10 00 00 00 7B F6 " + repeat("00", 246),
    "limit_read_write_121": "17 00 00 00 01 00 00 00 79 F2 " + repeat("00", 242),
    "limit_read_file_f5": "14 F5 " + repeat("06 00 01 00 00 00 01", 35),
    "limit_write_file_fb": "15 FB 06 00 01 00 00 00 7A " + repeat("AB", 244),
    "bad_write_coils_count": "0F 00 13 00 0A 03 CD 01 00",
    "bad_read_write_past_ffff": "17 00 00 00 01 FF FF 00 02 04 12 34 56 78",
    "bad_write_file_overrun": "15 0B 06 00 01 00 00 00 03 12 34 56 78",
    "bad_write_file_header": "15 0E 06 00 01 00 00 00 01 12 34 06 00 01 00 00",
    "bad_object_messaging_count": "5B 0A 00 00 01 00 01 00 07 00 01",
    "bare_write_registers": "10",
}

COMPANY = ascii_hex("Company identification")
PRODUCT = ascii_hex("Product code XX")
REVISION = ascii_hex("V2.11")

RESPONSES = {
    "app01_read_coils": "01 03 CD 6B 05",
    "app03_read_holding": "03 06 02 2B 00 00 00 64",
    "app04_read_input": "04 02 00 0A",
    "app05_write_coil": "05 00 AC FF 00",
    "app06_write_register": "06 00 01 00 03",
    "app07_exception_status": "07 6D",
    "app08_query_data": "08 00 00 A5 37",
    "app08_counter": "08 00 0B 01 08",
    "app0b_event_counter": "0B FF FF 01 08",
    "app0c_event_log": "0C 08 00 00 01 08 01 21 20 00",
    "app0f_write_coils": "0F 00 13 00 0A",
    "app10_write_registers": "10 00 01 00 02",
    "app11_server_id": "11 03 2A FF 01",
    "app14_read_file": "14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40",
    "app15_write_file": "15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D",
    "app16_mask_write": "16 00 04 00 F2 00 25",
    "app17_read_write": "17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF",
    "app18_fifo": "18 00 06 00 02 01 B8 12 84",
    "app2b_device_id": f"2B 0E 01 01 00 00 03 00 16 {COMPANY} 01 0F {PRODUCT} 02 05 {REVISION}",
    "app2b_device_id_more": f"2B 0E 01 01 FF 02 02 00 16 {COMPANY} 01 0F {PRODUCT}",
    "app2b_device_id_object": f"2B 0E 04 81 00 00 01 02 05 {REVISION}",
    "canopen": "2B 0D 00 01 02",
    "seed000_object_error": "5B 0B 00 00 01 00 01 00 08 00 16 00 01",
    "seed000_object_data": "5B 0B 00 00 01 00 01 00 08 00 00 00 2A",
    "seed000_exception_01": "A5 01",
    "seed000_exception_02": "83 02",
    "seed000_exception_03": "83 03",
    "seed001_exception_ab": "AB 01",
    "user_defined": "41 01 02",
    "limit_read_coils_250_bytes": "01 FA " + repeat("FF", 250),
    "limit_read_registers_125": "03 FA " + repeat("00", 250),
    "limit_event_log_64": "0C 46 00 00 00 01 00 02 " + repeat("20", 64),
    "limit_fifo_31": "18 00 40 00 1F " + repeat("12", 62),
    "bad_read_coils_count": "01 03 CD 6B",
    "bad_fifo_32": "18 00 42 00 20 " + repeat("12", 64),
    "bad_file_sub_overrun": "14 06 07 06 0D FE 00 20",
    "bad_device_id_count": "2B 0E 01 01 00 00 03 00 01 41",
    "bad_device_id_overrun": "2B 0E 01 01 00 00 01 00 05 41 42",
}


def write(folder, vectors):
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in vectors.items():
        (folder / name).write_bytes(bytes.fromhex(text))


def main():
    corpus = pathlib.Path(__file__).resolve().parent / "corpus"
    write(corpus / "fuzz_request_decode", REQUESTS)
    write(corpus / "fuzz_response_decode", RESPONSES)


if __name__ == "__main__":
    main()
