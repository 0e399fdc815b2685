"""Checks an `mblab conform --json` report against the verdicts a peer is known to earn.

usage: check_conform_verdicts.py REPORT.json [--others V1,V2] ID=VERDICT[|VERDICT]...

Every ID named must have one of its verdicts; with --others, every case not named must have
one of those. Prints each mismatch and exits 1 if there is any.
"""
import json
import sys


def main(argv):
    report = json.load(open(argv[1]))
    others = None
    expected = {}
    args = argv[2:]
    while args:
        arg = args.pop(0)
        if arg == "--others":
            others = set(args.pop(0).split(","))
            continue
        case_id, verdicts = arg.split("=", 1)
        expected[case_id] = set(verdicts.split("|"))
    seen = {}
    for suite in report["suites"]:
        for case in suite["cases"]:
            seen[case["id"]] = (case["verdict"], case["reason"])
    problems = []
    for case_id, verdicts in expected.items():
        if case_id not in seen:
            problems.append(f"{case_id}: not in the report")
        elif seen[case_id][0] not in verdicts:
            problems.append(f"{case_id}: {seen[case_id][0]} ({seen[case_id][1]}), expected "
                            + " or ".join(sorted(verdicts)))
    if others is not None:
        for case_id, (verdict, reason) in seen.items():
            if case_id not in expected and verdict not in others:
                problems.append(f"{case_id}: {verdict} ({reason}), expected "
                                + " or ".join(sorted(others)))
    for problem in problems:
        print(problem)
    print(f"{len(seen) - len(problems)} passed, {len(problems)} failed")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
