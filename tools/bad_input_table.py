"""The table of bad cases tried, for doc/input.md: every case of tests/test_bad_input.py's
CASES and SYNTAX run through the solver, with its exit code and message.

    .venv/bin/python tools/bad_input_table.py [--binary build/mbsph] > table.md
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import test_bad_input as t  # noqa: E402


def message(binary: Path, text: str) -> tuple[int, str]:
    with tempfile.TemporaryDirectory() as d:
        (Path(d) / "case.nml").write_text(text)
        proc = subprocess.run([str(binary), "case.nml"], cwd=d, capture_output=True, text=True, timeout=120,
                              stdin=subprocess.DEVNULL)
    lines = [ln for ln in proc.stderr.splitlines() if ln.startswith("mbsph: error")]
    return proc.returncode, lines[0] if lines else "(no message)"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--binary", type=Path, default=ROOT / "build" / "mbsph")
    args = ap.parse_args()
    print("| # | case (tests/test_bad_input.py) | exit | message |")
    print("|---|---|---|---|")
    k = 0
    for name, bad in list(t.CASES.items()) + list(t.SYNTAX.items()):
        k += 1
        code, msg = message(args.binary, bad.text)
        print(f"| {k} | `{name}` | {code} | `{msg.replace('|', '/')}` |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
