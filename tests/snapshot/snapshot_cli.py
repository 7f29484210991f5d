"""What both snapshot scripts share: the report of a deck's check and the command line
(`make LTCA CASES OUT` / `check LTCA CASES SNAPSHOT DECK`)."""
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


def main(make, check, doc):
    if len(sys.argv) == 5 and sys.argv[1] == "make":
        make(*sys.argv[2:5])
        return 0
    if len(sys.argv) == 6 and sys.argv[1] == "check":
        return check(*sys.argv[2:6])
    print(doc)
    return 2
