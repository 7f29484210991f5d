"""What both snapshot scripts share: the report of a deck's check and the command line
(`make LTCA CASES OUT` / `check LTCA CASES SNAPSHOT DECK`)."""
import sys


def report(deck, runs, problems, seconds=None):
    """Prints up to 40 mismatches and the deck's line; returns the exit code."""
    for line in problems[:40]:
        print(line)
    if len(problems) > 40:
        print(f"... and {len(problems) - 40} more")
    took = f" in {seconds:.1f} s" if seconds is not None else ""
    print(f"{deck}: {runs} runs{took}, {len(problems)} mismatches")
    return 1 if problems else 0


def main(make, check, doc):
    if len(sys.argv) == 5 and sys.argv[1] == "make":
        make(*sys.argv[2:5])
        return 0
    if len(sys.argv) == 6 and sys.argv[1] == "check":
        return check(*sys.argv[2:6])
    print(doc)
    return 2
