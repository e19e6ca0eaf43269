"""A spatial run folder for the 3-D explorer (docs/spatial.md §22): read, checked, served.

:func:`run_kind` tells a spatial robot's run (the columns of docs/spatial.md §9) from a planar
one by the header of ``DIR/results.csv`` (else the names of ``DIR/results.parquet``), so that
``prp3 explore`` names what to give instead of a missing column.  :func:`read_spatial_run`
reads the run of a spatial robot and checks that it is the robot's: the joint values of every
leg must close the legs at one platform pose (the chain of frames of §2, each leg's end frame
placed back by its attachment), to :data:`CLOSURE_TOLERANCE`.  :func:`serve_page` serves one
page (the 3-D explorer's, :mod:`prp3.explorer.spatial_page`) on ``http://host:port/`` with the
standard library's HTTP server, until a signal.  No plotly or Bokeh here.
"""

from __future__ import annotations

import errno
import http.server
import threading
import webbrowser
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from prp3.errors import InputFileError, Prp3Error
from prp3.explorer.run_folder import Run, broken_parquet, read_parquet_columns
from prp3.io.tables import read_table
from prp3.spatial.geometry import chain_frames
from prp3.spatial.model import SpatialRobot
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.outputs import spatial_inverse_dynamics, spatial_results_table
from prp3.validation import first_not_increasing

__all__ = ["CLOSURE_TOLERANCE", "read_spatial_run", "run_kind", "serve_page", "spatial_columns"]

FloatArray = NDArray[np.float64]

#: Largest gap (in units of the robot's scale; radians for the orientation) between the platform
#: poses the legs of one sample place.
CLOSURE_TOLERANCE: float = 1e-9

#: Longest header line read to tell the kind of a run (bytes).
_HEADER_BYTES: int = 1 << 20


def spatial_columns(robot: SpatialRobot) -> tuple[str, ...]:
    """The columns of a ``results.csv`` of ``robot`` (docs/spatial.md §9), in their order."""
    home = PlatformMotion.at_rest(robot.home_position, robot.home_rotation)
    return tuple(spatial_results_table(spatial_inverse_dynamics(robot, home, "newton-euler")))


def _names(folder: Path) -> tuple[Path, list[str]] | None:
    """The results file of ``folder`` and its column names, or ``None`` without one."""
    csv_path, parquet_path = folder / "results.csv", folder / "results.parquet"
    if csv_path.is_file():
        try:
            with csv_path.open("r", encoding="utf-8", errors="replace") as stream:
                line = stream.readline(_HEADER_BYTES)
        except OSError as error:
            raise InputFileError(f"cannot read it ({error.strerror})", file=csv_path) from None
        return csv_path, [cell.strip() for cell in line.split(",")]
    if parquet_path.is_file():
        try:
            import pyarrow.parquet as pq

            return parquet_path, list(pq.read_schema(str(parquet_path)).names)
        except ImportError:  # pragma: no cover - pyarrow is in the test extra
            raise InputFileError(
                "reading Parquet needs pyarrow: pip install 'prp3[parquet]'", file=parquet_path
            ) from None
        except Exception as error:  # pyarrow raises its own types for a broken file
            raise InputFileError(broken_parquet(parquet_path, error), file=parquet_path) from None
    return None


def run_kind(directory: str | Path) -> str | None:
    """``"spatial"`` for a folder of a spatial robot's results (``tau_1`` and ``q_1_…``
    columns), ``"planar"`` for another results file, ``None`` without a results file."""
    found = _names(Path(directory)) if Path(directory).is_dir() else None
    if found is None:
        return None
    names = found[1]
    spatial = "tau_1" in names and any(name.startswith("q_1_") for name in names)
    return "spatial" if spatial else "planar"


def read_spatial_run(directory: str | Path, robot: SpatialRobot) -> Run:
    """Read ``DIR/results.csv`` (else ``DIR/results.parquet``) of a run of ``robot``.

    The columns must be exactly those of ``robot``'s results (docs/spatial.md §9:
    :func:`spatial_columns`), every value finite, ``t`` strictly increasing, and the joint
    values must close every leg at one platform pose per sample (to
    :data:`CLOSURE_TOLERANCE` × ``robot.scale``, and in orientation).

    Raises
    ------
    InputFileError
        No such folder, no results file, a planar run, a column missing or unknown, a cell
        that is not a finite number, a time that does not increase, legs that do not close
        (each naming the file and, where there is one, the line).
    """
    folder = Path(directory)
    if not folder.is_dir():
        raise InputFileError("not a folder of `prp3 simulate` results", file=folder)
    found = _names(folder)
    if found is None:
        raise InputFileError(
            "no results.csv or results.parquet in it (the output of `prp3 simulate --robot "
            "SPATIAL.toml --output DIR`)",
            file=folder,
        )
    path, names = found
    if run_kind(folder) != "spatial":
        raise InputFileError(
            f"not a spatial robot's run (its columns {', '.join(names[:3])[:60]}, … are a planar "
            f"robot's): give the folder of `prp3 simulate --robot SPATIAL.toml`, or leave out "
            f"the spatial --robot",
            file=path,
        )
    columns = spatial_columns(robot)
    unknown = [name for name in names if name not in columns]
    missing = [name for name in columns if name not in names]
    if unknown or missing:
        which = f"it has {unknown[0]!r}" if unknown else f"it has no {missing[0]!r}"
        joints = ", ".join(robot.legs[0].labels)
        raise InputFileError(
            f"not a run of this {robot.name} ({len(robot.legs)} legs of joints {joints}): "
            f"{which[:80]}; give the --robot of the run",
            file=path,
            line=1 if path.suffix == ".csv" else None,
        )
    if path.suffix == ".csv":
        table = read_table(path, columns, (), "results")
        data, lines = table.columns, table.lines
    else:
        data, lines = read_parquet_columns(path, columns), None
    t = data["t"]
    bad = first_not_increasing(t)
    if bad is not None:
        raise InputFileError(
            f"t must be strictly increasing: t = {float(t[bad])!r} follows {float(t[bad - 1])!r}",
            file=path,
            line=int(lines[bad]) if lines is not None else None,
            sample=bad if lines is None else None,
            key="t",
        )
    _check_closure(robot, data, path, lines)
    return Run(path=path, table=data)


