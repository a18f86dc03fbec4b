"""benchmarks/RESULTS.md, written by the benchmarks themselves: each run replaces its own section.

A script runs its ``main()`` inside :func:`recorded`, which passes the printed lines through to the terminal and
then writes them into the script's section of RESULTS.md with the date, the machine and the command, so that
every figure there is a run's own output, never copied by hand.
"""

from __future__ import annotations

import contextlib
import datetime
import io
import os
import platform
import re
import shlex
import sys
from collections.abc import Iterator
from pathlib import Path

RESULTS = Path(__file__).with_name("RESULTS.md")
HEADER = """# Benchmark results

Written by the scripts in `benchmarks/` (each run of `python benchmarks/NAME.py` replaces its own section with
its output), not by hand. Runs on a shared virtual machine vary by 10 % or more: compare figures within one run.
"""


class _Tee(io.TextIOBase):
    """Writes to the terminal and keeps a copy."""

    def __init__(self, stream: io.TextIOBase) -> None:
        self.stream, self.copy = stream, io.StringIO()

    def write(self, text: str) -> int:
        self.copy.write(text)
        return self.stream.write(text)

    def flush(self) -> None:
        self.stream.flush()


def machine() -> str:
    """The processor, its cores and the load when the run ended."""
    model = platform.processor() or platform.machine()
    with contextlib.suppress(OSError):
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    load = ", ".join(f"{value:.1f}" for value in os.getloadavg()) if hasattr(os, "getloadavg") else "n/a"
    return f"{model}, {os.cpu_count()} cores, load average {load}; Python {platform.python_version()}"


def write_section(name: str, command: str, output: str) -> None:
    """Replace (or add) the section of ``name`` in RESULTS.md."""
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    section = (f"<!-- {name}: begin -->\n## {name}\n\n- date: {stamp}\n- machine: {machine()}\n- command: `{command}`\n\n"
               f"```\n{output.rstrip()}\n```\n<!-- {name}: end -->\n")
    text = RESULTS.read_text(encoding="utf-8") if RESULTS.exists() else HEADER
    pattern = re.compile(rf"<!-- {re.escape(name)}: begin -->.*?<!-- {re.escape(name)}: end -->\n", re.DOTALL)
    text = pattern.sub(lambda _: section, text) if pattern.search(text) else text.rstrip() + "\n\n" + section
    RESULTS.write_text(text, encoding="utf-8")


@contextlib.contextmanager
def recorded(name: str) -> Iterator[None]:
    """Run the block with its printed output kept, and write it to RESULTS.md if the block ends normally."""
    tee = _Tee(sys.stdout)
    with contextlib.redirect_stdout(tee):
        yield
    command = "python " + " ".join(shlex.quote(arg) for arg in [f"benchmarks/{Path(sys.argv[0]).name}", *sys.argv[1:]])
    write_section(name, command, tee.copy.getvalue())
    print(f"written to {RESULTS}")
