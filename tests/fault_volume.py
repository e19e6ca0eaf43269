"""Run a prp3 command on a real faulty volume, inside a mount namespace of its own.

Not a test module: ``tests/test_fault_injection.py`` starts it as
``unshare --map-root-user --mount python fault_volume.py SPEC.json``, so the
mounts it makes (a small tmpfs, a read-only bind mount) exist only for this
process and vanish with it, on any machine where unprivileged user namespaces
are allowed (as root or not).  The spec (JSON) gives:

* ``volume``: an empty folder that becomes a tmpfs of ``size`` bytes;
* ``argv``: the command's arguments (``prp3.cli.main``), its outputs inside
  ``volume``; run once on the healthy volume (it must succeed);
* then the fault (``"full"``: the volume filled to its last byte by a filler
  file; ``"read-only"``: the volume remounted read-only), and the same
  command again (``again``), and once more into ``fresh_argv`` if given (a
  folder that did not exist).

It prints one JSON object: for each run the exit status and what the command
wrote on stderr, and the volume's files (path → SHA-256, the filler left out)
before and after the faulty runs.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import io
import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

FILLER = ".filler"


def files(volume: Path) -> dict[str, str]:
    """Every file below ``volume`` (but the filler) → its SHA-256; folders end in ``/``."""
    found: dict[str, str] = {}
    for path in sorted(volume.rglob("*")):
        name = str(path.relative_to(volume))
        if name == FILLER:
            continue
        if path.is_dir():
            found[name + "/"] = ""
        else:
            found[name] = hashlib.sha256(path.read_bytes()).hexdigest()
    return found


def run(argv: list[str]) -> dict[str, Any]:
    """``prp3.cli.main(argv)`` in this process: its exit status and its stderr."""
    from prp3.cli import main

    stderr = io.StringIO()
    with contextlib.redirect_stderr(stderr), contextlib.redirect_stdout(io.StringIO()):
        try:
            status = main(argv)
        except SystemExit as stop:  # argparse's own exits
            status = stop.code if isinstance(stop.code, int) else 1
        except BaseException as error:  # reported: the test fails on it
            return {"status": None, "stderr": stderr.getvalue(), "raised": repr(error)}
    return {"status": status, "stderr": stderr.getvalue(), "raised": None}


def fill(volume: Path) -> None:
    """Write zeros into the volume's filler file until the volume is full."""
    block = bytes(65_536)
    with open(volume / FILLER, "wb", buffering=0) as filler:
        size = len(block)
        while size:
            try:
                filler.write(block[:size])
            except OSError as error:
                if error.errno != errno.ENOSPC:
                    raise
                size //= 2


def main() -> int:
    spec = json.loads(Path(sys.argv[1]).read_text())
    volume = Path(spec["volume"])
    subprocess.run(
        ["mount", "-t", "tmpfs", "-o", f"size={int(spec['size'])}", "tmpfs", str(volume)],
        check=True,
    )
    os.chdir(spec.get("cwd", str(volume.parent)))
    report: dict[str, Any] = {"first": run(spec["argv"])}
    report["before"] = files(volume)
    if spec["fault"] == "full":
        fill(volume)
    else:
        subprocess.run(["mount", "--bind", str(volume), str(volume)], check=True)
        subprocess.run(["mount", "-o", "remount,bind,ro", str(volume)], check=True)
    report["again"] = run(spec["argv"])
    report["after_again"] = files(volume)
    if spec.get("fresh_argv"):
        report["fresh"] = run(spec["fresh_argv"])
        report["after_fresh"] = files(volume)
    print(json.dumps(report))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
