"""What both snapshot scripts share: the report of a deck's check and the command line
(`make LTCA CASES OUT` / `check LTCA CASES SNAPSHOT DECK` / `remake LTCA CASES OLD OUT DECK...`)."""
import json
import lzma
import os
import sys


def stress_floor(obj, force_floor):
    """The floor of an object's max_contact_stress_mpa that a force floor gives it (issue 29):
    Hertz's stress goes as sqrt(F), so a force known to force_floor gives the stress to
    sigma / 2 * force_floor / F, with F the same object's max_pin_force_n (at least the force of
    the most stressed pin, so the floor is at most the one that pin's force gives)."""
    sigma, force = obj.get("max_contact_stress_mpa"), obj.get("max_pin_force_n")
    if not isinstance(sigma, (int, float)) or not isinstance(force, (int, float)) or not force > 0.0:
        return 0.0
    return 0.5 * abs(sigma) * force_floor / force


def report(deck, runs, problems, seconds=None):
    """Prints up to 40 mismatches and the deck's line; returns the exit code."""
    for line in problems[:40]:
        print(line)
    if len(problems) > 40:
        print(f"... and {len(problems) - 40} more")
    took = f" in {seconds:.1f} s" if seconds is not None else ""
    print(f"{deck}: {runs} runs{took}, {len(problems)} mismatches")
    return 1 if problems else 0


def remake(records_of, exe, cases, old, out, decks):
    """A recording whose numbers changed on purpose for some decks (tests/snapshot/README.md): the
    runs of `decks` recorded again with exe (records_of, as `make` records them), in the place of
    their old lines; every other line of `old` copied byte for byte, so the other decks keep the
    commit they were recorded at. Writes `out` uncompressed (then: xz -9)."""
    exe = os.path.abspath(exe)
    fresh = {}
    for r in records_of(exe, cases, decks):
        fresh.setdefault(r["deck"], []).append(json.dumps(r, sort_keys=True, separators=(",", ":")) + "\n")
    missing = [d for d in decks if d not in fresh]
    if missing:
        raise SystemExit(f"no runs recorded for {missing}")
    lines, placed, kept = [], set(), 0
    with lzma.open(old, "rt", encoding="utf-8") as f:
        for line in f:
            deck = json.loads(line)["deck"]
            if deck not in fresh:
                lines.append(line)
                kept += 1
            elif deck not in placed:
                lines += fresh[deck]
                placed.add(deck)
    absent = [d for d in decks if d not in placed]
    if absent:
        raise SystemExit(f"{absent} not in {old}: record the whole file with make")
    with open(out, "w", encoding="utf-8") as f:
        f.writelines(lines)
    print(f"{out}: {sum(len(v) for v in fresh.values())} runs of {len(decks)} decks recorded again, "
          f"{kept} lines of {old} kept")


def main(make, check, doc, records_of=None):
    if len(sys.argv) == 5 and sys.argv[1] == "make":
        make(*sys.argv[2:5])
        return 0
    if len(sys.argv) >= 7 and sys.argv[1] == "remake" and records_of is not None:
        remake(records_of, *sys.argv[2:6], sys.argv[6:])
        return 0
    if len(sys.argv) == 6 and sys.argv[1] == "check":
        return check(*sys.argv[2:6])
    print(doc)
    return 2
