"""``mbsph-post TOOL [ARGS]`` (or ``python -m post TOOL [ARGS]``): the post tools by name.

``pip install -e .`` in the repository root installs the package ``post`` and this
command; ``mbsph-post waves OUT`` is then ``python -m post.waves OUT`` from any folder.
"""

from __future__ import annotations

import importlib
import sys
from typing import Sequence

from .cli import EXIT_INPUT, run

#: the tools, each a module of this package with a main(); what each does
TOOLS = {
    "waves": "wave heights, periods, spectra and reflection from gauges.csv",
    "armour": "displaced armour units, Nod and Ns against the laboratory",
    "dambreak": "surge front of a dam break against Martin and Moyce (1952)",
    "hydrostatic": "pressure profile of a still tank against rho g (H - y)",
    "plot_field": "particles coloured by pressure, velocity or density",
    "plot_series": "time series of columns of energy.csv or bodies.csv",
    "paper_cases": "the seed paper's test cases against their analytic answers",
    "stability": "stability checks of the hard cases",
    "study": "accuracy-cost studies: runs at several resolutions, error against cost",
    "validation_cases": "the validation cases of the studies",
    "wave_cases": "write a wave-flume case file laid out in wavelengths",
}


def _usage() -> str:
    width = max(len(name) for name in TOOLS)
    lines = [f"  {name:{width}s}  {what}" for name, what in TOOLS.items()]
    return ("usage: mbsph-post TOOL [ARGS]   (mbsph-post TOOL --help for a tool's arguments)\n\n"
            "tools:\n" + "\n".join(lines))


def main(argv: Sequence[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    if not args or args[0] in ("-h", "--help"):
        print(_usage())
        return 0 if args else EXIT_INPUT
    tool, rest = args[0].replace("-", "_"), args[1:]
    if tool not in TOOLS:
        print(f"mbsph-post: error: no tool {args[0]!r}\n{_usage()}", file=sys.stderr)
        return EXIT_INPUT
    module = importlib.import_module(f"post.{tool}")
    prog = f"mbsph-post {tool}"
    # the tools parse sys.argv when called without arguments; their help names this command
    sys.argv = [prog] + rest
    return run(module.main, prog)


if __name__ == "__main__":
    raise SystemExit(main())
