#!/usr/bin/env python3
"""Issue 55: the suite's time, test by test, measured in CPU work.

    suite_times.py start RECORD_DIR
    suite_times.py report CTEST BUILD_DIR RECORD_DIR BUDGET_TEST_S BUDGET_FAST_S [REPORT_FILE]

Every test of tests/CMakeLists.txt runs through ltca-test-meter (tests/cpu_meter.cpp), which
writes the CPU seconds (user + system, the test and every process it waited for) and the wall
seconds of the test to RECORD_DIR. `start` empties RECORD_DIR: it is the setup of the ctest fixture
`ltca_suite`, which every test requires, so it runs first. `report` is that fixture's cleanup, so
it runs after every other test of the run (ctest orders a fixture's cleanup last). It reads the
tests ctest knows (`ctest --show-only=json-v1`) and the records of this run, prints the ten tests of
most CPU time with their share of the run's CPU time (and their wall time, for reference), writes
the same to REPORT_FILE (.ci/run prints it), and fails when

- a test carries neither or both of the labels `fast` and `slow` (the release test preset runs the
  `fast` ones, CI's `heavy` stage the `slow` ones: a test with neither would run nowhere);
- a test does not run through ltca-test-meter (register it with ${LTCA_METER} first, as the others);
- a test labelled `fast` took more than BUDGET_TEST_S CPU seconds: it belongs in `slow`
  (tests/CMakeLists.txt, LTCA_SLOW_TESTS), or it should do less work;
- the `fast` tests of the run took more than BUDGET_FAST_S CPU seconds together: the release
  preset's suite would no longer fit its time on two cores.

CPU time, not wall time: another process on the machine lengthens a test's wall time but takes
none of its CPU time (it can cost some through shared caches and hyperthreads, far within the
budgets' margins), so the verdict is on the work the tests do, not on the machine's load. A run
of only some tests (ctest -R, -L) is judged on the tests it ran.
"""
import json
import os
import shutil
import subprocess
import sys

FAST, SLOW = "fast", "slow"
START, REPORT = "start", "report"


def read_records(record_dir):
    """{tuple(command line): (cpu seconds, wall seconds)} of the tests of this run."""
    records = {}
    if not os.path.isdir(record_dir):
        return records
    for name in os.listdir(record_dir):
        if not name.endswith(".tsv"):
            continue
        with open(os.path.join(record_dir, name), "rb") as f:
            cpu, wall, argv = f.read().split(b"\t", 2)
        records[tuple(a.decode("utf-8", "replace") for a in argv.split(b"\0"))] = (float(cpu), float(wall))
    return records


def labels_of(test):
    for p in test.get("properties", []):
        if p.get("name") == "LABELS":
            return list(p.get("value", []))
    return []


def fixture_role(test):
    for p in test.get("properties", []):
        if p.get("name") in ("FIXTURES_SETUP", "FIXTURES_CLEANUP") and "ltca_suite" in p.get("value", []):
            return p["name"]
    return None


def report(ctest, build_dir, record_dir, budget_test, budget_fast, report_file=None):
    shown = subprocess.run([ctest, "--test-dir", build_dir, "--show-only=json-v1"], stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True, check=True)
    tests = json.loads(shown.stdout)["tests"]
    records = read_records(record_dir)
    problems = []
    ran = []  # (cpu, wall, name, label)
    unlabelled, unmetered = [], []
    for t in tests:
        labels = labels_of(t)
        kinds = [l for l in labels if l in (FAST, SLOW)]
        if len(kinds) != 1:
            unlabelled.append(f"{t['name']} (labels: {', '.join(labels) or 'none'})")
        if fixture_role(t):
            continue  # this script itself: not metered
        command = t.get("command", [])
        if len(command) < 3 or os.path.basename(command[0]) != "ltca-test-meter":
            unmetered.append(t["name"])
            continue
        rec = records.get(tuple(command[2:]))
        if rec is not None:
            ran.append((rec[0], rec[1], t["name"], kinds[0] if len(kinds) == 1 else "?"))
    if unlabelled:
        problems.append(f"{len(unlabelled)} tests carry neither or both of the labels fast and slow "
                        "(tests/CMakeLists.txt labels every test):\n    " + "\n    ".join(unlabelled[:20]))
    if unmetered:
        problems.append(f"{len(unmetered)} tests do not run through ltca-test-meter (add_test(NAME ... COMMAND "
                        "${LTCA_METER} ...) in tests/CMakeLists.txt):\n    " + "\n    ".join(unmetered[:20]))

    total_cpu = sum(r[0] for r in ran) or 1e-9
    total_wall = sum(r[1] for r in ran) or 1e-9
    fast_cpu = sum(r[0] for r in ran if r[3] == FAST)
    ran.sort(reverse=True)
    lines = [f"{len(ran)} of {len(tests)} tests ran ({sum(1 for r in ran if r[3] == FAST)} fast, "
             f"{sum(1 for r in ran if r[3] == SLOW)} slow): {total_cpu:.1f} s of CPU (fast ones {fast_cpu:.1f} s, "
             f"budget {budget_fast:g} s), {total_wall:.1f} s of wall time summed over the tests",
             "the ten tests of most CPU time (CPU s, share of the run's CPU, wall s, label, test):"]
    for cpu, wall, name, label in ran[:10]:
        lines.append(f"  {cpu:8.1f} {100 * cpu / total_cpu:5.1f} % {wall:8.1f}  {label:4}  {name}")
    over = [r for r in ran if r[3] == FAST and r[0] > budget_test]
    if over:
        problems.append(f"{len(over)} tests labelled fast took more than {budget_test:g} s of CPU each "
                        "(label them slow in tests/CMakeLists.txt, LTCA_SLOW_TESTS, or make them do less):\n    " +
                        "\n    ".join(f"{cpu:.1f} s  {name}" for cpu, _, name, _ in over))
    if fast_cpu > budget_fast:
        problems.append(f"the fast tests took {fast_cpu:.1f} s of CPU together, over the release suite's budget of "
                        f"{budget_fast:g} s (label the heaviest slow, or make them do less)")
    if not ran:
        problems.append(f"no test left a record in {record_dir}: ltca-test-meter did not run")
    text = "\n".join(lines + [f"FAIL {p}" for p in problems]) + "\n"
    print(text, end="")
    if report_file:
        with open(report_file, "w", encoding="utf-8") as f:
            f.write(text)
    return 1 if problems else 0


def main(argv):
    if len(argv) == 3 and argv[1] == START:
        shutil.rmtree(argv[2], ignore_errors=True)
        os.makedirs(argv[2])
        print(f"CPU records of this run: {argv[2]}")
        return 0
    if len(argv) in (7, 8) and argv[1] == REPORT:
        return report(argv[2], argv[3], argv[4], float(argv[5]), float(argv[6]), argv[7] if len(argv) == 8 else None)
    print(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