def _check_closure(
    robot: SpatialRobot,
    table: dict[str, FloatArray],
    path: Path,
    lines: NDArray[np.int64] | None,
) -> None:
    """Refuse joint values whose legs place the platform at different poses (another robot's
    run): each leg's end frame ``F_n = (p + R·c_A, R·R_A)`` gives ``R = R_n·R_Aᵀ`` and
    ``p = c_n − R·c_A``, held against leg 1's."""
    leg = robot.legs[0]
    legs = len(robot.legs)
    q = np.stack(
        [
            np.stack([table[f"q_{i + 1}_{c}"] for c in leg.coordinates], axis=-1)
            for i in range(legs)
        ],
        axis=1,
    )  # (N, legs, dof)
    frames = chain_frames(robot, q)
    positions, turns = [], []
    for i, each in enumerate(robot.legs):
        end, rotation = frames.origin[:, i, -1], frames.rotation[:, i, -1]
        turn = rotation @ np.asarray(each.attachment_rotation).T
        positions.append(end - np.einsum("nij,j->ni", turn, np.asarray(each.attachment_position)))
        turns.append(turn)
    position, turn = np.stack(positions, axis=1), np.stack(turns, axis=1)  # (N, legs, ...)
    with np.errstate(all="ignore"):  # joint values of 1e308: a gap that is not finite, refused
        gap = np.maximum(
            np.abs(position - position[:, :1]).max(axis=-1) / robot.scale,
            np.abs(turn - turn[:, :1]).max(axis=(-2, -1)),
        )  # (N, legs)
    if not (gap <= CLOSURE_TOLERANCE).all():
        k, i = (int(v) for v in np.argwhere(~(gap <= CLOSURE_TOLERANCE))[0])
        raise InputFileError(
            f"the joint values of legs 1 and {i + 1} place the platform {float(gap[k, i]):.3g} "
            f"(of the scale {robot.scale:g} m, or of the rotation matrix) apart: not a run of "
            f"this {robot.name}; give the --robot of the run",
            file=path,
            line=int(lines[k]) if lines is not None else None,
            sample=k if lines is None else None,
            time=float(table["t"][k]),
        )


def _listen_error(host: str, port: int, error: OSError) -> Prp3Error:
    if error.errno == errno.EADDRINUSE:
        return Prp3Error(
            f"port {port} on {host} is busy (another program listens there): "
            "choose another with --port",
            origin=f"--port {port}",
        )
    return Prp3Error(
        f"cannot listen on {host}:{port}: {error.strerror or error}", origin=f"--host {host}"
    )


def serve_page(
    page: str,
    *,
    host: str = "127.0.0.1",
    port: int = 8765,
    open_browser: bool = True,
    announce: Callable[[str], None] = print,
) -> None:
    """Serve ``page`` (one HTML page) at ``http://host:port/`` until interrupted.

    Every other path is 404.  The command line's signal handlers stop it (SIGINT, SIGTERM).

    Raises
    ------
    Prp3Error
        The port is busy, or the address cannot be listened on (one line naming it).
    """
    body = page.encode("utf-8")

    class Handler(http.server.BaseHTTPRequestHandler):
        def do_GET(self) -> None:
            if self.path.split("?", 1)[0] not in ("/", "/index.html"):
                self.send_error(404)
                return
            self.send_response(200)
            self.send_header("Content-Type", "text/html; charset=utf-8")
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, format: str, *args: Any) -> None:
            return None  # quiet: the command prints one line

    class Server(http.server.ThreadingHTTPServer):
        def handle_error(self, request: Any, client_address: Any) -> None:
            return None  # a browser that closed the connection early: nothing to say

    try:
        server = Server((host, port), Handler)
    except OSError as error:
        raise _listen_error(host, port, error) from None
    except (OverflowError, ValueError) as error:  # pragma: no cover - the parser bounds --port
        raise Prp3Error(
            f"cannot listen on {host}:{port}: {error}", origin=f"--port {port}"
        ) from None
    url = f"http://{host}:{port}/"
    with server:
        announce(url)
        if open_browser:
            threading.Thread(target=webbrowser.open, args=(url,), daemon=True).start()
        server.serve_forever()
