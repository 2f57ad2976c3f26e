"""Tilting table: the table angle at which a cube tips (mu = 1.5, it cannot slide first)
and at which it slides (mu = 0.5), at 4 and 8 particles across, for the contact's
defaults and for any &contact variables given; the harness of tests/test_tilt.py.

    .venv/bin/python tools/tilt_table.py                    # the defaults (stiff core)
    .venv/bin/python tools/tilt_table.py --contact "core_overlap = 0.0"   # no core (before it)

Tipping is the cube turning by 2 degrees against the table (the test's bar), and the
angle where it has turned by 15 degrees is printed too (a soft contact lets a cube lean
by 2 degrees long before it falls); sliding is its moving by 0.02 of its side along it; the table turns at --rate degrees per second (default 1) from
--span degrees below 47 (tipping) and from 16.57 to 29.57 degrees (sliding; atan 0.5 = 26.57).
"""
from __future__ import annotations

import argparse
import math
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from test_tilt import onset, tilt_table  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--contact", default="", help="variables of a &contact group, e.g. \"core_overlap = 0.0\"")
    ap.add_argument("--rate", type=float, default=1.0, help="the table's turning rate [deg/s]")
    ap.add_argument("--span", type=float, default=25.0, help="degrees the table turns in each run")
    ap.add_argument("--binary", default=str(ROOT / "build" / "mbsph"))
    a = ap.parse_args()
    print(f"&contact {a.contact or '(defaults)'}; table at {a.rate:g} deg/s")
    print("| across | turns 2 deg at (45) | turns 15 deg at | slides at (26.57) |")
    print("|---|---|---|---|")
    for n in (4, 8):
        with tempfile.TemporaryDirectory() as t1, tempfile.TemporaryDirectory() as t2:
            ang, turn, _ = tilt_table(Path(t1), n, 1.5, 47.0 - a.span, 47.0, a.rate, a.contact, a.binary)
            tip, fall = onset(ang, turn, 2.0), onset(ang, turn, 15.0)
            lo = math.degrees(math.atan(0.5))
            ang, turn, along = tilt_table(Path(t2), n, 0.5, lo - 10.0, lo + 3.0, a.rate, a.contact,
                                          a.binary)
            slide = onset(ang, along, 0.02)
            tipped = onset(ang, turn, 2.0)
            note = f" (tipped at {tipped:.2f} first)" if tipped < slide else ""
        print(f"| {n} | {tip:.2f} | {fall:.2f} | {slide:.2f}{note} |")


if __name__ == "__main__":
    main()
