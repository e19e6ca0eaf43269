#!/usr/bin/env python
"""Where the time of the batch path goes: the traced tape of ``actuator_forces``.

Run from the repository root::

    python benchmarks/profile_tape.py                 # N = 10⁵, chunks of 8192
    python benchmarks/profile_tape.py --chunk 4096 --rounds 20

Times, interleaved in one process on the same samples of the rotation motion
(median and best of ``--rounds`` × 3 calls, samples per second):

* ``actuator_forces`` — the whole validated call;
* ``tape`` — the traced ufunc calls alone, chunk after chunk on the same
  inputs copied into contiguous rows as :mod:`prp3.fast` does (no validation,
  no checks of the results);
* ``tape, cos/sin replaced`` — the same with ``cos`` and ``sin`` replaced by
  ``negative`` (wrong numbers, right memory traffic): the share of the two
  transcendental calls;

then the tape's operations counted by kind, and the median time of each kind
on one chunk in isolation (every operation repeated on warm rows): what one
ufunc call costs at this chunk size, on work rows, the inputs' contiguous
rows (``input``) and the output's columns of an ``(N, 3)`` array (``output
column``, strided).
"""

from __future__ import annotations

import argparse
import collections
import re
import statistics
import timeit
from collections.abc import Callable
from typing import Any

import numpy as np

import prp3
from prp3.fast import actuator_forces, compile_robot
from prp3.kernel import STATE_SYMBOLS


def motion(samples: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    m = prp3.paper_motion("rotation", samples=samples)
    return m.pose, m.velocity, m.acceleration


def chunks(
    function: Callable[..., None], arrays: tuple[np.ndarray, ...], chunk: int
) -> Callable[[], None]:
    samples = arrays[0].shape[0]
    out, checks, state = np.empty((samples, 3)), np.empty(chunk), np.empty((9, chunk))

    def run() -> None:
        with np.errstate(all="ignore"):
            for start in range(0, samples, chunk):
                stop = min(start + chunk, samples)
                rows = state[:, : stop - start]  # as prp3.fast: contiguous copies of the inputs
                for k, array in enumerate(arrays):
                    np.copyto(rows[3 * k : 3 * k + 3], array[start:stop].T)
                targets = [checks[: stop - start], *(out[start:stop, leg] for leg in range(3))]
                function(*rows, targets)

    return run


def rates(calls: dict[str, Callable[[], object]], samples: int, rounds: int) -> None:
    times: dict[str, list[float]] = {name: [] for name in calls}
    for _ in range(rounds):  # interleaved: a change of the machine's speed hits every row
        for name, call in calls.items():
            times[name].extend(timeit.repeat(call, number=1, repeat=3))
    for name, values in times.items():
        print(
            f"  {name:<28} median {samples / statistics.median(values):9.3g}/s"
            f"   best {samples / min(values):9.3g}/s"
        )


def operation_costs(
    function: Callable[..., None], arrays: tuple[np.ndarray, ...], chunk: int
) -> None:
    source = function.__doc__ or ""
    lines = source.splitlines()
    start = next(k for k, line in enumerate(lines) if line.startswith("def "))
    namespace: dict[str, Any] = dict(function.__globals__)  # type: ignore[attr-defined]
    exec("\n".join([*lines, "    return locals()"]), namespace)
    rows = list(np.ascontiguousarray(np.concatenate([a[:chunk].T for a in arrays])))
    out, checks = np.empty((chunk, 3)), np.empty(chunk)
    with np.errstate(all="ignore"):
        env = namespace["batch_kernel"](*rows, [checks, *(out[:, leg] for leg in range(3))])
        env.update(function.__globals__)  # type: ignore[attr-defined]
        kinds: dict[str, list[float]] = collections.defaultdict(list)
        for statement in (line.strip() for line in lines[start + 3 :]):
            if not statement:
                continue
            name = statement.split("(")[0]
            operands = statement[statement.index("(") + 1 : -1].split(", ")
            strided = any(o.startswith("o") and o != "o0" for o in operands)
            state = any(o in STATE_SYMBOLS for o in operands)
            constant = any(o.startswith("k") for o in operands)
            kind = (
                name
                + (", input" if state else "")
                + (", output column" if strided else "")
                + (", constant" if constant else "")
            )
            seconds = min(timeit.repeat(statement, globals=env, number=20, repeat=5)) / 20
            kinds[kind].append(seconds)
    total = sum(sum(v) for v in kinds.values())
    print(f"  {sum(len(v) for v in kinds.values())} ufunc calls per chunk of {chunk}; in isolation "
          f"{total * 1e6:.0f} µs per chunk = {total / chunk * 1e9:.1f} ns per sample")  # fmt: skip
    for kind, values in sorted(kinds.items(), key=lambda item: -sum(item[1])):
        print(
            f"    {kind:<28} ×{len(values):3d}  {statistics.median(values) * 1e6:6.2f} µs each"
            f"  ({100 * sum(values) / total:4.1f} %)"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=10**5)
    parser.add_argument("--chunk", type=int, default=8192)
    parser.add_argument("--rounds", type=int, default=12)
    args = parser.parse_args()
    compiled = compile_robot(prp3.Robot())
    arrays = motion(args.samples)
    tape = compiled.batch_function(("f10",))
    source = tape.__doc__ or ""
    namespace: dict[str, Any] = dict(tape.__globals__)  # type: ignore[attr-defined]
    exec(re.sub(r"^    (cos|sin)\(", "    negative(", source, flags=re.MULTILINE), namespace)
    no_trig = namespace["batch_kernel"]
    for _ in range(3):
        actuator_forces(compiled, *arrays, chunk_size=args.chunk)
    print(f"N = {args.samples}, chunks of {args.chunk} samples, the rotation motion:")
    rates(
        {
            "actuator_forces": lambda: actuator_forces(compiled, *arrays, chunk_size=args.chunk),
            "tape": chunks(tape, arrays, args.chunk),
            "tape, cos/sin replaced": chunks(no_trig, arrays, args.chunk),
        },
        args.samples,
        args.rounds,
    )
    operation_costs(tape, arrays, args.chunk)
    phi = arrays[0][: args.chunk, 2]
    for label, call in (
        ("cos and sin", lambda: (np.cos(phi), np.sin(phi))),
        ("tan", lambda: np.tan(phi)),
    ):
        seconds = min(timeit.repeat(call, number=20, repeat=5)) / 20
        print(f"  {label} of one chunk's phi: {seconds / args.chunk * 1e9:.1f} ns per sample")


if __name__ == "__main__":
    main()
