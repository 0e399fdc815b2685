"""Compares what `mblab ... --decode bytes` printed with tshark's dissection of the same capture.

  check_client_decode.py TSHARK_FIELDS DECODE_LOG...

TSHARK_FIELDS holds one tab-separated line per Modbus/TCP frame: tcp.payload, mbtcp.trans_id,
mbtcp.prot_id, mbtcp.len, mbtcp.unit_id, modbus.func_code, modbus.reference_num,
modbus.word_cnt, modbus.bit_cnt, modbus.byte_cnt, modbus.exception_code. The decode logs are the
stderr of each mblab run, in the order they ran. Each frame must match in its bytes and in every
field both name; exits 1 with the first difference.
"""
import re
import sys

FIELDS = ["hex", "transaction", "protocol", "length", "unit", "function", "reference",
          "words", "bits", "byte_count", "exception"]
BIT_FUNCTIONS = {1, 2, 15}


def from_tshark(path):
    frames = []
    with open(path) as f:
        for line in f:
            cells = line.rstrip("\n").split("\t")
            cells += [""] * (len(FIELDS) - len(cells))
            frame = dict(zip(FIELDS, cells))
            frame["hex"] = frame["hex"].replace(":", "").upper()
            frames.append({k: v for k, v in frame.items() if v != ""})
    return frames


def from_decode(paths):
    frames = []
    for path in paths:
        with open(path) as f:
            for line in f:
                mark, rest = line[:1], line[1:].strip()
                if mark not in "<>" or not rest:
                    continue
                if re.fullmatch(r"[0-9A-F]{2}( [0-9A-F]{2})*", rest):
                    frames.append({"hex": rest.replace(" ", "")})
                    continue
                frame = frames[-1]
                mbap = re.match(r"MBAP transaction id (\d+) \(0x[0-9A-F]+\), protocol id (\d+), "
                                r"length (\d+), unit id (\d+)", rest)
                if mbap:
                    frame.update(zip(["transaction", "protocol", "length", "unit"], mbap.groups()))
                    continue
                function = re.match(r"function 0x([0-9A-F]{2})", rest)
                frame["function"] = str(int(function.group(1), 16) & 0x7F)
                numbers = {
                    "reference": r"starting address (\d+)",
                    "count": r"quantity (\d+)",
                    "byte_count": r"byte count (\d+)",
                    "exception": r"exception code ([0-9A-F]{2})",
                }
                for name, pattern in numbers.items():
                    found = re.search(pattern, rest)
                    if found:
                        base = 16 if name == "exception" else 10
                        frame[name] = str(int(found.group(1), base))
                if "count" in frame:
                    key = "bits" if int(frame["function"]) in BIT_FUNCTIONS else "words"
                    frame[key] = frame.pop("count")
    return frames


def main():
    wire = from_tshark(sys.argv[1])
    logged = from_decode(sys.argv[2:])
    if len(wire) != len(logged):
        print(f"tshark saw {len(wire)} frames, mblab logged {len(logged)}", file=sys.stderr)
        return 1
    compared = 0
    for index, (seen, said) in enumerate(zip(wire, logged)):
        for key in FIELDS:
            if key in said and key in seen:
                compared += 1
                if said[key] != seen[key]:
                    print(f"frame {index + 1}: {key} is {seen[key]} on the wire, mblab said "
                          f"{said[key]}", file=sys.stderr)
                    return 1
            elif key in said and key != "function":
                print(f"frame {index + 1}: mblab shows {key} {said[key]}, tshark has no such "
                      f"field", file=sys.stderr)
                return 1
    print(f"ok: {len(wire)} frames, {compared} fields agree with tshark")
    return 0


if __name__ == "__main__":
    sys.exit(main())
